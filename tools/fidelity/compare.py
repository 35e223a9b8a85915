"""Step-by-step comparisons of rdsim with pybullet on the same URDF (importable by other tools).

Every function builds fresh simulators, drives both the same way and returns a small dict of
numbers (metres and radians); the pytest file and the report script only choose the sizes.

- :func:`joint_targets` -- the same random joint targets (position motors, the preset gains).
- :func:`inverse_kinematics` -- IK solutions for random reachable goals from the same start.
- :func:`action_sequence` -- the original's discrete-move recipe (IK goal = effector +- step, position
  motors, two physics steps per move) in pybullet against rdsim's paper preset recipe.

Options passed on to :func:`fidelity.arms.make_pair`: ``inertia`` ("shapes", the default and the
original's, or "urdf") and rdsim's ``speed_limits``, ``link_damping``, ``pybullet_solver`` (to measure
rdsim as it was before the fidelity changes).
- :func:`link_inertias` -- the masses and moments both derive from the collision shapes.
- :func:`recipe_search` -- greedy and beam searches over the six moves (closest approach to a point).
"""
from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from .arms import PYBULLET_RESIDUAL_THRESHOLD, PyBulletArm, RdsimArm, make_pair
from .robots import CASES, RobotCase

PHYSICS_STEPS_PER_MOVE = 2  # the original: two stepSimulation() calls per env step


def _case(case) -> RobotCase:
    return CASES[case] if isinstance(case, str) else case


def _summary(ee_dev: np.ndarray, q_dev: np.ndarray) -> dict:
    return {"ee_mean": float(ee_dev.mean()), "ee_max": float(ee_dev.max()), "ee_final": float(ee_dev[-1]),
            "q_mean": float(q_dev.mean()), "q_max": float(q_dev.max())}


def joint_targets(case, *, steps: int = 1000, hold: int = 100, seed: int = 0, spread: float = 0.5,
                  **options) -> dict:
    """Both arms from the reset pose towards random joint targets (reset +- spread rad, within the
    limits), a new target every `hold` physics steps: effector and joint deviations per physics step."""
    case = _case(case)
    pb, rd = make_pair(case, **options)
    rng = np.random.default_rng(seed)
    q0 = np.array(case.pose(rd.joint_names, "reset"))
    pb.reset_joints(q0)
    rd.reset_joints(q0)
    ee_dev, q_dev = [], []
    for k in range(steps):
        if k % hold == 0:
            target = np.clip(q0 + rng.uniform(-spread, spread, q0.size), rd.lower, rd.upper)
            pb.set_position_targets(target)
            rd.set_position_targets(target)
        pb.step()
        rd.step()
        ee_dev.append(np.linalg.norm(pb.link_position(case.effector) - rd.link_position(case.effector)))
        q_dev.append(np.abs(pb.joint_positions() - rd.joint_positions()).max())
    pb.close()
    return _summary(np.array(ee_dev), np.array(q_dev))


def _chain_mask(rd: RdsimArm, case: RobotCase) -> np.ndarray:
    """The movable joints between the root and the effector (the IK chain), read from the URDF."""
    import xml.etree.ElementTree as ET

    tree = ET.parse(str(case.urdf())).getroot()
    parent_of = {j.find("child").get("link"): (j.get("name"), j.find("parent").get("link")) for j in tree.iter("joint")}
    mask = np.zeros(rd.dof, dtype=bool)
    link = case.effector
    while link in parent_of:
        joint, link = parent_of[link]
        if joint in rd.joint_names:
            mask[rd.joint_names.index(joint)] = True
    return mask


