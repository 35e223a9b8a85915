"""PPO in one file, in CleanRL's style, on rdsim.make_vec (PyTorch, CPU).

    python examples/cleanrl_ppo.py                                 # rdsim/JakaButton-v0, 300k steps
    python examples/cleanrl_ppo.py --env rdsim/CartPole-v1 --timesteps 50000

Discrete action spaces (a categorical policy). rdsim's vector env resets an ended episode in the
same step (metadata["autoreset_mode"] == SAME_STEP): the value of info["final_obs"] bootstraps the
return of an episode cut by its step limit, and the observation returned is the next episode's first.
"""
from __future__ import annotations

import argparse
import time

import numpy as np
import torch
import torch.nn as nn
from torch.distributions.categorical import Categorical


def layer(inputs: int, outputs: int, std: float = np.sqrt(2)) -> nn.Linear:
    lin = nn.Linear(inputs, outputs)
    nn.init.orthogonal_(lin.weight, std)
    nn.init.constant_(lin.bias, 0.0)
    return lin


class Agent(nn.Module):
    def __init__(self, obs_dim: int, actions: int, hidden: int = 64) -> None:
        super().__init__()
        self.critic = nn.Sequential(layer(obs_dim, hidden), nn.Tanh(), layer(hidden, hidden), nn.Tanh(), layer(hidden, 1, 1.0))
        self.actor = nn.Sequential(layer(obs_dim, hidden), nn.Tanh(), layer(hidden, hidden), nn.Tanh(),
                                   layer(hidden, actions, 0.01))

    def value(self, x: torch.Tensor) -> torch.Tensor:
        return self.critic(x).squeeze(-1)

    def act(self, x: torch.Tensor, action=None):
        dist = Categorical(logits=self.actor(x))
        if action is None:
            action = dist.sample()
        return action, dist.log_prob(action), dist.entropy(), self.value(x)


