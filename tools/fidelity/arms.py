"""One robot in pybullet and the same robot in rdsim, behind one small interface.

Both arms speak rdsim's joint order (the URDF's movable joints in rdsim's tree order, by name), so
joint vectors compare element by element. The methods are the few the comparisons need: reset,
position targets with gains, physics steps, joint angles, link origins, and the IK each simulator
offers (pybullet's calculateInverseKinematics with rest poses; rdsim's null_space_ik).
"""
from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from .robots import RobotCase

TIME_STEP = 1.0 / 240.0  # s: pybullet's default step, also rdsim's
GRAVITY = (0.0, 0.0, -9.8)
# pybullet's physics server stops the solver's iterations once the squared residual falls below this.
PYBULLET_RESIDUAL_THRESHOLD = 1e-7


class PyBulletArm:
    """The robot in its own pybullet DIRECT client.

    ``inertia_from_file``: pybullet's URDF import ignores the URDF's inertia tensors unless asked
    (URDF_USE_INERTIA_FROM_FILE) and derives them from the collision shapes instead; the original
    platform loaded with the default. rdsim always uses the URDF's tensors.
    """

    def __init__(self, case: RobotCase, *, solver_iterations: int = 150, inertia_from_file: bool = True,
                 position_gain: float = 0.1, velocity_gain: float = 1.0,
                 solver_residual_threshold: float = PYBULLET_RESIDUAL_THRESHOLD) -> None:
        import pybullet as p

        self.p = p
        self.case = case
        self.client = p.connect(p.DIRECT)
        p.setGravity(*GRAVITY, physicsClientId=self.client)
        p.setTimeStep(TIME_STEP, physicsClientId=self.client)
        p.setPhysicsEngineParameter(numSolverIterations=solver_iterations,
                                    solverResidualThreshold=solver_residual_threshold, physicsClientId=self.client)
        flags = p.URDF_USE_INERTIA_FROM_FILE if inertia_from_file else 0
        self.body = p.loadURDF(str(case.urdf()), case.base_position, useFixedBase=True, flags=flags,
                               physicsClientId=self.client)
        self.kp, self.kd = position_gain, velocity_gain
        self._links = {p.getBodyInfo(self.body, physicsClientId=self.client)[0].decode(): -1}
        movable: dict[str, int] = {}
        self._limits: dict[str, tuple[float, float, float]] = {}
        for j in range(p.getNumJoints(self.body, physicsClientId=self.client)):
            info = p.getJointInfo(self.body, j, physicsClientId=self.client)
            self._links[info[12].decode()] = j
            if info[2] != p.JOINT_FIXED:
                movable[info[1].decode()] = j
                self._limits[info[1].decode()] = (info[8], info[9], info[10])
        self._movable = movable
        self.pb_joint_names = list(movable)  # pybullet's dof order (calculateInverseKinematics')
        self.joint_names = self.pb_joint_names
        self._index = [movable[n] for n in self.joint_names]

    def use_order(self, names: Sequence[str]) -> None:
        """Speak another joint order (rdsim's): the same names, permuted."""
        if sorted(names) != sorted(self.pb_joint_names):
            raise ValueError(f"{self.case.name}: the simulators disagree on the movable joints")
        self.joint_names = list(names)
        self._index = [self._movable[n] for n in names]

    @property
    def dof(self) -> int:
        return len(self.joint_names)

    @property
    def lower(self) -> np.ndarray:
        return np.array([self._limits[n][0] for n in self.joint_names])

    @property
    def upper(self) -> np.ndarray:
        return np.array([self._limits[n][1] for n in self.joint_names])

    @property
    def effort(self) -> np.ndarray:
        return np.array([self._limits[n][2] for n in self.joint_names])

    def reset_joints(self, q: Sequence[float]) -> None:
        for j, v in zip(self._index, q):
            self.p.resetJointState(self.body, j, float(v), 0.0, physicsClientId=self.client)
        self.set_position_targets(q)

    def set_position_targets(self, q: Sequence[float]) -> None:
        # The original's call: position control with the preset gains and the URDF efforts as forces.
        n = self.dof
        self.p.setJointMotorControlArray(self.body, self._index, self.p.POSITION_CONTROL,
                                         targetPositions=[float(v) for v in q], forces=list(self.effort),
                                         positionGains=[self.kp] * n, velocityGains=[self.kd] * n,
                                         physicsClientId=self.client)

    def step(self, steps: int = 1) -> None:
        for _ in range(steps):
            self.p.stepSimulation(physicsClientId=self.client)

    def joint_positions(self) -> np.ndarray:
        states = self.p.getJointStates(self.body, self._index, physicsClientId=self.client)
        return np.array([s[0] for s in states])

    def link_position(self, link: str) -> np.ndarray:
        j = self._links[link]
        if j < 0:
            return np.array(self.p.getBasePositionAndOrientation(self.body, physicsClientId=self.client)[0])
        return np.array(self.p.getLinkState(self.body, j, computeForwardKinematics=True,
                                            physicsClientId=self.client)[4])

    def link_inertia(self, link: str) -> tuple[float, np.ndarray]:
        """(mass kg, principal moments kg m^2) as pybullet simulates the link (getDynamicsInfo)."""
        info = self.p.getDynamicsInfo(self.body, self._links[link], physicsClientId=self.client)
        return info[0], np.array(info[2])

    def ik(self, link: str, target: Sequence[float], rest: Sequence[float],
           start: Optional[Sequence[float]] = None) -> np.ndarray:
        """pybullet's calculateInverseKinematics as the original called it: rest poses with the URDF's
        limits and ranges, defaults otherwise (20 iterations, residual 1e-4), from the current joint
        angles (or from `start`, set for the call and put back)."""
        saved = None
        if start is not None:
            saved = self.p.saveState(physicsClientId=self.client)
            for j, v in zip(self._index, start):
                self.p.resetJointState(self.body, j, float(v), 0.0, physicsClientId=self.client)
        order = [self.joint_names.index(n) for n in self.pb_joint_names]  # ours -> pybullet's
        lower, upper = self.lower[order], self.upper[order]
        rest_pb = [float(np.asarray(rest)[i]) for i in order]
        q_pb = self.p.calculateInverseKinematics(self.body, self._links[link], [float(v) for v in target],
                                                 lowerLimits=list(lower), upperLimits=list(upper),
                                                 jointRanges=list(upper - lower), restPoses=rest_pb,
                                                 physicsClientId=self.client)
        if saved is not None:
            self.p.restoreState(saved, physicsClientId=self.client)
            self.p.removeState(saved, physicsClientId=self.client)
        q = np.empty(self.dof)
        for k, i in enumerate(order):
            q[i] = q_pb[k]
        return q

    def save(self) -> int:
        return self.p.saveState(physicsClientId=self.client)

    def restore(self, state: int) -> None:
        self.p.restoreState(state, physicsClientId=self.client)

    def discard(self, state: int) -> None:
        self.p.removeState(state, physicsClientId=self.client)

    def close(self) -> None:
        self.p.disconnect(self.client)


