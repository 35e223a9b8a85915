"""The robots the fidelity harness compares, and how the original platform drove each.

rdsim's own Jaka and InMoov come from assets/; the KUKA iiwa and the Franka Panda come from the
installed pybullet package's pybullet_data (found at run time, never copied into the repository).
Poses are keyed by joint name, so they do not depend on either simulator's joint order.
"""
from __future__ import annotations

import math
import pathlib
from dataclasses import dataclass, field
from typing import Callable, Mapping, Optional

ROOT = pathlib.Path(__file__).resolve().parents[2]


def pybullet_data_path() -> Optional[pathlib.Path]:
    """pybullet_data's folder, or None when pybullet is not installed."""
    try:
        import pybullet_data
    except ImportError:
        return None
    return pathlib.Path(pybullet_data.getDataPath())


@dataclass(frozen=True)
class RobotCase:
    name: str
    urdf: Callable[[], pathlib.Path]  # where the URDF is (a function: pybullet_data is found late)
    effector: str                     # link whose origin the IK places and the tasks measure
    reset: Mapping[str, float] = field(default_factory=dict)  # joint -> rad at reset (others 0)
    rest: Mapping[str, float] = field(default_factory=dict)   # the IK's rest pose (others 0)
    base_position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    action_step: float = 1.0   # m: how far the IK goal of one discrete move lies (the original's recipe)
    has_meshes: bool = False   # mesh collision geometry: rdsim loads it only with mesh support

    def pose(self, names: list[str], which: str) -> list[float]:
        values = self.reset if which == "reset" else self.rest
        unknown = sorted(set(values) - set(names))
        if unknown:  # a misspelt joint would silently start the robot elsewhere
            raise ValueError(f"{self.name}: {which} pose names joints the robot does not have: {unknown}")
        return [float(values.get(n, 0.0)) for n in names]


_JAKA_POSE = {"joint_1": 0.0, "joint_2": 0.0, "joint_3": 1.0, "joint_4": 1.0, "joint_5": 1.0, "joint_6": 1.0}
# pybullet's own KUKA example's rest pose; the Panda's is the pose pybullet's Panda demo starts from.
_KUKA_REST = {"lbr_iiwa_joint_1": 0.0, "lbr_iiwa_joint_2": 0.0, "lbr_iiwa_joint_3": 0.0,
              "lbr_iiwa_joint_4": 0.5 * math.pi, "lbr_iiwa_joint_5": 0.0, "lbr_iiwa_joint_6": -0.5 * math.pi * 0.66,
              "lbr_iiwa_joint_7": 0.0}
_PANDA_REST = {"panda_joint1": 0.98, "panda_joint2": 0.458, "panda_joint3": 0.31, "panda_joint4": -2.24,
               "panda_joint5": -0.30, "panda_joint6": 2.66, "panda_joint7": 2.32}


def _data(rel: str) -> Callable[[], pathlib.Path]:
    def find() -> pathlib.Path:
        base = pybullet_data_path()
        if base is None:
            raise RuntimeError("pybullet is not installed (pip install pybullet==3.2.7)")
        return base / rel
    return find


CASES: dict[str, RobotCase] = {
    # RobotDrlSim's Jaka button recipe: reset and rest pose [0, 0, 1, 1, 1, 1], IK goals 1 m away.
    "jaka": RobotCase("jaka", lambda: ROOT / "assets/jaka/jaka_zu7.urdf", "flange_link", _JAKA_POSE, _JAKA_POSE),
    # RobotDrlSim's InMoov tomato recipe: every joint 0 at reset and as the rest pose, goals 1.2 m away.
    "inmoov": RobotCase("inmoov", lambda: ROOT / "assets/inmoov/inmoov.urdf", "r_hand_ee", action_step=1.2),
    "kuka": RobotCase("kuka", _data("kuka_iiwa/model.urdf"), "lbr_iiwa_link_7", _KUKA_REST, _KUKA_REST,
                      has_meshes=True),
    "panda": RobotCase("panda", _data("franka_panda/panda.urdf"), "panda_hand", _PANDA_REST, _PANDA_REST,
                       has_meshes=True),
}
