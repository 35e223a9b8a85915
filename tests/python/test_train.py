"""rdsim.train: the C++ trainer in-process, the same run as `rdsim train`; Ctrl-C saves as in the CLI."""
import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time

import pytest

import rdsim
from conftest import ROOT, rdsim_binary

CONFIG = ROOT / "configs" / "jaka_button.json"
STEPS = 8192  # 4 updates of 8 envs x 256 steps
# Columns that depend on the clock, the only ones two runs of one config and seed may differ in.
CLOCK_COLUMNS = {"wall_time", "steps_per_s"}


def binary():
    path = rdsim_binary()
    if not path.exists():
        pytest.fail(f"{path} not found: build rdsim first (tools/setup.sh) or set RDSIM_BIN")
    return str(path)


def rows_without_clock(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    keep = [i for i, name in enumerate(rows[0]) if name not in CLOCK_COLUMNS]
    return [[row[i] for i in keep] for row in rows]


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    run = tmp_path_factory.mktemp("cli") / "run"
    subprocess.run([binary(), "train", "--config", str(CONFIG), "--seed", "3", "--timesteps", str(STEPS), "-q", "--log-dir",
                    str(run)], check=True, capture_output=True, timeout=600)
    return run


def test_same_files_as_the_binary(cli_run, tmp_path, capfd):
    result = rdsim.train(CONFIG, seed=3, timesteps=STEPS, log_dir=tmp_path / "run")
    run = tmp_path / "run"
    for name in ("episodes.csv", "progress.csv"):
        rows = rows_without_clock(run / name)
        assert len(rows) > 2, name
        assert rows == rows_without_clock(cli_run / name), name
    ours, theirs = (json.loads((r / "config.json").read_text()) for r in (run, cli_run))
    assert ours.pop("log_dir") == str(run) and theirs.pop("log_dir") == str(cli_run)
    assert ours == theirs
    # The result: the run folder, its files and the last row of progress.csv.
    assert result.run_dir == str(run) and os.fspath(result) == str(run)
    assert result.model_path == str(run / "model.bin") and os.path.isfile(result.model_path)
    assert os.path.isfile(result.checkpoint_path)
    assert (result.timesteps, result.total_timesteps, result.updates) == (STEPS, STEPS, 4)
    assert not result.interrupted and result.stop_signal == 0
    with open(run / "progress.csv", newline="") as f:
        last = list(csv.DictReader(f))[-1]
    assert int(last["episodes"]) == result.episodes > 0
    assert float(last["success_rate"]) == pytest.approx(result.success_rate)
    assert float(last["mean_return"]) == pytest.approx(result.mean_return)
    # The CLI's output: the summary on stdout, the progress line on stderr.
    out, err = capfd.readouterr()
    assert f"rdsim train: ppo on jaka_button, {STEPS} timesteps" in out
    assert f"{STEPS}/{STEPS} steps (100%)" in err
    assert rdsim.load_model(result.model_path).algorithm == "ppo"


def test_dict_config_and_the_gil(cli_run, tmp_path):
    config = json.loads(CONFIG.read_text())
    ticks = 0
    done = threading.Event()

    def tick():  # runs only while rdsim.train has released the GIL
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.002)

    thread = threading.Thread(target=tick)
    thread.start()
    started = time.monotonic()
    try:
        result = rdsim.train(config, seed=3, timesteps=STEPS, log_dir=str(tmp_path / "run"), quiet=True, threads=2)
    finally:
        done.set()
        thread.join()
    seconds = time.monotonic() - started
    assert rows_without_clock(tmp_path / "run" / "episodes.csv") == rows_without_clock(cli_run / "episodes.csv")
    assert result.timesteps == STEPS
    # A thread that had to wait for the GIL would not have ticked while the trainer worked.
    assert ticks >= min(50, seconds / 0.002 / 4), (ticks, seconds)


# Python installs its KeyboardInterrupt handler only where SIGINT is not ignored, and a shell starts
# background jobs with SIGINT ignored: installed here, as in an interactive session.
INTERRUPTED = """
import signal, sys, rdsim
signal.signal(signal.SIGINT, signal.default_int_handler)
try:
    rdsim.train(sys.argv[1], seed=5, timesteps=10**7, log_dir=sys.argv[2], quiet=True)
except KeyboardInterrupt as e:
    print("stopped", e.result.timesteps, e.result.interrupted, e.result.stop_signal, flush=True)
    raise
"""


