"""Issue #45, "First contact, second round": remote envs from the package (item 2), Stable-Baselines3
through rdsim (item 5), and docs whose commands keep the checkout clean and whose quoted errors are
the real ones (item 9)."""
import json
import pathlib
import re
import shlex
import socket
import subprocess
import sys

import gymnasium
import numpy as np
import pytest

import rdsim
from conftest import ROOT, rdsim_binary

sys.path.insert(0, str(ROOT / "tools"))

PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))


def page_text(name: str) -> str:
    """A page with its line breaks and indents as single spaces (quotes may be wrapped)."""
    return " ".join((ROOT / name).read_text().split())


# -- item 2: remote envs from Python ------------------------------------------------------------

def test_item2_remote_env_found_from_python(server):
    env = rdsim.make("rdsim/CartPole-v1", remote=server.address, timeout=10, max_steps=20)
    assert isinstance(env, rdsim.RemoteEnv) and env.config["max_steps"] == 20
    local = rdsim.make("rdsim/CartPole-v1", max_steps=20)
    assert env.observation_space == local.observation_space and env.action_space == local.action_space
    np.testing.assert_array_equal(env.reset(seed=2)[0], local.reset(seed=2)[0])
    # env.spec makes the same remote env again, as gymnasium.make does with the keywords.
    assert env.spec.kwargs["remote"] == server.address
    again = gymnasium.make(env.spec)
    assert isinstance(again.unwrapped, rdsim.RemoteEnv)
    again.close()
    env.close()
    # Server-side checks keep the config reader's messages.
    with pytest.raises(rdsim.Error, match="max_steps"):
        rdsim.make("rdsim/CartPole-v1", remote=server.address, max_steps=0)
    # The docs show the package's client first.
    assert 'remote="tcp://127.0.0.1:7777"' in page_text("docs/remote.md")
    assert "rdsim.RemoteEnv" in page_text("docs/remote.md") and "remote=" in page_text("docs/python.md")


@pytest.mark.parametrize("arguments, message", [
    ({"server_key": "keys/server.key"}, 'server_key: expected only with remote="tcp://host:port"'),
    ({"client_key": "alice.key_secret"}, 'client_key: expected only with remote="tcp://host:port"'),
    ({"timeout": 5}, 'timeout: expected only with remote="tcp://host:port"'),
    ({"remote": "tcp://127.0.0.1:1", "timeout": 0}, "timeout: expected a number of seconds > 0, got 0"),
    ({"remote": "tcp://127.0.0.1:1", "render_mode": "rgb_array"}, "render_mode: expected None for a remote env"),
    ({"remote": "nonsense"}, 'address: expected "tcp://host:port", got \'nonsense\''),
    ({"remote": 7}, 'remote: expected an address such as "tcp://host:port", got 7'),
])
def test_item2_remote_arguments_are_checked(arguments, message):
    with pytest.raises(rdsim.Error, match=re.escape(message)):
        rdsim.make("rdsim/JakaPush-v0", **arguments)


def test_item2_remote_goal_env_is_the_local_goal_env(server):
    remote = rdsim.make("push", remote=server.address, max_steps=15)
    local = rdsim.make("push", max_steps=15)
    assert isinstance(remote.observation_space, gymnasium.spaces.Dict)
    assert remote.observation_space == local.observation_space and remote.action_space == local.action_space
    assert remote.goal == local.goal
    a, _ = remote.reset(seed=7)
    b, _ = local.reset(seed=7)
    assert remote.observation_space.contains(a)
    for key in b:
        np.testing.assert_array_equal(a[key], b[key])
    remote.action_space.seed(7)
    achieved, desired, rewards = [], [], []
    for _ in range(15):
        action = remote.action_space.sample()
        (ra, rr, rt, rtr, rinfo), (la, lr, lt, ltr, linfo) = remote.step(action), local.step(action)
        for key in la:
            np.testing.assert_array_equal(ra[key], la[key])
        assert (rr, rt, rtr, rinfo["is_success"]) == (lr, lt, ltr, linfo["is_success"])
        assert remote.compute_reward(ra["achieved_goal"], ra["desired_goal"], rinfo) == rr
        achieved.append(ra["achieved_goal"])
        desired.append(ra["desired_goal"])
        rewards.append(rr)
        if rt or rtr:
            break
    batch = (np.stack(achieved), np.stack(desired))
    np.testing.assert_array_equal(remote.compute_reward(*batch, None), local.compute_reward(*batch, None))
    np.testing.assert_array_equal(remote.compute_reward(*batch, None), np.asarray(rewards, np.float32))
    remote.close()
    local.close()


def test_item2_non_goal_remote_env_has_no_compute_reward(server):
    env = rdsim.RemoteEnv(server.address, "rdsim/JakaButton-v0")
    assert env.goal is None and not hasattr(env, "compute_reward")
    assert isinstance(env.observation_space, gymnasium.spaces.Box)
    env.close()