def inverse_kinematics(case, *, goals: int = 100, seed: int = 0, spread: float = 0.6) -> dict:
    """IK solutions for random reachable goals (the effector at random joint angles within reset +-
    spread rad), both from the reset pose with the case's rest pose: joint differences over the
    effector's chain and the distance between the two solutions' effector positions."""
    case = _case(case)
    pb, rd = make_pair(case)
    rng = np.random.default_rng(seed)
    q0 = np.array(case.pose(rd.joint_names, "reset"))
    rest = np.array(case.pose(rd.joint_names, "rest"))
    chain = _chain_mask(rd, case)
    q_dev, ee_dev, pb_err, rd_err = [], [], [], []
    for _ in range(goals):
        q = q0.copy()
        q[chain] = np.clip(q0[chain] + rng.uniform(-spread, spread, chain.sum()), rd.lower[chain], rd.upper[chain])
        rd.reset_joints(q)
        goal = rd.link_position(case.effector)
        rd.reset_joints(q0)
        pb.reset_joints(q0)
        q_pb = pb.ik(case.effector, goal, rest)
        q_rd = rd.ik(case.effector, goal, rest)
        q_dev.append(np.abs(q_pb[chain] - q_rd[chain]).max())
        # Where each solution puts the effector (rdsim's kinematics for both: the same model).
        rd.reset_joints(q_pb)
        e_pb = rd.link_position(case.effector)
        rd.reset_joints(q_rd)
        e_rd = rd.link_position(case.effector)
        ee_dev.append(np.linalg.norm(e_pb - e_rd))
        pb_err.append(np.linalg.norm(e_pb - goal))
        rd_err.append(np.linalg.norm(e_rd - goal))
    pb.close()
    return {"q_mean": float(np.mean(q_dev)), "q_max": float(np.max(q_dev)), "ee_mean": float(np.mean(ee_dev)),
            "ee_max": float(np.max(ee_dev)), "pb_residual_mean": float(np.mean(pb_err)),
            "rd_residual_mean": float(np.mean(rd_err))}


