#!/usr/bin/env python3
"""Prints rdsim-versus-pybullet tables (docs/fidelity.md shows them and says how they were made).

    .venv/bin/python tools/fidelity/report.py                # the full benchmark (minutes)
    .venv/bin/python tools/fidelity/report.py --quick        # one seed, 200 steps
    .venv/bin/python tools/fidelity/report.py --robots jaka --only actions

Sections: targets (the same joint targets), ik (100 random reachable goals), inertia (the moments both
derive from the collision shapes), actions (10 seeds of 1,000 random discrete moves under the
original's recipe, with pybullet's solver early exit and with all 150 iterations), search (closest approach to the paper
button, greedy and beam search). Robots whose URDFs use meshes run only where rdsim loads meshes.
"""
from __future__ import annotations

import argparse
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

from fidelity import (CASES, action_sequence, inverse_kinematics, joint_targets, link_inertias,  # noqa: E402
                      pybullet_sensitivity)
from fidelity.arms import PYBULLET_RESIDUAL_THRESHOLD  # noqa: E402
from fidelity.button import button_search  # noqa: E402


def loads_in_rdsim(case) -> tuple[bool, str]:
    import rdsim
    import rdsim.sim

    try:
        rdsim.sim.World().add_robot(str(case.urdf()))
    except rdsim.Error as e:
        return False, str(e).splitlines()[0]
    return True, ""


def mm(x: float) -> str:
    return f"{1000 * x:.2f}"


def per_seed(rs) -> str:
    return ", ".join(f"{mm(r['ee_mean'])}/{mm(r['ee_max'])}" for r in rs)


def actions(name, case, inertia: str, seeds: int, steps: int) -> None:
    """Random moves under the original's recipe, with pybullet's early exit (residual threshold 1e-7)
    and with every one of the 150 solver iterations run (threshold 0) in both simulators, each
    beside pybullet against itself: its reset nudged by 1e-7 rad, and (early exit) its threshold
    lowered to 1e-9."""
    for residual, solver in ((PYBULLET_RESIDUAL_THRESHOLD, "early exit 1e-7"), (0.0, "150 iterations")):
        def line(what, rs):
            print(f"| {name} | inertia from the {inertia}, {solver} | {what} | "
                  f"ee mean {mm(np.mean([r['ee_mean'] for r in rs]))} mm | ee max {mm(np.max([r['ee_max'] for r in rs]))} mm | "
                  f"per seed mean/max {per_seed(rs)} mm |")
            sys.stdout.flush()
        line(f"rdsim vs pybullet, {seeds} x {steps} moves",
             [action_sequence(case, steps=steps, seed=s, inertia=inertia, solver_residual_threshold=residual)
              for s in range(seeds)])
        line("pybullet vs itself, reset nudged by 1e-7 rad",
             [pybullet_sensitivity(case, steps=steps, seed=s, inertia=inertia, solver_residual_threshold=residual)
              for s in range(seeds)])
        if residual > 0.0:
            line("pybullet vs itself, threshold 1e-9",
                 [pybullet_sensitivity(case, steps=steps, seed=s, nudge=0.0, inertia=inertia,
                                       second_residual_threshold=1e-9) for s in range(seeds)])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--robots", default="jaka,inmoov,kuka,panda")
    ap.add_argument("--only", default="targets,ik,inertia,actions,search")
    ap.add_argument("--quick", action="store_true", help="one seed, 200 steps, 20 IK goals")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--search-residual", type=float, default=1e-7,
                    help="the searches' solver residual threshold in both simulators (1e-7: pybullet's; 0: every iteration)")
    args = ap.parse_args()
    seeds = 1 if args.quick else args.seeds
    steps = 200 if args.quick else args.steps
    sections = args.only.split(",")
    for name in args.robots.split(","):
        case = CASES[name]
        ok, why = loads_in_rdsim(case)
        if not ok:
            print(f"| {name} | pending: rdsim does not load it yet ({why}) |")
            continue
        if "targets" in sections:
            for inertia in ("shapes", "urdf"):
                r = joint_targets(case, steps=steps, inertia=inertia)
                print(f"| {name} | joint targets, inertia from the {inertia} | "
                      f"ee mean {mm(r['ee_mean'])} mm | ee max {mm(r['ee_max'])} mm | q max {r['q_max']:.4f} rad |")
        if "ik" in sections:
            r = inverse_kinematics(case, goals=20 if args.quick else 100)
            print(f"| {name} | IK, {20 if args.quick else 100} goals | solution ee mean {mm(r['ee_mean'])} mm | "
                  f"max {mm(r['ee_max'])} mm | q max {r['q_max']:.2e} rad | residual pybullet "
                  f"{mm(r['pb_residual_mean'])} mm, rdsim {mm(r['rd_residual_mean'])} mm |")
        if "inertia" in sections:
            r = link_inertias(case)
            print(f"| {name} | inertia from the shapes, links with mass | worst relative difference "
                  f"{r['worst']:.1e} ({r['link']}) |")
        if "actions" in sections:
            for inertia in ("shapes", "urdf"):
                actions(name, case, inertia, seeds, steps)
        sys.stdout.flush()
    if "search" in sections and "jaka" in args.robots:
        for row in button_search(steps=steps, solver_residual_threshold=args.search_residual):
            print(row)
    return 0


if __name__ == "__main__":
    sys.exit(main())
