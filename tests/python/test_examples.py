"""The examples in examples/, with small budgets: they must learn something."""
import pytest


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
