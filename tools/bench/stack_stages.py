"""How far a stack policy gets: over N episodes from the env's own starts (seeds 10000, 10001, ... by default),
the share in which the first cube ever comes within distance_threshold (5 cm) of its goal, the
share in which it is still there at the end, the same for the second cube, and the successes; then
each failed episode in one category, the first that fits:

  no lift          neither cube was ever lifted (2 cm above the table)
  second first     the second (green) cube was lifted before the first (blue) one
  first not placed the first cube was lifted but never reached its goal
  first moved      the first cube reached its goal and was not there at the end
  second not on    the first cube ends on its goal, the second does not end on top

and how far each episode's layout lies from the nearest of the expert's demonstrated ones (seeds
1000-1049, `rdsim demos record`'s default), for the successes and the failures apart: the first
cube's start alone, and the first cube, the second and the first goal together (x and y of each).

    .venv/bin/python tools/bench/stack_stages.py RUN/model.bin [--episodes 50] [--seed 10000]
"""
from __future__ import annotations

import argparse
from collections import Counter

import numpy as np

import rdsim

THRESHOLD = 0.05  # m: the env's distance_threshold
CUBE = 0.04  # m: the cubes' edge
LIFTED = CUBE / 2 + 0.02  # m: a cube's centre this high is off the table


def failure(first_lifted: int | None, reached: bool, first_at_end: bool) -> str:
    """The category of a failed episode (the module's docstring)."""
    if first_lifted is None:
        return "no lift"
    if first_lifted == 1:
        return "second first"
    if not reached:
        return "first not placed"
    if not first_at_end:
        return "first moved"
    return "second not on"


def layout(obs: dict) -> np.ndarray:
    """x, y of the first cube, the second and the first goal at a reset."""
    achieved, desired = obs["achieved_goal"], obs["desired_goal"]
    return np.concatenate([achieved[0:2], achieved[3:5], desired[0:2]])


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("model")
    p.add_argument("--episodes", type=int, default=50)
    p.add_argument("--seed", type=int, default=10_000,
                   help="episode k starts from reset(seed + k); the expert's 50 demonstrated layouts are "
                        "--seed 1000 --episodes 50 (seeds 1000-1049)")
    args = p.parse_args()
    if args.episodes < 1:
        p.error("--episodes: expected 1 or more")
    if args.seed < 0:
        p.error("--seed: expected 0 or more")
    model = rdsim.load_model(args.model)
    env = rdsim.make("stack")
    demonstrated = np.array([layout(env.reset(seed=1000 + k)[0]) for k in range(50)])
    reached_n = at_end_1 = at_end_2 = wins = 0
    failures: Counter[str] = Counter()
    nearest: dict[bool, list[tuple[float, float]]] = {True: [], False: []}  # m, by success
    for k in range(args.episodes):
        obs, _ = env.reset(seed=args.seed + k)
        offsets = demonstrated - layout(obs)
        near = (float(np.min(np.linalg.norm(offsets[:, 0:2], axis=1))), float(np.min(np.linalg.norm(offsets, axis=1))))
        ever = False
        first_lifted = None  # 0 or 1: the cube lifted first
        while True:
            flat = np.concatenate([obs["observation"], obs["achieved_goal"], obs["desired_goal"]])
            obs, _, terminated, truncated, info = env.step(model.predict(flat))
            achieved, desired = obs["achieved_goal"], obs["desired_goal"]
            ever |= bool(np.linalg.norm(achieved[:3] - desired[:3]) < THRESHOLD)
            if first_lifted is None:
                for cube in (0, 1):
                    if achieved[3 * cube + 2] > LIFTED:
                        first_lifted = cube
                        break
            if terminated or truncated:
                break
        first_ok = bool(np.linalg.norm(achieved[:3] - desired[:3]) < THRESHOLD)
        reached_n += ever
        at_end_1 += first_ok
        at_end_2 += bool(np.linalg.norm(achieved[3:] - desired[3:]) < THRESHOLD)
        nearest[bool(info["is_success"])].append(near)
        if info["is_success"]:
            wins += 1
        else:
            failures[failure(first_lifted, ever, first_ok)] += 1
    env.close()
    n = args.episodes
    print(f"{args.model}: first cube on its goal at some step {reached_n / n:.2f}, at the end {at_end_1 / n:.2f}; "
          f"second cube at the end {at_end_2 / n:.2f}; success {wins / n:.2f} ({n} episodes)")
    order = ["no lift", "second first", "first not placed", "first moved", "second not on"]
    print("failures: " + ", ".join(f"{name} {failures[name]}" for name in order))
    for won, name in ((True, "successes"), (False, "failures")):
        if nearest[won]:
            first, whole = np.mean(nearest[won], axis=0) * 100
            print(f"nearest demonstrated layout, {name}: first cube {first:.1f} cm, cubes and goal {whole:.1f} cm (mean)")


if __name__ == "__main__":
    main()
