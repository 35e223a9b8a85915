"""The manipulation tasks' grasp in pybullet and in rdsim, on the same scene (docs/fidelity.md).

Both simulators get rdsim's JAKA Zu 7 with its parallel gripper (assets/jaka/jaka_zu7_gripper.urdf),
the table and a 4 cm cube (assets/objects/), the manipulation tasks' physics (4 ms steps, 10 solver
iterations, pads and cube at friction 1.0 with friction anchors, the fingers coupled to move as one
and squeezing with their 60 N effort) and the same joint targets: above the cube with the fingers
open, down to it, close, lift 12.5 cm. The targets come from pybullet's IK once per seed (the gripper
pointing down, fingers across y), so what differs is only the simulation. rdsim runs its env's
drive: the arm by computed torques (position gain 0.3 per physics step), the fingers by joint motors;
pybullet runs POSITION_CONTROL motors with the same gain and the URDF's efforts.

:func:`grasp_and_lift` returns each simulator's cube position after the lift; :func:`compare` runs
seeds and reports who lifted the cube and how far apart the two cubes ended.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .robots import ROOT

ARM = ROOT / "assets" / "jaka" / "jaka_zu7_gripper.urdf"
TABLE = ROOT / "assets" / "objects" / "table.urdf"
CUBE = ROOT / "assets" / "objects" / "cube_blue.urdf"
TABLE_AT = (0.35, 0.0, 0.0)
TIME_STEP = 0.004        # s, the tasks' physics step
SOLVER_ITERATIONS = 10
FRICTION = 1.0           # pads and cube
POSITION_GAIN = 0.3      # the tasks' drive: share of the error closed per physics step
HOME = [-0.2561, 1.4791, -1.7509, 1.8426, 1.5708, 1.3147]  # the tasks' home (effector 15 cm over the area)
DOWN = (1.0, 0.0, 0.0, 0.0)  # gripper pointing down, fingers closing along the world's y (x, y, z, w)
ARM_JOINTS = [f"joint_{i}" for i in range(1, 7)]
FINGERS = ["finger_left_joint", "finger_right_joint"]
OPEN, CLOSED = 0.0425, 0.0
GRASP_Z, ABOVE_Z, LIFT_Z = 0.025, 0.10, 0.15   # m: the effector (tool centre point) heights
LIFTED = 0.10            # m: a cube centre above this at the end was lifted
# Steps of each phase: settle above, descend, settle, close, lift, hold.
PHASES = (("settle", 25), ("descend", 100), ("settle", 25), ("close", 100), ("lift", 150), ("hold", 50))


@dataclass
class Targets:
    above: np.ndarray  # arm joints
    grasp: np.ndarray
    lift: np.ndarray


def cube_start(seed: int) -> tuple[float, float, float]:
    rng = np.random.default_rng(seed)
    x, y = 0.45 + rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15)
    return (float(x), float(y), 0.02)


def schedule(t: Targets):
    """(arm targets, finger targets) for every physics step, phase by phase."""
    arm, fingers = t.above, OPEN
    for name, steps in PHASES:
        start = arm
        goal = {"descend": t.grasp, "lift": t.lift}.get(name, arm)
        if name == "close":
            fingers = CLOSED
        for k in range(steps):
            arm = start + (goal - start) * min(1.0, (k + 1) / steps)
            yield arm, fingers


class PyBulletScene:
    def __init__(self, cube_at):
        import pybullet as p

        self.p = p
        self.c = p.connect(p.DIRECT)
        p.setGravity(0, 0, -9.8, physicsClientId=self.c)
        p.setPhysicsEngineParameter(fixedTimeStep=TIME_STEP, numSolverIterations=SOLVER_ITERATIONS, physicsClientId=self.c)
        p.loadURDF(str(TABLE), TABLE_AT, useFixedBase=True, physicsClientId=self.c)
        self.robot = p.loadURDF(str(ARM), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=self.c)
        self.cube = p.loadURDF(str(CUBE), cube_at, flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=self.c)
        names = {p.getJointInfo(self.robot, j, physicsClientId=self.c)[1].decode(): j
                 for j in range(p.getNumJoints(self.robot, physicsClientId=self.c))}
        self.arm = [names[n] for n in ARM_JOINTS]
        self.fingers = [names[n] for n in FINGERS]
        self.tcp = names["gripper_tcp_joint"]
        self.effort = [p.getJointInfo(self.robot, j, physicsClientId=self.c)[10] for j in self.arm + self.fingers]
        for link in range(-1, p.getNumJoints(self.robot, physicsClientId=self.c)):  # rdsim: no link damping
            p.changeDynamics(self.robot, link, linearDamping=0, angularDamping=0, physicsClientId=self.c)
        for body, link in [(self.cube, -1)] + [(self.robot, f) for f in self.fingers]:
            p.changeDynamics(body, link, lateralFriction=FRICTION, frictionAnchor=1, physicsClientId=self.c)
        gear = p.createConstraint(self.robot, self.fingers[0], self.robot, self.fingers[1], p.JOINT_GEAR, [0, 1, 0],
                                  [0, 0, 0], [0, 0, 0], physicsClientId=self.c)
        p.changeConstraint(gear, gearRatio=-1, erp=0.2, maxForce=2 * max(self.effort[-2:]), physicsClientId=self.c)

    def ik(self, position, start):
        p = self.p
        for j, q in zip(self.arm, start):
            p.resetJointState(self.robot, j, q, physicsClientId=self.c)
        q = p.calculateInverseKinematics(self.robot, self.tcp, position, DOWN, maxNumIterations=200,
                                         residualThreshold=1e-6, physicsClientId=self.c)
        return np.array(q[:6])

    def reset(self, arm, fingers):
        for j, q in zip(self.arm + self.fingers, list(arm) + [fingers, fingers]):
            self.p.resetJointState(self.robot, j, q, physicsClientId=self.c)

    def control(self, arm, fingers):
        q = list(arm) + [fingers, fingers]
        self.p.setJointMotorControlArray(self.robot, self.arm + self.fingers, self.p.POSITION_CONTROL, targetPositions=q,
                                         positionGains=[POSITION_GAIN] * 8, forces=self.effort, physicsClientId=self.c)
        self.p.stepSimulation(physicsClientId=self.c)

    def cube_position(self):
        return np.array(self.p.getBasePositionAndOrientation(self.cube, physicsClientId=self.c)[0])

    def close(self):
        self.p.disconnect(self.c)


class RdsimScene:
    def __init__(self, cube_at):
        from rdsim import sim

        self.world = sim.World(time_step=TIME_STEP, solver_iterations=SOLVER_ITERATIONS)
        self.world.add_static_body(str(TABLE), TABLE_AT)
        self.robot = self.world.add_robot(str(ARM), drive="computed_torque", position_gain=POSITION_GAIN,
                                          limit_constraints=False, motor_joints=FINGERS, coupled_joints=[FINGERS])
        self.cube = self.world.add_free_body(str(CUBE), cube_at)
        self.world.set_friction(self.cube, FRICTION)
        for finger in ("finger_left", "finger_right"):
            self.robot.set_link_friction(finger, FRICTION)
        self.order = [self.robot.joint_names.index(n) for n in ARM_JOINTS + FINGERS]

    def _full(self, arm, fingers):
        q = np.zeros(self.robot.dof)
        q[self.order] = list(arm) + [fingers, fingers]
        return q

    def reset(self, arm, fingers):
        self.robot.reset_joints(self._full(arm, fingers))

    def control(self, arm, fingers):
        self.robot.set_position_targets(self._full(arm, fingers))
        self.world.step()

    def cube_position(self):
        return np.array(self.world.body_pose(self.cube)[0])

    def close(self):
        pass


def grasp_and_lift(seed: int) -> dict:
    """Each simulator's cube after the scripted grasp and lift of `seed`'s cube."""
    cube_at = cube_start(seed)
    bullet = PyBulletScene(cube_at)
    over = lambda z: (cube_at[0], cube_at[1], z)  # noqa: E731
    above = bullet.ik(over(ABOVE_Z), HOME)
    targets = Targets(above, bullet.ik(over(GRASP_Z), above), bullet.ik(over(LIFT_Z), above))
    out = {}
    for name, scene in (("pybullet", bullet), ("rdsim", RdsimScene(cube_at))):
        scene.reset(targets.above, OPEN)
        for arm, fingers in schedule(targets):
            scene.control(arm, fingers)
        out[name] = scene.cube_position()
        scene.close()
    return out


def compare(seeds) -> dict:
    """Lift success of each simulator over `seeds`, and the cubes' distance where both lifted."""
    lifted = {"pybullet": 0, "rdsim": 0}
    gaps = []
    for seed in seeds:
        end = grasp_and_lift(seed)
        ok = {name: bool(end[name][2] > LIFTED) for name in end}
        for name in ok:
            lifted[name] += ok[name]
        if all(ok.values()):
            gaps.append(float(np.linalg.norm(end["rdsim"] - end["pybullet"])))
    return {"seeds": len(list(seeds)), "lifted": lifted, "gaps": gaps}


if __name__ == "__main__":
    r = compare(range(50))
    g = np.array(r["gaps"]) * 1000
    print(f"grasp and lift, {r['seeds']} seeds: lifted by pybullet {r['lifted']['pybullet']}, by rdsim {r['lifted']['rdsim']}")
    if len(g):
        print(f"cube after the lift, rdsim - pybullet where both lifted ({len(g)} seeds): "
              f"mean {g.mean():.2f} mm, median {np.median(g):.2f} mm, largest {g.max():.2f} mm")
