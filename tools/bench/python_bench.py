"""Steps/s of rdsim's Python vector env against the C++ VecEnv, Gymnasium's SyncVectorEnv, EnvPool
and Gymnasium's own vectorised CartPole (tools/bench/python.sh runs it; wall-clock, rerun on an idle
machine). Random actions are drawn before the clock starts; resets are included.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import time

import gymnasium
import numpy as np

import rdsim


def rate(step, actions, seconds: float, num_envs: int) -> float:
    """Env steps/s of `step(actions[k])` over at least `seconds` (after 50 warm-up steps)."""
    for k in range(50):
        step(actions[k % len(actions)])
    steps, start = 0, time.perf_counter()
    while True:
        for k in range(len(actions)):
            step(actions[k])
        steps += len(actions)
        elapsed = time.perf_counter() - start
        if elapsed >= seconds:
            return steps * num_envs / elapsed


def random_actions(space, n: int, count: int = 1000, seed: int = 0):
    rng = np.random.default_rng(seed)
    if isinstance(space, gymnasium.spaces.Discrete):
        return [rng.integers(0, space.n, size=n) for _ in range(count)]
    return [rng.uniform(space.low, space.high, size=(n,) + space.shape).astype(np.float32) for _ in range(count)]


def cpp_vec_env_rate(binary: str, env: str, num_envs: int, threads: int) -> dict:
    """`rdsim bench-fps --threads`: the C++ VecEnv with C++ random actions, no Python at all."""
    out = subprocess.run([binary, "bench-fps", "--env", env, "--mode", "ground_truth", "--threads", str(threads),
                          "--num-envs", str(num_envs), "--json", "-"], check=True, capture_output=True, text=True).stdout
    return json.loads(out[out.index("{"):] if "{" in out else out)


def fixed_rate(venv, step, actions, steps: int) -> float:
    """Env steps/s of `steps` vector steps after `reset(seed=0)` and `steps // 4` untimed ones (past
    the first episodes' start), with `actions` in turn: the same trajectories for every `step`
    function given, so only the per-call cost differs."""
    venv.reset(seed=0)
    warm_up = steps // 4
    for k in range(warm_up):
        venv._vec.step(actions[k % len(actions)])
    start = time.perf_counter()
    for k in range(warm_up, warm_up + steps):
        step(actions[k % len(actions)])
    return steps * venv.num_envs / (time.perf_counter() - start)


def overhead_ratios(binary: str, env: str, num_envs: int, seconds: float, rounds: int) -> None:
    """make_vec (one thread) against the C++ VecEnv on one thread (`rdsim bench-fps`, no Python) and
    against the same VecEnv stepped through the binding alone (the same seeds and actions, so the
    same trajectories), in rounds that rotate the order; prints each kind's median and the ratios."""
    name = rdsim._ids.env_name(env)
    venv = rdsim.make_vec(env, num_envs, num_threads=1)
    acts = random_actions(venv.single_action_space, num_envs)
    venv.reset(seed=0)
    steps = max(1000, int(seconds * rate(venv._vec.step, acts, 1.0, num_envs) / num_envs))

    def cpp_rate() -> float:
        out = subprocess.run([binary, "bench-fps", "--env", name, "--mode", "ground_truth", "--threads", "1",
                              "--num-envs", str(num_envs), "--runs", "1", "--steps", str(steps * num_envs),
                              "--json", "-"], check=True, capture_output=True, text=True).stdout
        return float(json.loads(out[out.index("{"):])["rows"][0]["threads"][0]["steps_per_s"])

    kinds = {"make_vec": lambda: fixed_rate(venv, venv.step, acts, steps),
             "binding": lambda: fixed_rate(venv, venv._vec.step, acts, steps), "cpp": cpp_rate}
    runs: dict[str, list[float]] = {kind: [] for kind in kinds}
    order = list(kinds)
    for r in range(rounds):
        for kind in order[r % 3:] + order[:r % 3]:  # each kind goes first in every third round
            runs[kind].append(kinds[kind]())
    venv.close()
    med = {k: float(np.median(v)) for k, v in runs.items()}
    # Ratios within each round (the same minute of a shared machine), then their median.
    ratio_cpp = float(np.median(np.array(runs["make_vec"]) / np.array(runs["cpp"])))
    ratio_binding = float(np.median(np.array(runs["make_vec"]) / np.array(runs["binding"])))
    print(f"{env}, {num_envs} envs, one thread, {rounds} rounds of {steps} vector steps (medians):")
    print(f"  rdsim.make_vec                       {med['make_vec']:>12,.0f} steps/s")
    print(f"  C++ VecEnv through the binding alone {med['binding']:>12,.0f} steps/s")
    print(f"  C++ VecEnv, no Python (bench-fps)    {med['cpp']:>12,.0f} steps/s")
    print(f"  make_vec / C++ VecEnv = {ratio_cpp:.3f}   make_vec / binding = {ratio_binding:.3f}"
          "   (medians of the per-round ratios)", flush=True)
    if os.environ.get("RDSIM_BENCH_VERBOSE"):
        print("  runs:", {k: [round(x) for x in v] for k, v in runs.items()})


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seconds", type=float, default=3.0, help="per row")
    p.add_argument("--num-envs", type=int, default=8)
    p.add_argument("--env", default="rdsim/JakaButton-v0")
    p.add_argument("--binary", default=os.environ.get("RDSIM_BIN", "build/rdsim"))
    p.add_argument("--overhead", action="store_true",
                   help="only the Python layer's cost: make_vec against the C++ VecEnv at 8 and 64 envs, alternating rounds")
    p.add_argument("--rounds", type=int, default=21, help="--overhead: alternating rounds")
    args = p.parse_args(argv)
    if args.overhead:
        for n in (8, 64):
            overhead_ratios(args.binary, args.env, n, min(args.seconds, 0.5), args.rounds)
        return
    n, s = args.num_envs, args.seconds
    rows = []

    def row(name, value):
        rows.append((name, value))
        print(f"{name:<58} {value:>12,.0f} steps/s", flush=True)

    print(f"{args.env}, {n} envs, {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    for threads in (1, 2):
        venv = rdsim.make_vec(args.env, n, num_threads=threads)
        venv.reset(seed=0)
        acts = random_actions(venv.single_action_space, n)
        row(f"rdsim.make_vec, {threads} thread(s)", rate(venv.step, acts, s, n))
        venv.close()
        venv = rdsim.make_vec(args.env, n, num_threads=threads, copy=False)
        venv.reset(seed=0)
        row(f"rdsim.make_vec(copy=False), {threads} thread(s)", rate(venv.step, acts, s, n))
        raw = venv._vec  # the C++ VecEnv through the binding alone: no Gymnasium layer
        row(f"C++ VecEnv stepped through the binding, {threads} thread(s)", rate(raw.step, acts, s, n))
        venv.close()
    try:
        name = rdsim._ids.env_name(args.env)
        result = cpp_vec_env_rate(args.binary, name, n, 2)
        for t in result["rows"][0]["threads"]:
            row(f"rdsim bench-fps (C++ only, no Python), {t['threads']} thread(s), {t['env_groups']} group(s)",
                t["steps_per_s"])
    except (OSError, subprocess.CalledProcessError, ValueError, KeyError, IndexError) as e:
        print(f"rdsim bench-fps not run: {e}")

    sync = gymnasium.vector.SyncVectorEnv([lambda: rdsim.make(args.env) for _ in range(n)])
    sync.reset(seed=0)
    row("gymnasium SyncVectorEnv of rdsim.make", rate(sync.step, random_actions(sync.single_action_space, n), s, n))
    sync.close()

    print(f"\nCartPole, {n} envs")
    cart = rdsim.make_vec("rdsim/CartPole-v1", n, num_threads=1)
    cart.reset(seed=0)
    acts = random_actions(cart.single_action_space, n)
    row("rdsim.make_vec('rdsim/CartPole-v1'), 1 thread", rate(cart.step, acts, s, n))
    cart.close()
    cart = rdsim.make_vec("rdsim/CartPole-v1", n, num_threads=1, copy=False)
    cart.reset(seed=0)
    row("rdsim.make_vec('rdsim/CartPole-v1', copy=False), 1 thread", rate(cart.step, acts, s, n))
    cart.close()
    try:
        import envpool

        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # EnvPool's float64 space bounds
            pool = envpool.make("CartPole-v1", env_type="gymnasium", num_envs=n)
            one = envpool.make("CartPole-v1", env_type="gymnasium", num_envs=n, num_threads=1)
        pool.reset()
        row("envpool.make('CartPole-v1', env_type='gymnasium')", rate(pool.step, acts, s, n))
        pool.close()
        one.reset()
        row("envpool.make(..., num_threads=1)", rate(one.step, acts, s, n))
        one.close()
    except ImportError as e:
        print(f"envpool not installed: {e}")
    gym_vec = gymnasium.make_vec("CartPole-v1", num_envs=n, vectorization_mode="vector_entry_point")
    gym_vec.reset(seed=0)
    row("gymnasium.make_vec('CartPole-v1') (NumPy-vectorised)", rate(gym_vec.step, acts, s, n))
    gym_vec.close()
    sync = gymnasium.make_vec("CartPole-v1", num_envs=n, vectorization_mode="sync")
    sync.reset(seed=0)
    row("gymnasium SyncVectorEnv of CartPole-v1", rate(sync.step, acts, s, n))
    sync.close()


if __name__ == "__main__":
    main()
