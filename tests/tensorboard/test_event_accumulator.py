#!/usr/bin/env python3
"""TensorBoard's own reader (EventAccumulator, from the `tensorboard` package) over event files rdsim
writes: every scalar of progress.csv at every update, with its step (the row's timesteps).

  test_event_accumulator.py --writer PATH   a progress.csv written through rdsim's EventWriter
                                            (tests/tensorboard/write_events), then a resumed run
                                            that rewinds and replaces the rows after its checkpoint
  test_event_accumulator.py --run DIR...    real run folders of `rdsim train`: DIR/progress.csv
                                            against DIR's event files
  test_event_accumulator.py --rdsim PATH    trains a PPO, a DQN and a SAC run (tiny budgets, a
                                            scratch folder) and a resumed PPO run, then reads each
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile
import time

from tensorboard.backend.event_processing import event_accumulator


def read_scalars(folder):
    """{tag: [(step, value), ...]} as TensorBoard reads the folder (every event file, in name order)."""
    acc = event_accumulator.EventAccumulator(folder, size_guidance={event_accumulator.SCALARS: 0})
    acc.Reload()
    return {tag: [(e.step, e.value) for e in acc.Scalars(tag)] for tag in acc.Tags()["scalars"]}


def expected_scalars(progress_csv):
    """{column: [(timesteps, value), ...]} for every non-empty cell of progress.csv."""
    out = {}
    with open(progress_csv, newline="") as f:
        for row in csv.DictReader(f):
            step = int(row["timesteps"])
            for column, cell in row.items():
                if cell != "":
                    out.setdefault(column, []).append((step, float(cell)))
    return out


def check_same(expected, seen, where):
    assert set(seen) == set(expected), f"{where}: tags {sorted(seen)}, expected {sorted(expected)}"
    for tag, points in expected.items():
        got = seen[tag]
        assert [s for s, _ in got] == [s for s, _ in points], f"{where}: {tag}: steps {got} != {points}"
        for (step, want), (_, have) in zip(points, got):
            # simple_value is a float: 24 bits of mantissa.
            assert math.isclose(have, want, rel_tol=1e-6, abs_tol=1e-30), f"{where}: {tag} at {step}: {have} != {want}"
    print(f"{where}: {len(expected)} scalars, {sum(len(p) for p in expected.values())} points read back by TensorBoard")


def write_csv(path, columns, rows):
    with open(path, "w", newline="") as f:
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")


def writer_test(writer):
    columns = ["timesteps", "updates", "episodes", "mean_return", "success_rate", "policy_loss", "steps_per_s", "wall_time"]

    def row(update):
        t = 2048 * update
        # No episode ended in the first update: empty cells (NaN), as CsvWriter writes them.
        mean = "" if update == 1 else f"{-50 + 3.25 * update:.9g}"
        success = "" if update == 1 else f"{min(1.0, update / 10):.9g}"
        return [str(t), str(update), str(3 * update), mean, success, f"{0.5 / update:.9g}", "4100.5", f"{0.75 * update:.9g}"]

    with tempfile.TemporaryDirectory(prefix="rdsim_tb_") as tmp:
        run = os.path.join(tmp, "runs", "ppo")  # not there yet: the writer makes it
        first = os.path.join(tmp, "first.csv")
        write_csv(first, columns, [row(u) for u in range(1, 11)])
        subprocess.run([writer, first, run], check=True, stdout=subprocess.DEVNULL)
        check_same(expected_scalars(first), read_scalars(run), "fresh run")

        # A resumed run: its checkpoint was at update 6 (timesteps 12288), so progress.csv keeps
        # rows 1..6 and the resumed process writes 7.. again, with other values. TensorBoard must
        # show the resumed values, not the first process's rows after the checkpoint.
        resumed_rows = [row(u) for u in range(7, 13)]
        for r in resumed_rows:
            r[5] = f"{1.5 / int(r[1]):.9g}"
        resumed = os.path.join(tmp, "resumed.csv")
        write_csv(resumed, columns, resumed_rows)
        whole = os.path.join(tmp, "whole.csv")
        write_csv(whole, columns, [row(u) for u in range(1, 7)] + resumed_rows)
        # The new file's name must sort after the first one's (a later second).
        time.sleep(1.1)
        subprocess.run([writer, resumed, run, "--session-start", str(2048 * 7)], check=True, stdout=subprocess.DEVNULL)
        assert len([n for n in os.listdir(run) if "tfevents" in n]) == 2
        check_same(expected_scalars(whole), read_scalars(run), "resumed run")


def training_test(rdsim, source):
    """`rdsim train` writes the event files itself: every progress.csv scalar of PPO, DQN and SAC."""
    runs = [("ppo", "cartpole_ppo.json", 2048), ("dqn", "cartpole_dqn.json", 1000), ("sac", "pendulum_sac.json", 1200)]
    with tempfile.TemporaryDirectory(prefix="rdsim_tb_train_") as tmp:
        folders = []
        for name, config, steps in runs:
            folder = os.path.join(tmp, name)
            subprocess.run([rdsim, "train", "--config", os.path.join(source, "configs", config), "--timesteps", str(steps),
                            "--log-dir", folder, "--quiet"], check=True)
            folders.append(folder)
        # Resumed with a larger budget: the second process's file continues the first's.
        subprocess.run([rdsim, "train", "--resume", folders[0], "--timesteps", "4096", "--quiet"], check=True)
        for folder in folders:
            files = [n for n in os.listdir(folder) if "tfevents" in n]
            assert files, f"{folder}: rdsim train wrote no TensorBoard event file"
            check_same(expected_scalars(os.path.join(folder, "progress.csv")), read_scalars(folder), folder)
        assert len([n for n in os.listdir(folders[0]) if "tfevents" in n]) == 2, "the resumed run: one file per process"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--writer", help="the write_events test program")
    parser.add_argument("--run", nargs="*", default=[], help="run folders of rdsim train")
    parser.add_argument("--rdsim", help="the rdsim binary: train PPO, DQN and SAC runs and read them")
    args = parser.parse_args()
    if not args.writer and not args.run and not args.rdsim:
        parser.error("give --writer, --run or --rdsim")
    if args.writer:
        writer_test(args.writer)
    if args.rdsim:
        training_test(args.rdsim, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    for folder in args.run:
        check_same(expected_scalars(os.path.join(folder, "progress.csv")), read_scalars(folder), folder)
    return 0


if __name__ == "__main__":
    sys.exit(main())
