#!/usr/bin/env python3
"""The original's recipe in pybullet, timed: env steps per CPU-second, and where the time goes.

    .venv/bin/python tools/fidelity/recipe_speed.py [--steps 3000] [--runs 3]

rdsim's JAKA URDF loaded as the original loaded its robot (inertia from the shapes), the paper's
free 5 kg button on a floor plane, random moves of the original's recipe (IK goal = effector +- 1 m,
pybullet's calculateInverseKinematics with rest poses, position motors with kp 0.1 and kd 1, two
stepSimulation calls at 150 solver iterations), reset every 1,000 moves. Prints, per run, env steps
per CPU-second of the whole loop, and the CPU time per env step of the IK with its Python calls and
of the two physics steps: the bare loop of the original's env, without its observation, reward and
Gym layers. `rdsim bench-fps --paper --env jaka_button --mode ground_truth` is the rdsim side.
"""
from __future__ import annotations

import argparse
import pathlib
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

from fidelity.arms import PyBulletArm  # noqa: E402
from fidelity.button import PAPER_TARGET, pybullet_scene  # noqa: E402
from fidelity.compare import PHYSICS_STEPS_PER_MOVE, aim  # noqa: E402
from fidelity.robots import CASES  # noqa: E402


def run(steps: int, seed: int) -> tuple[float, float, float]:
    """(env steps per CPU-second, IK + targets us per step, physics us per step)."""
    case = CASES["jaka"]
    arm = PyBulletArm(case, inertia_from_file=False)
    pybullet_scene(arm, PAPER_TARGET)
    q0 = np.array(case.pose(arm.joint_names, "reset"))
    rest = np.array(case.pose(arm.joint_names, "rest"))
    actions = np.random.default_rng(seed).integers(0, 6, size=steps)
    ik = physics = 0.0
    for k, action in enumerate(actions):
        if k % 1000 == 0:
            arm.reset_joints(q0)
        t0 = time.process_time()
        aim(arm, case, int(action), rest)
        t1 = time.process_time()
        arm.step(PHYSICS_STEPS_PER_MOVE)
        t2 = time.process_time()
        ik += t1 - t0
        physics += t2 - t1
    arm.close()
    return steps / (ik + physics), 1e6 * ik / steps, 1e6 * physics / steps


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    if args.steps < 1 or args.runs < 1:
        ap.error("--steps and --runs must be at least 1")
    for r in range(args.runs):
        rate, ik, physics = run(args.steps, seed=r)
        print(f"run {r + 1}: {rate:,.0f} env steps per CPU-second; per env step: IK and targets {ik:.1f} us, "
              f"two physics steps {physics:.1f} us", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