def test_keyboard_interrupt_saves_and_the_cli_resumes(tmp_path):
    run = tmp_path / "run"
    child = subprocess.Popen([sys.executable, "-c", INTERRUPTED, str(CONFIG), str(run)], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 300
        progress = run / "progress.csv"
        while not (progress.exists() and len(progress.read_text().splitlines()) >= 2):  # one update done
            assert child.poll() is None, child.communicate()
            assert time.monotonic() < deadline, "no update within 300 s"
            time.sleep(0.05)
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=300)
    finally:
        child.kill()
    # Python's exit for an uncaught KeyboardInterrupt: killed by SIGINT, as the CLI exits 130.
    assert child.returncode == -signal.SIGINT, (out, err)
    words = out.split()
    assert words[0] == "stopped" and words[2:] == ["True", "2"], out
    stopped_at = int(words[1])
    assert 0 < stopped_at < 10**7 and stopped_at % 2048 == 0
    assert f"rdsim: interrupted at {stopped_at} of 10000000 steps; saved" in err
    assert f'continue with: rdsim.train(resume="{run}")' in err  # Python's words, not the command's
    rows = rows_without_clock(run / "progress.csv")
    assert int(rows[-1][0]) == stopped_at

    # The CLI continues the run from the checkpoint Ctrl-C saved.
    target = stopped_at + 2 * 2048
    resumed = subprocess.run([binary(), "train", "--resume", str(run), "--timesteps", str(target), "-q"], capture_output=True,
                             text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    rows = rows_without_clock(run / "progress.csv")
    steps = [int(r[0]) for r in rows[1:]]
    assert steps == list(range(2048, target + 1, 2048))
    assert rdsim.load_model(run / "model.bin").algorithm == "ppo"


def test_a_run_folder_is_not_replaced(cli_run, tmp_path):
    with pytest.raises(rdsim.Error) as caught:
        rdsim.train(CONFIG, timesteps=2048, log_dir=cli_run, quiet=True)
    assert "\n" not in str(caught.value)
    # resume= continues it in this process too; overwrite=True replaces it.
    copy = tmp_path / "copy"
    copy.mkdir()
    for f in cli_run.iterdir():
        if f.is_file():
            (copy / f.name).write_bytes(f.read_bytes())
    result = rdsim.train(resume=copy, timesteps=STEPS + 2048, quiet=True)
    assert (result.timesteps, result.updates) == (STEPS + 2048, 5)
    result = rdsim.train(CONFIG, timesteps=2048, log_dir=copy, overwrite=True, quiet=True)
    assert result.timesteps == 2048


def config_with(**keys):
    return {**json.loads(CONFIG.read_text()), **keys}


BAD_TRAIN_CALLS = {
    "no config": lambda d: rdsim.train(),
    "config not a path": lambda d: rdsim.train(42),
    "empty config path": lambda d: rdsim.train(""),
    "missing config file": lambda d: rdsim.train(d / "nope.json"),
    "config is a folder": lambda d: rdsim.train(d),
    "unknown argument": lambda d: rdsim.train(CONFIG, timestep=10),
    "negative seed": lambda d: rdsim.train(CONFIG, seed=-1, log_dir=d / "r"),
    "float seed": lambda d: rdsim.train(CONFIG, seed=1.5, log_dir=d / "r"),
    "bool seed": lambda d: rdsim.train(CONFIG, seed=True, log_dir=d / "r"),
    "seed beyond 64 bits": lambda d: rdsim.train(CONFIG, seed=2**64, log_dir=d / "r"),
    "zero timesteps": lambda d: rdsim.train(CONFIG, timesteps=0, log_dir=d / "r"),
    "string timesteps": lambda d: rdsim.train(CONFIG, timesteps="2048", log_dir=d / "r"),
    "zero threads": lambda d: rdsim.train(CONFIG, threads=0, timesteps=1, log_dir=d / "r"),
    "too many threads": lambda d: rdsim.train(CONFIG, threads=5000, timesteps=1, log_dir=d / "r"),
    "overwrite not a bool": lambda d: rdsim.train(CONFIG, overwrite="yes", timesteps=1, log_dir=d / "r"),
    "quiet not a bool": lambda d: rdsim.train(CONFIG, quiet=1, timesteps=1, log_dir=d / "r"),
    "zero memory": lambda d: rdsim.train(CONFIG, max_memory=0, timesteps=1, log_dir=d / "r"),
    "NaN memory": lambda d: rdsim.train(CONFIG, max_memory=float("nan"), timesteps=1, log_dir=d / "r"),
    "string memory": lambda d: rdsim.train(CONFIG, max_memory="1", timesteps=1, log_dir=d / "r"),
    "too little memory": lambda d: rdsim.train(CONFIG, max_memory=0.001, timesteps=1, log_dir=d / "r"),
    "log_dir not a path": lambda d: rdsim.train(CONFIG, log_dir=5, timesteps=1),
    "empty log_dir": lambda d: rdsim.train(CONFIG, log_dir="", timesteps=1),
    "resume not a path": lambda d: rdsim.train(resume=5),
    "resume a missing folder": lambda d: rdsim.train(resume=d / "nope"),
    "config and resume": lambda d: rdsim.train(CONFIG, resume=d),
    "dashboard not a string": lambda d: rdsim.train(CONFIG, dashboard=8097, timesteps=1, log_dir=d / "r"),
    "bad dashboard address": lambda d: rdsim.train(CONFIG, dashboard="nowhere", timesteps=1, log_dir=d / "r", quiet=True),
    "dict with a bad key": lambda d: rdsim.train(config_with(seeed=1), log_dir=d / "r"),
    "dict without env": lambda d: rdsim.train({"algorithm": "ppo"}, log_dir=d / "r"),
    "dict with NaN": lambda d: rdsim.train(config_with(seed=float("nan")), log_dir=d / "r"),
    "dict with an object": lambda d: rdsim.train(config_with(seed=object()), log_dir=d / "r"),
    "dict with an unknown algorithm": lambda d: rdsim.train(config_with(algorithm="nope"), log_dir=d / "r"),
}


@pytest.mark.parametrize("name", sorted(BAD_TRAIN_CALLS))
def test_bad_train_call_raises_rdsim_error(name, tmp_path):
    with pytest.raises(rdsim.Error) as caught:
        BAD_TRAIN_CALLS[name](tmp_path)
    message = str(caught.value)
    assert message and "\n" not in message
    assert not (tmp_path / "r" / "model.bin").exists()


def test_messages_name_the_argument():
    expected = r"^rdsim.train\(seed=...\): seed: expected an integer in \[0, 2\^64 - 1\], got -1$"
    with pytest.raises(rdsim.Error, match=expected):
        rdsim.train(CONFIG, seed=-1)
    with pytest.raises(rdsim.Error, match=r"^rdsim.train: unknown argument 'timestep': expected one of seed, timesteps"):
        rdsim.train(CONFIG, timestep=10)