# -- item 5: Stable-Baselines3 through rdsim ----------------------------------------------------

def sb3_ppo(monitor: bool):
    """PPO for 512 steps on CartPole through SB3VecEnv (8 envs x 64 steps), with or without VecMonitor."""
    torch = pytest.importorskip("torch")
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecMonitor

    from rdsim.sb3 import SB3VecEnv

    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        venv = SB3VecEnv(rdsim.make_vec("rdsim/CartPole-v1", 8, num_threads=1))
        venv = VecMonitor(venv) if monitor else venv
        venv.seed(1)
        model = PPO("MlpPolicy", venv, n_steps=64, batch_size=256, n_epochs=2, seed=1, device="cpu", verbose=0)
        model.learn(total_timesteps=512)
        venv.close()
        return model
    finally:
        torch.set_num_threads(threads)


def test_item5_sb3_ppo_logs_episodes_with_vecmonitor():
    model = sb3_ppo(monitor=True)
    assert len(model.ep_info_buffer) > 0
    episode = model.ep_info_buffer[-1]
    assert episode["l"] >= 1 and episode["r"] == episode["l"]  # CartPole: +1 per step
    assert len(model.ep_success_buffer) == len(model.ep_info_buffer)


def test_item5_without_vecmonitor_sb3_sees_no_episode_returns():
    # What the docs warn about: only the success flags reach SB3's buffers.
    model = sb3_ppo(monitor=False)
    assert len(model.ep_info_buffer) == 0 and len(model.ep_success_buffer) > 0


def test_item5_docs_have_an_sb3_section_with_its_snippet():
    text = (ROOT / "docs/python.md").read_text()
    section = text.split("## Stable-Baselines3", 1)[1].split("\n## ", 1)[0]
    snippet = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    for needed in ("VecMonitor(SB3VecEnv(", "torch.set_num_threads(1)", "batch_size=256", "ep_info_buffer"):
        assert needed in snippet
    assert "examples/sb3_ppo.py" in section and "examples/sb3_her.py" in section


# -- item 9: docs write no files into the checkout's root, and quote the real errors ------------

OUTPUT_SUFFIXES = (".gif", ".png", ".mp4", ".svg")


def code_blocks(page: pathlib.Path):
    """(line, language, text) of each sh/bash/python fenced block of a page (run in CI or not)."""
    found, lines, i = [], page.read_text().split("\n"), 0
    while i < len(lines):
        m = re.match(r"^\s*```(\w+)\s*$", lines[i])
        end = i + 1
        while m and end < len(lines) and not lines[end].strip().startswith("```"):
            end += 1
        if m and m.group(1) in ("sh", "bash", "python"):
            found.append((i + 1, m.group(1), "\n".join(lines[i + 1:end])))
        i = end + 1 if m else i + 1
    return found


def root_media_outputs(language: str, text: str) -> list[str]:
    """Pictures and videos a block names without a folder: written into the folder it runs in."""
    if language == "python":
        words = re.findall(r"""["']([^"'\s]+)["']""", text)
    else:
        words = []
        for line in text.replace("\\\n", " ").split("\n"):
            try:
                words += shlex.split(line, comments=True)
            except ValueError:  # a heredoc's Python line: its own quotes
                words += line.split("#", 1)[0].split()
        words = [part for word in words for part in word.split("=")]
    return [w for w in words if w.lower().endswith(OUTPUT_SUFFIXES) and "/" not in w]


def test_item9_no_docs_block_writes_media_into_the_repo_root():
    offenders = [f"{page.relative_to(ROOT)}:{line}: {name}"
                 for page in PAGES for line, language, text in code_blocks(page)
                 for name in root_media_outputs(language, text)]
    assert offenders == [], "write these under runs/ (git-ignored): " + ", ".join(offenders)


def test_item9_the_check_finds_root_outputs():
    assert root_media_outputs("sh", "build/rdsim replay m.bin --video replay.gif  # filmed") == ["replay.gif"]
    assert root_media_outputs("sh", "chromium --screenshot=dash.png http://x/") == ["dash.png"]
    assert root_media_outputs("python", 'plt.savefig("curves.png")') == ["curves.png"]
    assert root_media_outputs("sh", "build/rdsim plot runs/a --out runs/curves.png") == []


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def message(call) -> str:
    with pytest.raises(rdsim.Error) as e:
        call()
    return str(e.value)


def raw_replies(address: str, requests: list) -> list[str]:
    """The error texts of the server's replies to `requests`, sent in order on one connection."""
    import zmq

    sock = zmq.Context.instance().socket(zmq.DEALER)
    sock.setsockopt(zmq.LINGER, 0)
    sock.connect(address)
    errors = []
    for i, request in enumerate(requests, 1):
        sock.send(json.dumps(dict(request, id=i)).encode())
        assert sock.poll(10_000), f"{address}: no reply to {request}"
        errors.append(json.loads(sock.recv_multipart()[0]).get("error", ""))
    sock.close()
    return errors


