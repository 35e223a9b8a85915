"""How far a stack policy gets: over N episodes from the env's own starts (seeds 10000, 10001, ...),
the share in which the first cube ever comes within distance_threshold (5 cm) of its goal, the
share in which it is still there at the end, the same for the second cube, and the successes.

    .venv/bin/python tools/bench/stack_stages.py RUN/model.bin [--episodes 50]
"""
from __future__ import annotations

import argparse

import numpy as np

import rdsim


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("model")
    p.add_argument("--episodes", type=int, default=50)
    args = p.parse_args()
    model = rdsim.load_model(args.model)
    env = rdsim.make("stack")
    threshold = 0.05
    reached = at_end_1 = at_end_2 = wins = 0
    for k in range(args.episodes):
        obs, _ = env.reset(seed=10_000 + k)
        ever = False
        while True:
            flat = np.concatenate([obs["observation"], obs["achieved_goal"], obs["desired_goal"]])
            obs, _, terminated, truncated, info = env.step(model.predict(flat))
            achieved, desired = obs["achieved_goal"], obs["desired_goal"]
            ever |= bool(np.linalg.norm(achieved[:3] - desired[:3]) < threshold)
            if terminated or truncated:
                break
        reached += ever
        at_end_1 += bool(np.linalg.norm(achieved[:3] - desired[:3]) < threshold)
        at_end_2 += bool(np.linalg.norm(achieved[3:] - desired[3:]) < threshold)
        wins += bool(info["is_success"])
    env.close()
    n = args.episodes
    print(f"{args.model}: first cube on its goal at some step {reached / n:.2f}, at the end {at_end_1 / n:.2f}; "
          f"second cube at the end {at_end_2 / n:.2f}; success {wins / n:.2f} ({n} episodes)")


if __name__ == "__main__":
    main()
