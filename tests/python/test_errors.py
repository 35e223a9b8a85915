"""Bad calls raise rdsim.Error (an Exception) with a one-line message: never a crash or a hang."""
import numpy as np
import pytest

import rdsim

J = "rdsim/JakaButton-v0"


def closed_env():
    env = rdsim.make("rdsim/CartPole-v1")
    env.close()
    return env


def closed_vec():
    venv = rdsim.make_vec("rdsim/CartPole-v1", 2)
    venv.close()
    return venv


def started_vec():
    venv = rdsim.make_vec("rdsim/CartPole-v1", 2)
    venv.reset(seed=0)
    venv.step_async(np.zeros(2, dtype=np.int64))
    return venv


disc = rdsim.make(J)
disc.reset(seed=0)
box = rdsim.make(J, is_discrete=False)
box.reset(seed=0)
vdisc = rdsim.make_vec(J, 3, num_threads=1)
vbox = rdsim.make_vec(J, 3, num_threads=1, is_discrete=False)

BAD_CALLS = {
    # make: ids and options, checked by the config reader with the CLI's messages
    "unknown id": lambda: rdsim.make("rdsim/Nope-v0"),
    "unknown option": lambda: rdsim.make(J, max_stepz=3),
    "option without effect": lambda: rdsim.make(J, image_width=32),
    "option for another env": lambda: rdsim.make("rdsim/CartPole-v1", action_step=0.01),
    "wrong option type": lambda: rdsim.make(J, max_steps="many"),
    "option out of range": lambda: rdsim.make(J, max_steps=0),
    "negative distance": lambda: rdsim.make(J, max_distance=-1.0),
    "bad choice": lambda: rdsim.make(J, observation="depth"),
    "no camera": lambda: rdsim.make("rdsim/CartPole-v1", observation="raw_pixels"),
    "multi_view without pixels": lambda: rdsim.make(J, multi_view=True),
    "list option": lambda: rdsim.make(J, max_steps=[1, 2]),
    "None option": lambda: rdsim.make(J, max_steps=None),
    "huge integer": lambda: rdsim.make(J, max_steps=2**80),
    "name option": lambda: rdsim.make(J, name="cartpole"),
    "render_mode human": lambda: rdsim.make(J, render_mode="human"),
    "bool for int": lambda: rdsim.make(J, max_steps=True),
    "string for bool": lambda: rdsim.make(J, random_target="yes"),
    "image too small": lambda: rdsim.make(J, observation="raw_pixels", image_width=2),
    # reset
    "negative seed": lambda: disc.reset(seed=-1),
    "float seed": lambda: disc.reset(seed=1.5),
    "string seed": lambda: disc.reset(seed="1"),
    "seed beyond 64 bits": lambda: disc.reset(seed=2**64),
    "reset options": lambda: disc.reset(options={"x": 1}),
    "reset options not a dict": lambda: disc.reset(options=[1]),
    # discrete actions
    "discrete too large": lambda: disc.step(6),
    "discrete negative": lambda: disc.step(-1),
    "discrete float": lambda: disc.step(1.5),
    "discrete numpy float": lambda: disc.step(np.float32(1)),
    "discrete string": lambda: disc.step("1"),
    "discrete None": lambda: disc.step(None),
    "discrete bool": lambda: disc.step(True),
    "discrete array": lambda: disc.step(np.array([1, 2])),
    "discrete list": lambda: disc.step([1]),
    "discrete huge": lambda: disc.step(2**70),
    # box actions
    "box wrong length": lambda: box.step(np.zeros(2, np.float32)),
    "box NaN": lambda: box.step(np.array([0.0, np.nan, 0.0], np.float32)),
    "box inf": lambda: box.step(np.array([np.inf, 0.0, 0.0], np.float32)),
    "box integer array": lambda: box.step(np.zeros(3, np.int64)),
    "box 2-D": lambda: box.step(np.zeros((1, 3), np.float32)),
    "box scalar": lambda: box.step(0.5),
    "box string": lambda: box.step("0 0 0"),
    "box None": lambda: box.step(None),
    "box complex": lambda: box.step(np.zeros(3, np.complex64)),
    # after close
    "step after close": lambda: closed_env().step(0),
    "reset after close": lambda: closed_env().reset(),
    "render after close": lambda: closed_env().render(),
    # make_vec
    "zero envs": lambda: rdsim.make_vec(J, 0),
    "too many envs": lambda: rdsim.make_vec(J, 5000),
    "string num_envs": lambda: rdsim.make_vec(J, "2"),
    "zero threads": lambda: rdsim.make_vec(J, 2, num_threads=0),
    "bad env_workers": lambda: rdsim.make_vec(J, 2, env_workers="fibers"),
    "vec unknown option": lambda: rdsim.make_vec(J, 2, colour="red"),
    "vec negative seed": lambda: rdsim.make_vec(J, 2, seed=-5),
    "vec actions wrong length": lambda: vdisc.step(np.zeros(2, np.int64)),
    "vec actions float for discrete": lambda: vdisc.step(np.zeros(3, np.float32)),
    "vec action out of range": lambda: vdisc.step(np.array([0, 1, 6])),
    "vec action negative": lambda: vdisc.step(np.array([0, -1, 0])),
    "vec actions 2-D for discrete": lambda: vdisc.step(np.zeros((3, 1), np.int64)),
    "vec actions list of str": lambda: vdisc.step(["a", "b", "c"]),
    "vec box wrong shape": lambda: vbox.step(np.zeros((3, 2), np.float32)),
    "vec box NaN": lambda: vbox.step(np.full((3, 3), np.nan, np.float32)),
    "vec box int": lambda: vbox.step(np.zeros((3, 3), np.int32)),
    "vec reset list of seeds": lambda: vdisc.reset(seed=[1, 2, 3]),
    "vec reset options": lambda: vdisc.reset(options={"a": 1}),
    "step_wait without step_async": lambda: vdisc.step_wait(),
    "step while a step is running": lambda: started_vec().step(np.zeros(2, np.int64)),
    "reset while a step is running": lambda: started_vec().reset(seed=1),
    "vec step after close": lambda: closed_vec().step(np.zeros(2, np.int64)),
    "vec reset after close": lambda: closed_vec().reset(seed=0),
    "vec step_async after close": lambda: closed_vec().step_async(np.zeros(2, np.int64)),
    # models
    "missing model": lambda: rdsim.load_model("/nonexistent/model.bin"),
    "not a model": lambda: rdsim.load_model(__file__),
    "model is a folder": lambda: rdsim.load_model("/"),
}