def main(argv=None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--env", default="rdsim/JakaButton-v0")
    p.add_argument("--timesteps", type=int, default=300_000)
    p.add_argument("--num-envs", type=int, default=8)
    p.add_argument("--num-threads", type=int, default=1)
    p.add_argument("--num-steps", type=int, default=256, help="steps per env per rollout")
    p.add_argument("--lr", type=float, default=3e-3)
    p.add_argument("--gamma", type=float, default=0.98)
    p.add_argument("--gae-lambda", type=float, default=0.95)
    p.add_argument("--minibatches", type=int, default=8)
    p.add_argument("--epochs", type=int, default=10)
    p.add_argument("--clip", type=float, default=0.2)
    p.add_argument("--vf-coef", type=float, default=0.5)
    p.add_argument("--max-grad-norm", type=float, default=0.5)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--target", type=float, default=0.95, help="success rate whose first time is reported")
    args = p.parse_args(argv)

    import rdsim

    torch.manual_seed(args.seed)
    torch.set_num_threads(1)
    options = {"random_target": True} if "Jaka" in args.env or "InMoov" in args.env else {}
    envs = rdsim.make_vec(args.env, args.num_envs, num_threads=args.num_threads, **options)
    n, obs_dim = envs.num_envs, int(np.prod(envs.single_observation_space.shape))
    agent = Agent(obs_dim, int(envs.single_action_space.n))
    optimizer = torch.optim.Adam(agent.parameters(), lr=args.lr, eps=1e-5)

    T = args.num_steps
    obs_buf = torch.zeros((T, n, obs_dim))
    act_buf = torch.zeros((T, n), dtype=torch.long)
    logp_buf, rew_buf, done_buf, val_buf = (torch.zeros((T, n)) for _ in range(4))

    next_obs = torch.as_tensor(envs.reset(seed=args.seed)[0]).reshape(n, -1)
    episode_return, returns, successes = np.zeros(n), [], []
    updates = max(1, args.timesteps // (T * n))
    reached = None  # (env steps, seconds) when the last 100 episodes' success rate first reached --target
    start = time.perf_counter()
    for update in range(updates):
        for g in optimizer.param_groups:
            g["lr"] = args.lr * (1.0 - update / updates)
        for t in range(T):
            obs_buf[t] = next_obs
            with torch.no_grad():
                action, logp, _, value = agent.act(next_obs)
            obs, reward, terminated, truncated, info = envs.step(action.numpy())
            track(episode_return, returns, successes, reward, terminated | truncated, info)
            if reached is None and len(successes) >= 100 and np.mean(successes[-100:]) >= args.target:
                reached = ((update * T + t + 1) * n, time.perf_counter() - start)
            reward = torch.as_tensor(reward)
            ended = terminated | truncated
            if ended.any():
                # Same-step autoreset: bootstrap a truncated episode from its final observation's value.
                for i in np.flatnonzero(truncated & ~terminated):
                    with torch.no_grad():
                        final = torch.as_tensor(info["final_obs"][i]).reshape(1, -1)
                        reward[i] += args.gamma * agent.value(final)[0]
            act_buf[t], logp_buf[t], val_buf[t], rew_buf[t] = action, logp, value, reward
            done_buf[t] = torch.as_tensor(ended, dtype=torch.float32)
            next_obs = torch.as_tensor(obs).reshape(n, -1)

        with torch.no_grad():  # GAE
            next_value = agent.value(next_obs)
            adv = torch.zeros((T, n))
            last = torch.zeros(n)
            for t in reversed(range(T)):
                nonterminal = 1.0 - done_buf[t]
                nv = next_value if t == T - 1 else val_buf[t + 1]
                delta = rew_buf[t] + args.gamma * nv * nonterminal - val_buf[t]
                last = delta + args.gamma * args.gae_lambda * nonterminal * last
                adv[t] = last
            ret = adv + val_buf

        b_obs, b_act, b_logp = obs_buf.reshape(T * n, -1), act_buf.reshape(-1), logp_buf.reshape(-1)
        b_adv, b_ret = adv.reshape(-1), ret.reshape(-1)
        size = T * n // args.minibatches
        for _ in range(args.epochs):
            order = torch.randperm(T * n)
            for s in range(0, T * n, size):
                mb = order[s:s + size]
                _, logp, entropy, value = agent.act(b_obs[mb], b_act[mb])
                ratio = (logp - b_logp[mb]).exp()
                a = b_adv[mb]
                a = (a - a.mean()) / (a.std() + 1e-8)
                pg = torch.max(-a * ratio, -a * ratio.clamp(1 - args.clip, 1 + args.clip)).mean()
                loss = pg + args.vf_coef * 0.5 * ((value - b_ret[mb]) ** 2).mean()
                optimizer.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
                optimizer.step()
    seconds = time.perf_counter() - start
    envs.close()

    window = max(1, len(returns) // 10)
    result = {
        "first_returns": float(np.mean(returns[:window])) if returns else 0.0,
        "last_returns": float(np.mean(returns[-window:])) if returns else 0.0,
        "last_success_rate": float(np.mean(successes[-window:])) if successes else 0.0,
        "episodes": len(returns),
        "timesteps": updates * T * n,
        "train_seconds": seconds,
        "steps_to_target": reached[0] if reached else None,
        "seconds_to_target": reached[1] if reached else None,
    }
    print(f"{args.env} seed {args.seed}: {result['timesteps']} steps in {seconds:.1f} s, {len(returns)} episodes; mean return of the "
          f"first/last {window}: {result['first_returns']:.2f} / {result['last_returns']:.2f}; success rate of the last "
          f"{window}: {result['last_success_rate']:.2f}; "
          + (f"success rate of the last 100 episodes first >= {args.target} at {reached[0]} steps, {reached[1]:.1f} s"
             if reached else f"success rate never reached {args.target}"))
    return result


def track(episode_return, returns, successes, reward, ended, info) -> None:
    """Episode returns (env rewards, before bootstrapping) and success flags of the episodes that ended."""
    episode_return += reward
    for i in np.flatnonzero(ended):
        returns.append(float(episode_return[i]))
        successes.append(bool(info["final_info"]["success"][i]))
        episode_return[i] = 0.0


if __name__ == "__main__":
    main()
