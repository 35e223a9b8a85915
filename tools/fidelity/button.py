"""The paper's Jaka button task under the original's recipe, in pybullet and in rdsim, side by side.

The original (RobotDrlSim on pybullet): a floor plane at z = 0, a free button of about 5 kg (20 cm
wide, 3.7 cm tall) standing on it, the target point (0.5, 0, 0) under the button (random buttons:
x += 0.15 U(-1, 1), y += 0.3 U(-1, 1)). Here pybullet runs that scene with rdsim's Jaka URDF; rdsim
runs the same scene at its sim level (rdsim.sim: a floor, the free 5 kg paper button) with its paper
preset's recipe. :func:`button_search` reports the closest approach of a greedy and a
beam search over the six moves with the button undisturbed (moved less than 5 mm).
"""
from __future__ import annotations

from typing import Callable, Iterator

import numpy as np

from .arms import PYBULLET_RESIDUAL_THRESHOLD, PyBulletArm, RdsimArm
from .compare import recipe_search
from .robots import CASES, ROOT

PAPER_TARGET = (0.5, 0.0, 0.0)
BUTTON_MASS = 5.0                      # kg, the original's
BUTTON_HALF = (0.1, 0.1, 0.0185)       # m: 20 cm wide, 3.7 cm tall
DISTURBED = 0.005                      # m the button may move before the search drops the state


def random_button(seed: int) -> tuple[float, float, float]:
    """A random button as the original drew it (x += 0.15 U(-1, 1), y += 0.3 U(-1, 1)); numpy's
    generator, so both simulators get the same buttons."""
    u = np.random.default_rng(seed).uniform(-1.0, 1.0, 2)
    return (PAPER_TARGET[0] + 0.15 * u[0], PAPER_TARGET[1] + 0.3 * u[1], 0.0)


def pybullet_scene(arm: PyBulletArm, target) -> Callable[[], bool]:
    """Floor plane and the original's free 5 kg button at `target`; returns "has the button moved"."""
    p, c = arm.p, arm.client
    p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=c), physicsClientId=c)
    box = p.createCollisionShape(p.GEOM_BOX, halfExtents=BUTTON_HALF, physicsClientId=c)
    start = np.array([target[0], target[1], BUTTON_HALF[2]])
    button = p.createMultiBody(BUTTON_MASS, box, basePosition=start.tolist(), physicsClientId=c)

    def moved() -> bool:
        pos = np.array(p.getBasePositionAndOrientation(button, physicsClientId=c)[0])
        return bool(np.linalg.norm(pos - start) > DISTURBED)
    return moved


def rdsim_scene(arm: RdsimArm, target, *, free: bool = True) -> Callable[[], bool]:
    """The same scene in rdsim: the floor (assets/objects/floor.urdf, top at z = 0) and the paper's
    button (assets/objects/paper_button.urdf, 5 kg) at `target`, free (the sim level's
    World.add_free_body) or static (rdsim's env today); returns "has the button moved"."""
    arm.world.add_static_body(str(ROOT / "assets/objects/floor.urdf"))
    urdf = str(ROOT / "assets/objects/paper_button.urdf")
    position = (target[0], target[1], 0.0)
    if not free:
        arm.world.add_static_body(urdf, position)
        return lambda: False
    button = arm.world.add_free_body(urdf, position)
    arm.free_bodies.append(button)
    start = np.array(position)

    def moved() -> bool:
        return bool(np.linalg.norm(np.asarray(arm.world.body_pose(button)[0]) - start) > DISTURBED)
    return moved


def search_pair(target, *, steps: int = 1000, beam: int = 16, hold: int = 4,
                solver_residual_threshold: float = PYBULLET_RESIDUAL_THRESHOLD) -> dict:
    """Greedy and beam closest approaches to `target` in both simulators (metres)."""
    case = CASES["jaka"]
    # as the original loaded it
    pb = PyBulletArm(case, inertia_from_file=False, solver_residual_threshold=solver_residual_threshold)
    pb_moved = pybullet_scene(pb, target)
    rd = RdsimArm(case, solver_residual_threshold=solver_residual_threshold)
    rd_moved = rdsim_scene(rd, target)
    out = {"pybullet": recipe_search(pb, case, target, steps=steps, beam=beam, hold=hold, disturbed=pb_moved),
           "rdsim": recipe_search(rd, case, target, steps=steps, beam=beam, hold=hold, disturbed=rd_moved)}
    pb.close()
    return out


def button_search(*, steps: int = 1000, seeds=range(100, 108), fixed: bool = True,
                  solver_residual_threshold: float = PYBULLET_RESIDUAL_THRESHOLD) -> Iterator[str]:
    """Report rows: the fixed button, then random buttons by seed."""
    targets = [("fixed (0.5, 0, 0)", PAPER_TARGET)] if fixed else []
    targets += [(f"random, seed {s}", random_button(s)) for s in seeds]
    for label, target in targets:
        r = search_pair(target, steps=steps, solver_residual_threshold=solver_residual_threshold)
        yield (f"| {label} | ({target[0]:.3f}, {target[1]:.3f}) | pybullet greedy {100 * r['pybullet']['greedy']:.1f} cm, "
               f"beam {100 * r['pybullet']['beam']:.1f} cm | "
               f"rdsim greedy {100 * r['rdsim']['greedy']:.1f} cm, beam {100 * r['rdsim']['beam']:.1f} cm |")
