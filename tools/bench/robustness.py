"""Robustness to the reality gap (issue #43's benchmark): a policy trained without and one trained
with domain randomization, each evaluated with its most likely actions on 100 unperturbed and 100
perturbed episodes. Tasks: PPO on jaka_button (configs/jaka_button.json), SAC + HER on push
(configs/jaka_push.json) and PPO with a CNN on jaka_button's pixels (configs/jaka_button_pixels.json).
The perturbation: link and object masses x0.7-1.3, friction x0.5-1.5, 2 steps of action latency,
and 5 mm observation noise (ground truth) or the camera moved 3 cm and turned 3 degrees (pixels).
The training randomization is the same, except that each episode's latency is drawn from 0-2 steps
(random_latency) and, unless --memoryless, the randomized policy observes the actions still to run
(observe_latency with 2 slots; its unperturbed episodes then show empty slots). Writes one CSV row per task, seed and
policy and prints each policy's perturbed / unperturbed success ("kept").

    .venv/bin/python tools/bench/robustness.py [--tasks jaka_button push jaka_button_pixels]
        [--seeds 1 2 3] [--out runs/robustness] [--jobs 2] [--policies plain randomized] [--memoryless]
        [--timesteps N]
        [--mass 0.3 --friction 0.5 --latency 2 --noise 0.005 --camera-shift 0.03 --camera-turn 3]

Trainings run as `rdsim train` processes, --jobs at a time, one thread each; the evaluation uses the
Python package.
"""
from __future__ import annotations

import argparse
import concurrent.futures
import csv
import json
import os
import pathlib
import platform
import subprocess
import time

import numpy as np

import rdsim

ROOT = pathlib.Path(__file__).resolve().parents[2]
TASKS = {"jaka_button": "configs/jaka_button.json", "push": "configs/jaka_push.json",
         "jaka_button_pixels": "configs/jaka_button_pixels.json"}


def flat(obs) -> np.ndarray:
    """The observation as the policy takes it: a goal env's dict concatenated (observation, achieved, desired)."""
    if isinstance(obs, dict):
        return np.concatenate([obs["observation"], obs["achieved_goal"], obs["desired_goal"]])
    return obs


def success_rate(model: rdsim.Model, env_options: dict, episodes: int, seed: int) -> float:
    """Fraction of `episodes` episodes (seeds seed, seed + 1, ...) the model ends in success."""
    env = rdsim.make(env_options["name"], **{k: v for k, v in env_options.items() if k != "name"})
    wins = 0
    for k in range(episodes):
        obs, _ = env.reset(seed=seed + k)
        while True:
            action = model.predict(flat(obs))
            obs, _, terminated, truncated, info = env.step(int(action) if np.ndim(action) == 0 else action)
            if terminated or truncated:
                wins += bool(info.get("is_success", info.get("success", False)))
                break
    env.close()
    return wins / episodes


def train(rdsim_bin: str, config: dict, run: pathlib.Path) -> float:
    """Trains `config` into `run` with one thread; returns the seconds it took."""
    run.mkdir(parents=True, exist_ok=True)
    path = run.parent / f"{run.name}.json"
    path.write_text(json.dumps(config, indent=1))
    start = time.monotonic()
    subprocess.run([rdsim_bin, "train", "--quiet", "--overwrite", "--threads", "1", "--config", str(path),
                    "--log-dir", str(run)], check=True)
    return time.monotonic() - start


