#!/usr/bin/env python3
"""rdsim's learner against PyTorch's on the same networks, in one run.

For every row of `rdsim bench-learner` (PPO's actor-critic MLPs and CNNs, SAC's critic pair) this
builds the same layers in PyTorch (CPU, float32, oneDNN as the wheel ships it) from the JSON that
rdsim writes, and times the same update: zero_grad + forward + backward + Adam step on fixed
random inputs, with the same loss terms, batch and activations. rdsim and PyTorch alternate row by
row (rdsim, then PyTorch on each thread count), so both see the same machine load; each figure is
the median over --reps repeats of a run of >= --min-seconds. The ratio is PyTorch's time per update
over rdsim's: above 1, rdsim is faster.

Usage (from the repository root, with the project's venv):
  /work/main/.venv/bin/python tools/bench/learner.py --rdsim build/rdsim [--reps 3] [--threads 1 2]
      [--row ppo_mlp] [--min-seconds 0.5] [--json results.json]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import torch
import torch.nn as nn
import torch.nn.functional as F

ACTIVATIONS = {"tanh": nn.Tanh, "relu": nn.ReLU}


def mlp(spec):
    layers, width = [], spec["inputs"]
    for h in spec["hidden"]:
        layers += [nn.Linear(width, h), ACTIVATIONS[spec["activation"]]()]
        width = h
    layers.append(nn.Linear(width, spec["outputs"]))
    return nn.Sequential(*layers)


class CnnActorCritic(nn.Module):
    """PPO's pixel actor-critic: conv trunk + fc (ReLU), linear policy and value heads."""

    def __init__(self, d):
        super().__init__()
        h, w, c = d["image"]
        layers = []
        for out, kernel, stride in d["convs"]:
            layers += [nn.Conv2d(c, out, kernel, stride), nn.ReLU()]
            c = out
            h, w = (h - kernel) // stride + 1, (w - kernel) // stride + 1
        layers.append(nn.Flatten())
        width = c * h * w
        for f in d["fc"]:
            layers += [nn.Linear(width, f), nn.ReLU()]
            width = f
        self.trunk = nn.Sequential(*layers)
        self.policy = nn.Linear(width, d["actions"])
        self.value = nn.Linear(width, 1)

    def forward(self, x):
        f = self.trunk(x)
        return self.policy(f), self.value(f).squeeze(-1)


def ppo_loss(logits, values, actions, advantages, returns, ent_coef):
    """PPO's loss without the ratio clipping: policy gradient, entropy bonus, 0.5 value MSE."""
    log_probs = F.log_softmax(logits, dim=-1)
    log_prob = log_probs.gather(1, actions.unsqueeze(1)).squeeze(1)
    entropy = -(log_probs.exp() * log_probs).sum(-1)
    return (-(log_prob * advantages).mean() - ent_coef * entropy.mean()
            + 0.5 * (values - returns).pow(2).mean())


def make_update(d, lr):
    """The row's networks, optimiser and inputs; returns update() (one training step)."""
    g = torch.Generator().manual_seed(1)
    batch = d["batch"]

    def uniform(*shape, low=-1.0, high=1.0):
        return low + (high - low) * torch.rand(*shape, generator=g)

    kind = d["kind"]
    if kind == "sac_critics":
        q = [mlp(d["critic"]), mlp(d["critic"])]
        opt = torch.optim.Adam([p for net in q for p in net.parameters()], lr=lr)
        x, target = uniform(batch, d["critic"]["inputs"]), uniform(batch, 1)

        def update():
            opt.zero_grad()
            loss = sum(0.5 * F.mse_loss(net(x), target) for net in q)
            loss.backward()
            opt.step()
        return update

    actions = torch.randint(0, d["actions"], (batch,), generator=g)
    advantages, returns = uniform(batch), uniform(batch)
    if kind == "ppo_mlp":
        actor, critic = mlp(d["actor"]), mlp(d["critic"])
        params = list(actor.parameters()) + list(critic.parameters())
        obs = uniform(batch, d["actor"]["inputs"])

        def forward():
            return actor(obs), critic(obs).squeeze(-1)
    elif kind == "ppo_cnn":
        net = CnnActorCritic(d)
        params = list(net.parameters())
        h, w, c = d["image"]
        obs = uniform(batch, c, h, w, low=0.0, high=1.0)  # PyTorch's own layout, NCHW

        def forward():
            return net(obs)
    else:
        raise SystemExit(f"learner.py: unknown row kind {kind!r} in rdsim's JSON")
    opt = torch.optim.Adam(params, lr=lr)

    def update():
        opt.zero_grad()
        logits, values = forward()
        ppo_loss(logits, values, actions, advantages, returns, d["ent_coef"]).backward()
        opt.step()
    return update


def torch_ms(update, min_seconds):
    """(wall-clock ms, process CPU ms) per update of one run, after 2 warm-up updates: >= min_seconds,
    >= 3 updates."""
    for _ in range(2):
        update()
    n, t0, cpu0 = 0, time.perf_counter(), time.process_time()
    while n < 3 or time.perf_counter() - t0 < min_seconds:
        update()
        n += 1
    return 1e3 * (time.perf_counter() - t0) / n, 1e3 * (time.process_time() - cpu0) / n


