"""The examples in examples/, with small budgets: they must learn something."""
import json
import subprocess
from pathlib import Path

import pytest
from conftest import rdsim_binary


def test_sb3_ppo_learns_cartpole():
    import sb3_ppo

    result = sb3_ppo.main(["--env", "rdsim/CartPole-v1", "--timesteps", "16384", "--eval-episodes", "16"])
    # A random policy balances about 22 steps.
    assert result["mean_return"] > 60


def test_cleanrl_ppo_learns_cartpole():
    import cleanrl_ppo

    result = cleanrl_ppo.main(["--env", "rdsim/CartPole-v1", "--timesteps", "16384"])
    assert result["last_returns"] > 2 * result["first_returns"]


@pytest.mark.slow
def test_sb3_ppo_solves_jaka_button():
    import sb3_ppo

    result = sb3_ppo.main(["--timesteps", "300000"])
    assert result["success_rate"] >= 0.95


@pytest.mark.slow
def test_cleanrl_ppo_solves_jaka_button():
    import cleanrl_ppo

    result = cleanrl_ppo.main(["--timesteps", "300000"])
    assert result["last_success_rate"] >= 0.95


def test_sb3_her_trains_sac_with_her_on_a_goal_task(tmp_path):
    """examples/sb3_her.py: SB3's SAC + HerReplayBuffer on a Dict goal env, with a config's settings."""
    import sb3_her

    csv_path = tmp_path / "episodes.csv"
    result = sb3_her.main(["--env", "rdsim/JakaReachGoal-v0", "--config",
                           str(Path(__file__).resolve().parents[2] / "configs/jaka_reach_goal.json"),
                           "--timesteps", "1500", "--eval-episodes", "10", "--torch-threads", "1", "--csv", str(csv_path),
                           "--log-dir", str(tmp_path / "run")])
    rows = csv_path.read_text().splitlines()
    assert rows[0] == "episode,timesteps,return,length,success,wall_time"
    assert len(rows) > 10
    assert result["timesteps"] == 1500 and 0.0 <= result["eval_success"] <= 1.0
    # --log-dir: a run folder that `rdsim plot` draws (from its episodes.csv) against wall-clock.
    assert (tmp_path / "run" / "episodes.csv").read_text() == csv_path.read_text()
    run = json.loads((tmp_path / "run" / "config.json").read_text())
    assert (run["algorithm"], run["env"]["name"], run["seed"]) == ("sb3_sac", "reach_goal", 1)
    plot = subprocess.run([str(rdsim_binary()), "plot", str(tmp_path / "run"), "--out", str(tmp_path / "wall.png"),
                           "--x", "wall_time"], capture_output=True, text=True, check=False)
    assert plot.returncode == 0, plot.stderr
    assert "reach_goal, sb3_sac (1 run): success rate at wall_time" in plot.stdout
    assert (tmp_path / "wall.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