def cli_remote_refused(tmp_path) -> str:
    """`rdsim train` on a remote env whose server is not there (3 s)."""
    address = f"tcp://127.0.0.1:{free_port()}"
    config = tmp_path / "remote.json"
    config.write_text(json.dumps({"algorithm": "ppo", "env": {"name": "cartpole", "remote": address},
                                  "total_timesteps": 256, "log_dir": str(tmp_path / "run")}))
    done = subprocess.run([str(rdsim_binary()), "train", "--config", str(config)], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 1
    return done.stderr.replace(address, "tcp://host:7777")


def test_item9_docs_quote_real_errors(server, tmp_path):
    hello = {"request": "hello", "protocol": 1}
    jaka = raw_replies(server.address, [dict(hello, env={"name": "jaka_button"}), {"request": "step", "action": 1},
                                        {"request": "reset"}, {"request": "step", "action": 7},
                                        dict(hello, env={"name": "jaka_button"})])
    cartpole = raw_replies(server.address, [{"request": "reset"}, dict(hello, env={"name": "cartpole"}),
                                            {"request": "reset"}, {"request": "position", "position": [0, 0, 0]}])
    quotes = [  # (page, text quoted there, what rdsim says today)
        ("docs/python.md", 'rdsim.make("rdsim/JakaButton-v0"): max_steps: expected an integer in [1, 1e8], got 0',
         message(lambda: rdsim.make("rdsim/JakaButton-v0", max_steps=0))),
        ("docs/python.md", "rdsim.train(seed=...): seed: expected an integer in [0, 2^64 - 1], got -1",
         message(lambda: rdsim.train(str(ROOT / "configs/jaka_button.json"), seed=-1))),
        ("docs/protocol.md", "hello: env.max_steps: expected an integer in [1, 1e8], got 0",
         raw_replies(server.address, [dict(hello, env={"name": "jaka_button", "max_steps": 0})])[0]),
        ("docs/protocol.md", "the episode has not started: send reset first", jaka[1]),
        ("docs/protocol.md", '"step: action: expected an integer in 0..5 (Discrete(6))"', json.dumps(jaka[3])),
        ("docs/protocol.md", "send close first", jaka[4]),
        ("docs/protocol.md", "no session on this connection: send hello first", cartpole[0]),
        ("docs/protocol.md", "cartpole has no robot to control", cartpole[3]),
        ("docs/remote.md", "tcp://host:7777: connection refused after 3 s: is `rdsim serve` running there?",
         cli_remote_refused(tmp_path)),
    ]
    for page, quoted, real in quotes:
        assert quoted in page_text(page), f"{page} no longer quotes: {quoted}"
        assert quoted in real, f"{page} quotes {quoted!r}; rdsim says {real!r}"


def test_item6_python_errors_name_python_arguments(tmp_path):
    """A Python caller is told about resume=, overwrite=True and log_dir=, not --resume and friends."""
    config = ROOT / "configs/cartpole_ppo.json"
    run = tmp_path / "run"
    rdsim.train(config, timesteps=256, log_dir=run, quiet=True)
    with pytest.raises(rdsim.Error) as caught:
        rdsim.train(config, timesteps=256, log_dir=run, quiet=True)
    message = str(caught.value)
    assert f'continue it with resume="{run}"' in message
    assert "overwrite=True" in message and "log_dir=" in message
    assert "--" not in message
    with pytest.raises(rdsim.Error, match="overwrite=True cannot be combined with resume="):
        rdsim.train(resume=run, overwrite=True)
    with pytest.raises(rdsim.Error, match=r"raise the limit with max_memory=GB"):
        rdsim.train(config, max_memory=0.001, timesteps=1, log_dir=tmp_path / "small")


def test_item6_dict_configs_train_into_their_own_folders(tmp_path, monkeypatch):
    """Two runs of dict configs without log_dir do not collide: runs/ENV_ALGORITHM_1, _2, ..."""
    monkeypatch.chdir(tmp_path)
    config = {"algorithm": "ppo", "env": {"name": "cartpole"}, "total_timesteps": 256, "num_envs": 1,
              "ppo": {"n_steps": 128, "batch_size": 64}}
    first = rdsim.train(config, quiet=True)
    second = rdsim.train(config, quiet=True)
    assert pathlib.Path(first.run_dir) == pathlib.Path("runs/cartpole_ppo_1")
    assert pathlib.Path(second.run_dir) == pathlib.Path("runs/cartpole_ppo_2")
    assert (tmp_path / "runs/cartpole_ppo_2/model.bin").exists()