def rdsim_row(rdsim, row, min_seconds, threads, gemm):
    """One run of `rdsim bench-learner --row ROW`: ((wall ms, CPU ms) per update, the row's JSON, the whole JSON)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "row.json")
        command = [rdsim, "bench-learner", "--row", row, "--runs", "1", "--min-seconds", str(min_seconds),
                   "--threads", str(threads), "--json", path]
        if gemm:
            command += ["--gemm", gemm]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        with open(path) as f:
            result = json.load(f)
    (r,) = [r for r in result["rows"] if r["name"] == row]
    return (r["ms_per_update"], r["cpu_ms_per_update"]), r, result


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rdsim", default="build/rdsim", help="the rdsim binary (default: build/rdsim)")
    ap.add_argument("--row", action="append", default=[], help="row name or prefix (repeatable; default: all)")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2],
                    help="thread counts (default: 1 2): PyTorch's, and rdsim's oneDNN matrix products'")
    ap.add_argument("--gemm", choices=["eigen", "onednn"],
                    help="rdsim's matrix products (default: the build's; eigen runs on one thread at every count)")
    ap.add_argument("--reps", type=int, default=3, help="repeats per row and side; the median is reported")
    ap.add_argument("--min-seconds", type=float, default=0.5, help="length of one run (default: 0.5)")
    ap.add_argument("--json", help="also write the results as JSON to this file")
    args = ap.parse_args()

    names = subprocess.run([args.rdsim, "bench-learner", "--list"], check=True, capture_output=True,
                           text=True).stdout.split()
    rows = [n for n in names if not args.row or any(n.startswith(w) for w in args.row)]
    if not rows:
        raise SystemExit(f"learner.py: no row matches {args.row}; rows: {' '.join(names)}")

    torch.manual_seed(1)
    _, _, meta = rdsim_row(args.rdsim, rows[0], 0.0, 1, args.gemm)
    gemm = meta["gemm"]
    threads = {t: t if gemm == "onednn" else 1 for t in args.threads}  # rdsim's threads at each count
    print(f"PyTorch {torch.__version__}, oneDNN (mkldnn) {'on' if torch.backends.mkldnn.is_available() else 'off'}; "
          f"rdsim {args.rdsim}, matrix products on {gemm}; threads {args.threads}; "
          f"median of {args.reps} x >= {args.min_seconds} s, alternating row by row", file=sys.stderr)
    results = []
    for row in rows:
        rd, th = {t: [] for t in args.threads}, {t: [] for t in args.threads}  # (wall, cpu) per rep
        updates = {}
        for rep in range(args.reps):
            for t in args.threads:
                ms, desc, meta = rdsim_row(args.rdsim, row, args.min_seconds, threads[t], args.gemm)
                rd[t].append(ms)
                torch.set_num_threads(t)
                update = updates.get(t) or updates.setdefault(t, make_update(desc["network"], meta["learning_rate"]))
                th[t].append(torch_ms(update, args.min_seconds))
            print(f"  {row} rep {rep + 1}: " + ", ".join(
                f"{t} thr rdsim {rd[t][-1][0]:.3f} ms (cpu {rd[t][-1][1]:.3f}) PyTorch {th[t][-1][0]:.3f} ms "
                f"(cpu {th[t][-1][1]:.3f})" for t in args.threads), file=sys.stderr)

        def med(runs, i):
            return statistics.median(r[i] for r in runs)
        results.append({"row": row, "batch": desc["network"]["batch"], "threads": {
            str(t): {"rdsim_ms": med(rd[t], 0), "rdsim_cpu_ms": med(rd[t], 1), "rdsim_runs": rd[t],
                     "rdsim_threads": threads[t], "torch_ms": med(th[t], 0), "torch_cpu_ms": med(th[t], 1),
                     "torch_runs": th[t]} for t in args.threads}})

    head = f"{'row':<20} {'batch':>5}"
    for t in args.threads:
        head += f" {f'rdsim {t}thr ms':>15} {f'torch {t}thr ms':>15} {f'ratio {t}thr':>10}"
    print(f"\nms per update (zero_grad + forward + backward + Adam), median of {args.reps}; ratio = PyTorch ms / "
          f"rdsim ms (> 1: rdsim faster); rdsim's matrix products on {gemm}" +
          (", one thread at every count" if gemm != "onednn" else "") + "\n")
    if 1 in args.threads:
        head += f" {'cpu ratio 1thr':>15}"
    print(head)
    for r in results:
        line = f"{r['row']:<20} {r['batch']:>5}"
        for t in args.threads:
            x = r["threads"][str(t)]
            line += f" {x['rdsim_ms']:>15.3f} {x['torch_ms']:>15.3f} {x['torch_ms'] / x['rdsim_ms']:>10.2f}"
        if 1 in args.threads:
            x = r["threads"]["1"]
            line += f" {x['torch_cpu_ms'] / x['rdsim_cpu_ms']:>15.2f}"
        print(line)
    if 1 in args.threads:
        print("\ncpu ratio 1thr: the same on CPU time per update (process CPU time, one thread each): on a busy "
              "machine steadier than the wall-clock ratio")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"torch": torch.__version__, "rdsim_gemm": gemm, "threads": args.threads, "reps": args.reps,
                       "min_seconds": args.min_seconds, "rows": results}, f, indent=1)


if __name__ == "__main__":
    main()