def aim(arm, case: RobotCase, action: int, rest: np.ndarray) -> None:
    """The first half of a move: the IK goal is the effector +- action_step along one axis (actions
    0..5 = -x, +x, -y, +y, -z, +z), and the IK solution becomes the position targets."""
    goal = arm.link_position(case.effector).copy()
    goal[action // 2] += case.action_step if action % 2 else -case.action_step
    arm.set_position_targets(arm.ik(case.effector, goal, rest))


def move(arm, case: RobotCase, action: int, rest: np.ndarray) -> None:
    """One discrete move of the original's recipe: aim, then two physics steps."""
    aim(arm, case, action, rest)
    arm.step(PHYSICS_STEPS_PER_MOVE)


def action_sequence(case, *, steps: int = 1000, seed: int = 0, hold: int = 1,
                    actions: Optional[np.ndarray] = None, **options) -> dict:
    """The same random sequence of discrete moves (each held `hold` env steps) through the original's
    recipe in both simulators: effector and joint deviations per env step."""
    case = _case(case)
    pb, rd = make_pair(case, **options)
    rng = np.random.default_rng(seed)
    if actions is None:
        actions = np.repeat(rng.integers(0, 6, size=(steps + hold - 1) // hold), hold)[:steps]
    q0 = np.array(case.pose(rd.joint_names, "reset"))
    rest = np.array(case.pose(rd.joint_names, "rest"))
    pb.reset_joints(q0)
    rd.reset_joints(q0)
    result = _moves_side_by_side(pb, rd, case, actions, rest)
    pb.close()
    return result


def _moves_side_by_side(a, b, case: RobotCase, actions, rest: np.ndarray) -> dict:
    """Arms `a` and `b` through the same moves: effector and joint deviations after each."""
    ee_dev, q_dev = [], []
    for act in actions:
        move(a, case, int(act), rest)
        move(b, case, int(act), rest)
        ee_dev.append(np.linalg.norm(a.link_position(case.effector) - b.link_position(case.effector)))
        q_dev.append(np.abs(a.joint_positions() - b.joint_positions()).max())
    return _summary(np.array(ee_dev), np.array(q_dev))


def pybullet_sensitivity(case, *, steps: int = 1000, seed: int = 0, nudge: float = 1e-7,
                         inertia: str = "shapes", solver_residual_threshold: float = PYBULLET_RESIDUAL_THRESHOLD,
                         second_residual_threshold: Optional[float] = None) -> dict:
    """pybullet against itself: the same move sequence as action_sequence twice, the second run's
    reset pose nudged by `nudge` rad per joint, or its solver stopping at `second_residual_threshold`
    instead of `solver_residual_threshold`. How far the recipe itself amplifies a difference at or
    below float rounding, or a change of the solver's tolerance: a sequence pybullet does not
    reproduce under it cannot judge rdsim."""
    case = _case(case)
    second = solver_residual_threshold if second_residual_threshold is None else second_residual_threshold
    a = PyBulletArm(case, inertia_from_file=inertia == "urdf", solver_residual_threshold=solver_residual_threshold)
    b = PyBulletArm(case, inertia_from_file=inertia == "urdf", solver_residual_threshold=second)
    rng = np.random.default_rng(seed)
    actions = rng.integers(0, 6, size=steps)
    q0 = np.array(case.pose(a.joint_names, "reset"))
    rest = np.array(case.pose(a.joint_names, "rest"))
    a.reset_joints(q0)
    b.reset_joints(q0 + nudge)
    result = _moves_side_by_side(a, b, case, actions, rest)
    a.close()
    b.close()
    return result


def link_inertias(case) -> dict:
    """The masses and principal moments both simulators give the links when they derive the inertia
    from the collision shapes (pybullet's getDynamicsInfo; rdsim's Robot.link_inertia): the largest
    relative moment difference over the links with mass, and its link."""
    case = _case(case)
    pb, rd = make_pair(case, inertia="shapes")
    worst, worst_link = 0.0, ""
    for link in rd.robot.link_names:
        mass_pb, moments_pb = pb.link_inertia(link)
        mass_rd, moments_rd = rd.link_inertia(link)
        if mass_pb <= 0.0:  # a fixed base: pybullet gives it no mass
            continue
        diff = max(abs(mass_pb - mass_rd) / mass_pb,
                   float(np.max(np.abs(moments_pb - moments_rd) / np.abs(moments_pb))))
        if diff > worst:
            worst, worst_link = diff, link
    pb.close()
    return {"worst": worst, "link": worst_link}


def recipe_search(arm, case: RobotCase, point, *, steps: int = 1000, beam: int = 16, hold: int = 4,
                  disturbed: Optional[Callable[[], bool]] = None) -> dict:
    """Closest approach of the effector to `point` over `steps` env steps under the original's recipe:
    a greedy one-step lookahead, and a beam search (`beam` states, each move held `hold` steps). States
    where `disturbed()` is true (e.g. the button moved) are dropped from the search."""
    case = _case(case)
    point = np.asarray(point, dtype=float)
    rest = np.array(case.pose(arm.joint_names, "rest"))
    q0 = np.array(case.pose(arm.joint_names, "reset"))

    def reset():
        arm.reset_joints(q0)
        arm.step(0)

    def dist():
        return float(np.linalg.norm(arm.link_position(case.effector) - point))

    # Greedy: try each move for one step from the current state, keep the best.
    reset()
    initial = arm.save()  # the whole scene (a pushed button too) comes back from here
    state = arm.save()
    greedy_best = dist()
    for _ in range(steps):
        options = []
        for a in range(6):
            arm.restore(state)
            move(arm, case, a, rest)
            if disturbed is None or not disturbed():
                options.append((dist(), arm.save()))
        if not options:
            break
        best = min(options, key=lambda o: o[0])
        for o in options:
            if o is not best:
                arm.discard(o[1])
        arm.discard(state)
        d, state = best
        greedy_best = min(greedy_best, d)
    arm.discard(state)
    # Beam: `beam` best states by distance, every move held `hold` steps.
    arm.restore(initial)
    frontier = [(dist(), initial)]
    beam_best = frontier[0][0]
    for _ in range(steps // hold):
        children = []
        for _, s in frontier:
            for a in range(6):
                arm.restore(s)
                best_here = np.inf
                ok = True
                for _ in range(hold):
                    move(arm, case, a, rest)
                    if disturbed is not None and disturbed():
                        ok = False
                        break
                    best_here = min(best_here, dist())
                if ok:
                    beam_best = min(beam_best, best_here)
                    children.append((dist(), arm.save()))
        if not children:
            break
        children.sort(key=lambda c: c[0])
        for _, s in frontier + children[beam:]:
            arm.discard(s)
        frontier = children[:beam]
    for _, s in frontier:
        arm.discard(s)
    return {"greedy": greedy_best, "beam": beam_best}
