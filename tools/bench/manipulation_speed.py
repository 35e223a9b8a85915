"""Manipulation speed against panda-gym, in one run on one machine (not a unit test; rerun on an idle
machine): env steps per CPU-second on one thread, random actions, resets included, the same simulated
time per env step (40 ms: panda-gym's 20 substeps of 2 ms, rdsim's 10 of 4 ms).

  rdsim      `rdsim bench-fps --env push --env pick_and_place --mode ground_truth` (C++, one thread;
             its figure is per wall second of a single-threaded loop, which is its CPU time)
  panda-gym  3.0.7 on pybullet 3.2.7: PandaPush-v3, PandaPickAndPlace-v3 through gymnasium.make
             (time.process_time around the loop)

  --substeps N ...  rdsim rows with N physics steps of 40/N ms per env step (`bench-fps --set substeps=N
             --set physics_step=...`; the drive's gain follows), one row per N; default 10 (the defaults)

Usage: .venv/bin/python tools/bench/manipulation_speed.py [--steps 3000] [--rounds 3] [--substeps 10 6 5]
       [--rdsim build/rdsim]
"""
import argparse
import re
import statistics
import subprocess
import time

PAIRS = [("push", "PandaPush-v3"), ("pick_and_place", "PandaPickAndPlace-v3")]


def panda_gym_rate(env_id, steps):
    import gymnasium
    import panda_gym  # noqa: F401  (registers the Panda envs)

    env = gymnasium.make(env_id)
    env.reset(seed=0)
    env.action_space.seed(0)
    start = time.process_time()
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset()
    rate = steps / (time.process_time() - start)
    env.close()
    return rate


def rdsim_rates(binary, steps, substeps):
    cmd = [binary, "bench-fps", "--mode", "ground_truth", "--runs", "3", "--steps", str(steps)]
    if substeps != 10:
        cmd += ["--set", "substeps=%d" % substeps, "--set", "physics_step=%r" % (0.04 / substeps)]
    for name, _ in PAIRS:
        cmd += ["--env", name]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    rates = {}
    for name, _ in PAIRS:
        m = re.search(r"^%s\s+ground_truth\s+-\s+(\d+)" % re.escape(name), out, re.M)
        rates[name] = float(m.group(1))
    return rates


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--steps", type=int, default=3000, help="env steps per measurement")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds (the median is reported)")
    parser.add_argument("--substeps", type=int, nargs="+", default=[10],
                        help="rdsim's physics steps per 40 ms env step, one row each")
    parser.add_argument("--rdsim", default="build/rdsim")
    a = parser.parse_args()
    rows = {name: {"panda-gym": [], **{n: [] for n in a.substeps}} for name, _ in PAIRS}
    for _ in range(a.rounds):  # interleaved, so both see the same machine
        for n in a.substeps:
            rates = rdsim_rates(a.rdsim, a.steps, n)
            for name, _ in PAIRS:
                rows[name][n].append(rates[name])
        for name, gym_id in PAIRS:
            rows[name]["panda-gym"].append(panda_gym_rate(gym_id, a.steps))
    print("env steps per CPU-second, one thread, random actions, resets included; median of %d rounds" % a.rounds)
    print("%-16s %9s %12s %12s %8s" % ("task", "substeps", "rdsim", "panda-gym", "ratio"))
    for name, gym_id in PAIRS:
        theirs = statistics.median(rows[name]["panda-gym"])
        for n in a.substeps:
            ours = statistics.median(rows[name][n])
            print("%-16s %9d %12.0f %12.0f %7.1fx   (%s)" % (name, n, ours, theirs, ours / theirs, gym_id))


if __name__ == "__main__":
    main()
