"""Robustness to the reality gap (issue #43's benchmark, the part rdsim can randomize today): PPO on
jaka_button trained without and with domain randomization (observation noise and action latency),
each policy then evaluated with its most likely actions on 100 unperturbed and 100 perturbed
episodes (2 steps of action latency, 5 mm observation noise). Writes one CSV row per seed and
policy and prints each policy's perturbed / unperturbed success.

    .venv/bin/python tools/bench/robustness.py [--seeds 1 2 3] [--out runs/robustness]
        [--latency 2 --noise 0.005]   (the perturbation; training randomizes with the same values)

Masses, friction and camera moves are not randomized yet, so they are not among the perturbations.
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import pathlib
import platform

import numpy as np

import rdsim

ROOT = pathlib.Path(__file__).resolve().parents[2]


def success_rate(model: rdsim.Model, env_options: dict, episodes: int, seed: int) -> float:
    """Fraction of `episodes` episodes (seeds seed, seed + 1, ...) the model ends in success."""
    env = rdsim.make("rdsim/JakaButton-v0", **env_options)
    wins = 0
    for k in range(episodes):
        obs, _ = env.reset(seed=seed + k)
        while True:
            obs, _, terminated, truncated, info = env.step(int(model.predict(obs)))
            if terminated or truncated:
                wins += bool(info["success"])
                break
    env.close()
    return wins / episodes


def cpu_model() -> str:
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--episodes", type=int, default=100)
    p.add_argument("--out", default="runs/robustness")
    p.add_argument("--latency", type=int, default=2, help="steps of action latency (evaluation and training)")
    p.add_argument("--noise", type=float, default=0.005, help="observation noise, m (evaluation and training)")
    args = p.parse_args()
    perturbed = {"action_latency": args.latency, "observation_noise": args.noise}
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    base = json.loads((ROOT / "configs/jaka_button.json").read_text())
    base.pop("eval", None)
    rows = []
    for seed in args.seeds:
        for name, randomize in (("plain", None), ("randomized", perturbed)):
            config = json.loads(json.dumps(base))
            if randomize:
                config["env"]["randomize"] = randomize
            result = rdsim.train(config, seed=seed, log_dir=str(out / f"{name}_{seed}"), overwrite=True, quiet=True)
            model = rdsim.load_model(result.model_path)
            env = {k: v for k, v in base["env"].items() if k != "name"}
            clean = success_rate(model, env, args.episodes, 10_000)
            worse = success_rate(model, dict(env, randomize=perturbed), args.episodes, 10_000)
            rows.append({"seed": seed, "policy": name, "train_success": round(result.success_rate, 3),
                         "success": clean, "perturbed_success": worse,
                         "kept": round(worse / clean, 3) if clean else float("nan")})
            print(json.dumps(rows[-1]), flush=True)
    with open(out / "results.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"\n{cpu_model()}, {os.cpu_count()} cores; perturbation {perturbed}; {args.episodes} episodes each")
    for name in ("plain", "randomized"):
        kept = [r["kept"] for r in rows if r["policy"] == name]
        clean = [r["success"] for r in rows if r["policy"] == name]
        pert = [r["perturbed_success"] for r in rows if r["policy"] == name]
        print(f"{name:>10}: success {np.mean(clean):.2f} unperturbed, {np.mean(pert):.2f} perturbed; "
              f"kept {np.mean(kept):.2f} (seeds: {', '.join(f'{k:.2f}' for k in kept)})")
    print(f"wrote {out / 'results.csv'}")


if __name__ == "__main__":
    main()