def test_at_least_fifty_bad_calls():
    assert len(BAD_CALLS) >= 50


@pytest.mark.parametrize("name", sorted(BAD_CALLS))
def test_bad_call_raises_rdsim_error(name):
    with pytest.raises(rdsim.Error) as caught:
        BAD_CALLS[name]()
    message = str(caught.value)
    assert message and "\n" not in message
    assert issubclass(rdsim.Error, Exception)


def test_option_messages_match_the_config_reader():
    with pytest.raises(rdsim.Error, match=r'^rdsim.make\("rdsim/JakaButton-v0"\): max_steps: expected an integer in \[1, '):
        rdsim.make(J, max_steps=0)
    with pytest.raises(rdsim.Error, match="image_width: has no effect without"):
        rdsim.make(J, image_width=32)


def test_envs_still_work_after_bad_calls():
    obs, *_ = disc.step(1)
    assert obs.shape == disc.observation_space.shape
    vdisc.reset(seed=1)
    vdisc.step(np.array([0, 1, 2]))


def test_item1_make_takes_its_own_resolved_config():
    """First contact, item 1: rdsim.make accepts its own resolved config back."""
    # env.config (and a model's config["env"]) holds render_mode "none": make accepts it back.
    config = {key: value for key, value in rdsim.make(J).config.items() if key != "name"}
    again = rdsim.make(J, **config)
    assert again.render_mode is None and again.config == rdsim.make(J).config
    again.close()
