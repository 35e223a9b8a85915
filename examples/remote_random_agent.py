"""A random agent on an env served by `rdsim serve` (rdsim.RemoteEnv, Gymnasium's API).

    build/rdsim serve --insecure --bind tcp://127.0.0.1:7777 &
    .venv/bin/python examples/remote_random_agent.py tcp://127.0.0.1:7777 --env rdsim/JakaButton-v0
"""
from __future__ import annotations

import argparse

import rdsim


def main(argv=None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("address")
    p.add_argument("--env", default="rdsim/JakaButton-v0")
    p.add_argument("--server-key")
    p.add_argument("--client-key")
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args(argv)
    env = rdsim.RemoteEnv(a.address, a.env, server_key=a.server_key, client_key=a.client_key)
    env.action_space.seed(a.seed)
    env.reset(seed=a.seed)
    episodes, total = 0, 0.0
    for _ in range(a.steps):
        _, reward, terminated, truncated, info = env.step(env.action_space.sample())
        total += reward
        if terminated or truncated:
            episodes += 1
            print(f"episode {episodes}: success {info['success']}")
            env.reset()
    env.close()
    print(f"{a.steps} steps, {episodes} episodes, total reward {total:.2f}")
    return {"episodes": episodes, "total_reward": total}


if __name__ == "__main__":
    main()
