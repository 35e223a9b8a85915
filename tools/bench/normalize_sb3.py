"""The peer of tools/bench/normalize.sh: Stable-Baselines3 PPO on Gymnasium's CartPole-v1 with the
hyperparameters of configs/cartpole_ppo.json (rl-baselines3-zoo's), with and without VecNormalize's
observation normalisation, the same seeds. Prints one line per run: the first step at which the mean
return of the last 100 episodes reached 475 (or never), that mean at the end, and a deterministic
evaluation over 100 episodes.

    .venv/bin/python tools/bench/normalize_sb3.py --seeds 1 2 3 [--variants plain normalized]
"""
import argparse

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.vec_env import VecNormalize


class FirstSolved(BaseCallback):
    """The first timestep at which the last 100 finished episodes average >= 475."""

    def __init__(self):
        super().__init__()
        self.returns, self.solved_at = [], None

    def _on_step(self):
        for info in self.locals["infos"]:
            if "episode" in info:
                self.returns.append(info["episode"]["r"])
                if self.solved_at is None and len(self.returns) >= 100 and np.mean(self.returns[-100:]) >= 475:
                    self.solved_at = self.num_timesteps
        return True


def run(seed, normalize, steps):
    venv = make_vec_env("CartPole-v1", n_envs=8, seed=seed)
    if normalize:
        venv = VecNormalize(venv, norm_obs=True, norm_reward=False)
    model = PPO("MlpPolicy", venv, n_steps=32, batch_size=256, gae_lambda=0.8, gamma=0.98, n_epochs=20, ent_coef=0.0,
                learning_rate=lambda p: 0.001 * p, clip_range=lambda p: 0.2 * p, policy_kwargs={"net_arch": [64, 64]},
                seed=seed, device="cpu", verbose=0)
    callback = FirstSolved()
    model.learn(steps, callback=callback)
    if normalize:
        venv.training = False
    env = gym.make("CartPole-v1")
    returns = []
    obs, _ = env.reset(seed=seed)
    for _ in range(100):
        total, done = 0.0, False
        while not done:
            o = venv.normalize_obs(obs) if normalize else obs
            action, _ = model.predict(o, deterministic=True)
            obs, reward, terminated, truncated, _ = env.step(int(action))
            total += reward
            done = terminated or truncated
        returns.append(total)
        obs, _ = env.reset()
    last = np.mean(callback.returns[-100:])
    print(f"sb3 ppo cartpole {'normalized' if normalize else 'plain'} seed {seed}: solved at "
          f"{callback.solved_at or 'never'}, last 100 mean return {last:.1f}, eval {np.mean(returns):.1f}", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--timesteps", type=int, default=100_000)
    parser.add_argument("--variants", nargs="+", choices=["plain", "normalized"], default=["plain", "normalized"])
    args = parser.parse_args()
    torch.set_num_threads(1)
    for normalize in (v == "normalized" for v in args.variants):
        for seed in args.seeds:
            run(seed, normalize, args.timesteps)


if __name__ == "__main__":
    main()