def observed(args) -> dict:
    """The randomize keys that put the pending actions into the observation (none with --memoryless)."""
    return {} if args.memoryless else {"observe_latency": True, "latency_slots": args.latency}


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
    p.add_argument("--tasks", nargs="+", choices=list(TASKS), default=list(TASKS))
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--episodes", type=int, default=100)
    p.add_argument("--out", default="runs/robustness")
    p.add_argument("--jobs", type=int, default=2, help="trainings at a time")
    p.add_argument("--mass", type=float, default=0.3, help="masses x (1 +- this)")
    p.add_argument("--friction", type=float, default=0.5, help="friction x (1 +- this)")
    p.add_argument("--latency", type=int, default=2, help="steps of action latency")
    p.add_argument("--noise", type=float, default=0.005, help="observation noise, m (ground truth)")
    p.add_argument("--camera-shift", type=float, default=0.03, help="camera moves, m per axis (pixels)")
    p.add_argument("--camera-turn", type=float, default=3.0, help="camera turns, degrees of yaw and pitch (pixels)")
    p.add_argument("--policies", nargs="+", choices=["plain", "randomized"], default=["plain", "randomized"])
    p.add_argument("--timesteps", type=int, help="training steps of every run (default: each config's)")
    p.add_argument("--memoryless", action="store_true", help="the randomized policy does not observe the pending actions")
    p.add_argument("--rdsim", default=os.environ.get("RDSIM_BIN", str(ROOT / "build/rdsim")), help="the rdsim binary")
    args = p.parse_args()
    physical = {"mass_scale": [1 - args.mass, 1 + args.mass], "friction_scale": [1 - args.friction, 1 + args.friction],
                "action_latency": args.latency}
    perturbations = {"ground_truth": dict(physical, observation_noise=args.noise),
                     "raw_pixels": dict(physical, camera_shift=args.camera_shift, camera_turn=args.camera_turn)}
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    runs = []  # (task, seed, policy, config, run folder)
    for task in args.tasks:
        base = json.loads((ROOT / TASKS[task]).read_text())
        base.pop("eval", None)
        perturbation = perturbations[base["env"].get("observation", "ground_truth")]
        for seed in args.seeds:
            for policy in args.policies:
                config = json.loads(json.dumps(base))
                config["seed"] = seed
                if args.timesteps:
                    config["total_timesteps"] = args.timesteps
                if policy == "randomized":  # the perturbation, each episode's latency drawn from 0..its latency
                    pixels = base["env"].get("observation") == "raw_pixels"  # observe_latency: ground truth only
                    config["env"]["randomize"] = dict(perturbation, random_latency=True, **({} if pixels else observed(args)))
                runs.append((task, seed, policy, config, out / f"{task}_{policy}_{seed}"))
    print(f"training {len(runs)} policies, {args.jobs} at a time", flush=True)
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        seconds = list(pool.map(lambda r: train(args.rdsim, r[3], r[4]), runs))

    rows = []
    for (task, seed, policy, config, run), took in zip(runs, seconds):
        model = rdsim.load_model(run / "model.bin")
        env = {k: v for k, v in config["env"].items() if k != "randomize"}
        perturbation = perturbations[env.get("observation", "ground_truth")]
        # The policy's own observation layout: with the pending actions, the unperturbed env keeps empty slots.
        layout = observed(args) if policy == "randomized" and env.get("observation") != "raw_pixels" else {}
        clean = success_rate(model, dict(env, randomize=layout) if layout else env, args.episodes, 10_000)
        worse = success_rate(model, dict(env, randomize=dict(perturbation, **layout)), args.episodes, 10_000)
        rows.append({"task": task, "seed": seed, "policy": policy, "train_seconds": round(took),
                     "success": clean, "perturbed_success": worse,
                     "kept": round(worse / clean, 3) if clean else float("nan")})
        print(json.dumps(rows[-1]), flush=True)
    with open(out / "results.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"\n{cpu_model()}, {os.cpu_count()} cores; perturbations {perturbations}; {args.episodes} episodes each")
    for task in args.tasks:
        for policy in args.policies:
            mine = [r for r in rows if r["task"] == task and r["policy"] == policy]
            print(f"{task:>12} {policy:>10}: success {np.mean([r['success'] for r in mine]):.2f} unperturbed, "
                  f"{np.mean([r['perturbed_success'] for r in mine]):.2f} perturbed; kept "
                  f"{np.mean([r['kept'] for r in mine]):.2f} (seeds: {', '.join(str(r['kept']) for r in mine)})")
    print(f"wrote {out / 'results.csv'}")


if __name__ == "__main__":
    main()
