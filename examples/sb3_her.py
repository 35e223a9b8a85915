"""Stable-Baselines3 SAC + HerReplayBuffer on an rdsim goal task (CPU torch).

    python examples/sb3_her.py                                   # rdsim/JakaPush-v0, configs/jaka_push.json
    python examples/sb3_her.py --env rdsim/JakaReachGoal-v0 --timesteps 20000 --log-dir runs/sb3_reach

The same task as rdsim's own SAC + HER config (configs/jaka_push.json): the same networks, batch,
learning rate, discount, Polyak factor, warm-up, gradient steps per env step and HER settings, read
from --config, so the two can be compared (tools/bench/her.sh). Trains on a C++ vector env
(rdsim.make_vec, adapted by rdsim.sb3.SB3VecEnv, whose env_method("compute_reward") is the env's
batched goal reward), then evaluates the deterministic policy over --eval-episodes episodes.
--csv writes every training episode as rdsim's episodes.csv does (episode, timesteps, return,
length, success, wall_time), so tools/bench/learning.sh's statistics apply to both; --log-dir makes a
run folder of it (episodes.csv and a config.json naming the algorithm "sb3_sac", the env and the
seed) that `rdsim plot` draws beside rdsim's runs, e.g. against wall-clock (--x wall_time).
"""
from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def write_episodes(path: Path, rows: list) -> None:
    """Training episodes in rdsim's episodes.csv columns (tools/bench/her.sh and `rdsim plot` read both)."""
    with open(path, "w", newline="") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(["episode", "timesteps", "return", "length", "success", "wall_time"])
        writer.writerows(rows)


def evaluate(predict, env_id: str, episodes: int, seed: int, options: dict) -> float:
    """Success rate of `predict(obs batch) -> actions` over `episodes` episodes."""
    import rdsim

    venv = rdsim.make_vec(env_id, 8, num_threads=1, **options)
    obs, _ = venv.reset(seed=seed)
    successes = []
    while len(successes) < episodes:
        obs, _, terminated, truncated, info = venv.step(predict(obs))
        for i in np.flatnonzero(terminated | truncated):
            successes.append(bool(info["final_info"]["success"][i]))
    venv.close()
    return float(np.mean(successes[:episodes]))


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="rdsim/JakaPush-v0")
    parser.add_argument("--config", default=str(ROOT / "configs/jaka_push.json"),
                        help="rdsim training config whose sac, her, network and num_envs settings to use")
    parser.add_argument("--timesteps", type=int, default=None, help="default: the config's total_timesteps")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--torch-threads", type=int, default=None, help="default: torch's (every core)")
    parser.add_argument("--eval-episodes", type=int, default=100)
    parser.add_argument("--target", type=float, default=0.9, help="success rate whose first time is reported")
    parser.add_argument("--csv", help="write every training episode here")
    parser.add_argument("--log-dir", help="write a run folder here for `rdsim plot`: episodes.csv and config.json")
    args = parser.parse_args(argv)

    import torch
    from stable_baselines3 import SAC, HerReplayBuffer
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecMonitor

    import rdsim
    from rdsim.sb3 import SB3VecEnv

    config = json.loads(Path(args.config).read_text())
    sac, her, net = config.get("sac", {}), config.get("her", {}), config.get("network", {})
    timesteps = args.timesteps or config["total_timesteps"]
    num_envs = config.get("num_envs", 1)
    options = {k: v for k, v in config.get("env", {}).items() if k != "name"}
    if args.torch_threads:
        torch.set_num_threads(args.torch_threads)

    class EpisodeLog(BaseCallback):
        """Every finished episode as a row; the first time the last 100 reach --target."""

        def __init__(self) -> None:
            super().__init__()
            self.rows, self.successes = [], []
            self.steps_to_target = self.seconds_to_target = None
            self.start = time.perf_counter()

        def _on_step(self) -> bool:
            for info in self.locals["infos"]:
                if "episode" not in info:
                    continue
                success = float(info.get("is_success", 0.0))
                self.successes.append(success)
                elapsed = time.perf_counter() - self.start
                self.rows.append([len(self.rows) + 1, self.num_timesteps, info["episode"]["r"], info["episode"]["l"],
                                  int(success), round(elapsed, 3)])
                if self.steps_to_target is None and len(self.successes) >= 100 and np.mean(self.successes[-100:]) >= args.target:
                    self.steps_to_target, self.seconds_to_target = self.num_timesteps, elapsed
            return True

    venv = VecMonitor(SB3VecEnv(rdsim.make_vec(args.env, num_envs, num_threads=1, **options)), info_keywords=("is_success",))
    venv.seed(args.seed)
    model = SAC(
        "MultiInputPolicy", venv, learning_rate=sac.get("learning_rate", 3e-4), buffer_size=sac.get("buffer_size", 1_000_000),
        learning_starts=sac.get("learning_starts", 100), batch_size=sac.get("batch_size", 256), tau=sac.get("tau", 0.005),
        gamma=sac.get("gamma", 0.99), train_freq=sac.get("train_freq", 1), gradient_steps=sac.get("gradient_steps", 1),
        replay_buffer_class=HerReplayBuffer,
        replay_buffer_kwargs={"n_sampled_goal": her.get("n_sampled_goal", 4),
                              "goal_selection_strategy": her.get("goal_selection_strategy", "future")},
        policy_kwargs={"net_arch": net.get("hidden_sizes", [256, 256])}, seed=args.seed, device="cpu", verbose=0,
    )
    log = EpisodeLog()
    start = time.perf_counter()
    model.learn(total_timesteps=timesteps, callback=log)
    seconds = time.perf_counter() - start
    venv.close()
    if args.log_dir:
        folder = Path(args.log_dir)
        folder.mkdir(parents=True, exist_ok=True)
        write_episodes(folder / "episodes.csv", log.rows)
        # What `rdsim plot` reads of a run's config.json (algorithm, env name, seed), and where it came from.
        run = {"algorithm": "sb3_sac", "env": {"name": rdsim.IDS.get(args.env, args.env), **options}, "seed": args.seed,
               "total_timesteps": timesteps, "written_by": "examples/sb3_her.py: Stable-Baselines3 SAC + HerReplayBuffer "
               f"with {Path(args.config).name}'s settings (not an rdsim config)"}
        (folder / "config.json").write_text(json.dumps(run, indent=2) + "\n")
    if args.csv:
        write_episodes(Path(args.csv), log.rows)
    success = evaluate(lambda obs: model.predict(obs, deterministic=True)[0], args.env, args.eval_episodes,
                       args.seed + 1000, options)
    reached = (f"success of the last 100 episodes first >= {args.target} at {log.steps_to_target} steps, "
               f"{log.seconds_to_target:.1f} s" if log.steps_to_target else f"success never reached {args.target}")
    print(f"SB3 SAC+HER {args.env} seed {args.seed}: {timesteps} steps in {seconds:.1f} s; {reached}; deterministic "
          f"policy over {args.eval_episodes} episodes: success {success:.2f}")
    return {"timesteps": timesteps, "train_seconds": seconds, "steps_to_target": log.steps_to_target,
            "seconds_to_target": log.seconds_to_target, "eval_success": success}


if __name__ == "__main__":
    main()