class RdsimArm:
    """The robot in an rdsim.sim.World, driven by position motors as the env option drive
    position_motor sets them up (no speed limit, pybullet's link damping 0.04 and solver settings,
    inertia from the collision shapes as pybullet's loadURDF computes it by default, the URDF's joint
    damping applied as pybullet applies it; ``speed_limits=True, link_damping=0, pybullet_solver=False,
    inertia_from_shapes=False, joint_damping=False`` give rdsim's plain defaults)."""

    def __init__(self, case: RobotCase, *, solver_iterations: int = 150, position_gain: float = 0.1,
                 velocity_gain: float = 1.0, speed_limits: bool = False, link_damping: float = 0.04,
                 pybullet_solver: bool = True, inertia_from_shapes: bool = True, joint_damping: bool = True,
                 solver_residual_threshold: Optional[float] = None) -> None:
        import rdsim.sim

        self.case = case
        self.world = rdsim.sim.World(time_step=TIME_STEP, solver_iterations=solver_iterations, gravity=GRAVITY,
                                     pybullet_solver=pybullet_solver, solver_residual_threshold=solver_residual_threshold)
        self.robot = self.world.add_robot(str(case.urdf()), case.base_position, drive="position_motor",
                                          position_gain=position_gain, velocity_gain=velocity_gain,
                                          speed_limits=speed_limits, link_damping=link_damping,
                                          inertia_from_shapes=inertia_from_shapes, joint_damping=joint_damping)
        self.joint_names = list(self.robot.joint_names)
        self.lower, self.upper = np.asarray(self.robot.lower), np.asarray(self.robot.upper)
        self.free_bodies: list[int] = []  # World.add_free_body ids that save()/restore() carry

    @property
    def dof(self) -> int:
        return self.robot.dof

    def reset_joints(self, q: Sequence[float]) -> None:
        self.robot.reset_joints(np.asarray(q, dtype=float))

    def set_position_targets(self, q: Sequence[float]) -> None:
        self.robot.set_position_targets(np.asarray(q, dtype=float))

    def step(self, steps: int = 1) -> None:
        self.world.step(steps)

    def joint_positions(self) -> np.ndarray:
        return np.asarray(self.robot.joint_positions())

    def link_position(self, link: str) -> np.ndarray:
        return np.asarray(self.robot.link_position(link))

    def link_inertia(self, link: str) -> tuple[float, np.ndarray]:
        mass, moments = self.robot.link_inertia(link)
        return mass, np.asarray(moments)

    def ik(self, link: str, target: Sequence[float], rest: Sequence[float],
           start: Optional[Sequence[float]] = None) -> np.ndarray:
        return np.asarray(self.robot.null_space_ik(link, np.asarray(target, dtype=float),
                                                   None if start is None else np.asarray(start, dtype=float),
                                                   np.asarray(rest, dtype=float)))

    def save(self) -> tuple:
        return self.robot.state(), [self.world.body_pose(b) for b in self.free_bodies]

    def restore(self, state: tuple) -> None:
        # Free bodies come back at rest (Bullet rigid-body velocities are not saved): the searches keep
        # only states where they have not moved.
        self.robot.set_state(state[0])
        for b, (position, orientation) in zip(self.free_bodies, state[1]):
            self.world.set_body_pose(b, position, orientation)

    def discard(self, state: tuple) -> None:
        pass

    def close(self) -> None:
        pass


def make_pair(case: RobotCase, *, inertia: str = "shapes", **options) -> tuple[PyBulletArm, RdsimArm]:
    """The robot in both simulators, pybullet's arm speaking rdsim's joint order. ``inertia``: "shapes"
    (both derive the inertia tensors from the collision shapes: pybullet's loadURDF default, which the
    original used, and the paper presets') or "urdf" (both use the URDF's tensors)."""
    if inertia not in ("shapes", "urdf"):
        raise ValueError(f'inertia: expected "shapes" or "urdf", got {inertia!r}')
    rdsim_only = {k: options.pop(k) for k in ("speed_limits", "link_damping", "pybullet_solver", "joint_damping")
                  if k in options}
    rd = RdsimArm(case, inertia_from_shapes=inertia == "shapes", **options, **rdsim_only)
    pb = PyBulletArm(case, inertia_from_file=inertia == "urdf", **options)
    pb.use_order(rd.joint_names)
    return pb, rd
