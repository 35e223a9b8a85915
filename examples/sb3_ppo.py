"""Stable-Baselines3 PPO on rdsim.make_vec (CPU torch).

    python examples/sb3_ppo.py                                  # rdsim/JakaButton-v0, 300k steps
    python examples/sb3_ppo.py --env rdsim/CartPole-v1 --timesteps 50000

Trains on a C++ vector env (rdsim.make_vec, adapted to SB3 by rdsim.sb3.SB3VecEnv), then evaluates
the deterministic policy over --eval-episodes episodes; prints the mean return and success rate.
The JakaButton hyperparameters are configs/jaka_button.json's.
"""
from __future__ import annotations

import argparse
import time

import numpy as np


def evaluate(policy_act, env_id: str, episodes: int, seed: int, options: dict) -> dict:
    """Mean return and success rate of `policy_act(obs batch) -> actions` over `episodes` episodes."""
    import rdsim

    venv = rdsim.make_vec(env_id, 8, num_threads=1, **options)
    obs, _ = venv.reset(seed=seed)
    returns, successes, running = [], [], np.zeros(venv.num_envs)
    while len(returns) < episodes:
        obs, reward, terminated, truncated, info = venv.step(policy_act(obs))
        running += reward
        for i in np.flatnonzero(terminated | truncated):
            returns.append(running[i])
            successes.append(bool(info["final_info"]["success"][i]))
            running[i] = 0.0
    venv.close()
    return {"mean_return": float(np.mean(returns[:episodes])), "success_rate": float(np.mean(successes[:episodes]))}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="rdsim/JakaButton-v0")
    parser.add_argument("--timesteps", type=int, default=300_000)
    parser.add_argument("--num-envs", type=int, default=8)
    parser.add_argument("--num-threads", type=int, default=1)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--eval-episodes", type=int, default=100)
    parser.add_argument("--target", type=float, default=0.95, help="success rate whose first time is reported")
    args = parser.parse_args(argv)

    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecMonitor

    class TimeToTarget(BaseCallback):
        """The env steps and seconds until the success rate of the last 100 episodes first reaches --target."""

        def __init__(self) -> None:
            super().__init__()
            self.steps, self.seconds, self.start = None, None, time.perf_counter()

        def _on_step(self) -> bool:
            buf = self.model.ep_success_buffer
            if self.steps is None and len(buf) == buf.maxlen and np.mean(buf) >= args.target:
                self.steps, self.seconds = self.num_timesteps, time.perf_counter() - self.start
            return True

    import rdsim
    from rdsim.sb3 import SB3VecEnv

    torch.set_num_threads(1)
    options = {"random_target": True} if "Jaka" in args.env or "InMoov" in args.env else {}
    venv = VecMonitor(SB3VecEnv(rdsim.make_vec(args.env, args.num_envs, num_threads=args.num_threads, **options)))
    venv.seed(args.seed)
    model = PPO(
        "MlpPolicy", venv, n_steps=256, batch_size=256, n_epochs=10, learning_rate=lambda f: 3e-3 * f, gamma=0.98,
        gae_lambda=0.95, clip_range=0.2, ent_coef=0.0, vf_coef=0.5, max_grad_norm=0.5,
        policy_kwargs={"net_arch": [64, 64], "activation_fn": torch.nn.Tanh}, seed=args.seed, device="cpu", verbose=0,
    )
    start = time.perf_counter()
    target = TimeToTarget()
    model.learn(total_timesteps=args.timesteps, callback=target)
    seconds = time.perf_counter() - start
    venv.close()

    result = evaluate(lambda obs: model.predict(obs, deterministic=True)[0], args.env, args.eval_episodes, args.seed + 1000,
                      options)
    result.update({"timesteps": args.timesteps, "train_seconds": seconds, "steps_to_target": target.steps,
                   "seconds_to_target": target.seconds})
    reached = (f"success rate of the last 100 episodes first >= {args.target} at {target.steps} steps, "
               f"{target.seconds:.1f} s" if target.steps else f"success rate never reached {args.target} in training")
    print(f"{args.env} seed {args.seed}: {args.timesteps} steps in {seconds:.1f} s; {reached}; deterministic policy "
          f"over {args.eval_episodes} episodes: mean return {result['mean_return']:.2f}, "
          f"success rate {result['success_rate']:.2f}")
    return result


if __name__ == "__main__":
    main()
