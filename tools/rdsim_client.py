#!/usr/bin/python3
"""A Python client for `rdsim serve` (the protocol is docs/protocol.md).

Needs only Debian's python3-zmq and python3-numpy (run it with /usr/bin/python3):

    import numpy as np
    from rdsim_client import RemoteEnv
    with RemoteEnv("tcp://127.0.0.1:7777", {"name": "jaka_button"},
                   server_key="keys/server.key", client_key="keys/alice/alice.key_secret") as env:
        obs, info = env.reset(seed=1)
        obs, reward, terminated, truncated, info = env.step(3)   # Gymnasium-style
        # position() is ONE env step towards the point, not a move that waits until the arm is there:
        # the joint drives are speed-limited, so repeat it (10 cm: about 15 calls on jaka_button) and stop
        # when the effector is close enough (or the episode ends: each call counts towards max_steps).
        goal = np.array([0.5, 0.0, 0.1])
        for _ in range(100):
            obs, reward, terminated, truncated, info = env.position(goal)
            if np.linalg.norm(info["effector_position"] - goal) < 0.005 or terminated or truncated:
                break
        images = env.cameras(224, 224)             # {"wrist": uint8 (224, 224, 3), "scene": ...}

Run as a program it drives an env with random actions and prints what happens:

    /usr/bin/python3 tools/rdsim_client.py tcp://127.0.0.1:7777 --env jaka_button \\
        --server-key keys/server.key --client-key keys/alice/alice.key_secret
"""

import argparse
import json
import os
import sys

import numpy as np
import zmq

PROTOCOL_VERSION = 1
_DTYPES = {"float32": np.dtype("<f4"), "uint8": np.dtype("u1")}


class RdsimError(Exception):
    """An error reply of the server, a refused key, or no reply in time."""


def _key_field(path, label):
    if not os.path.exists(path):
        folder, name = os.path.split(path)
        raise RdsimError(f"{path}: no such file; make it with: rdsim keygen {os.path.splitext(name)[0]} --dir {folder or '.'}")
    with open(path, encoding="ascii") as f:
        for line in f:
            if line.startswith(label + " "):
                return line.split(None, 1)[1].strip().encode("ascii")
    raise RdsimError(f"{path}: no '{label} <key>' line (write key files with `rdsim keygen NAME`)")


def load_public_key(path):
    """The Z85 public key in a NAME.key file written by `rdsim keygen`."""
    return _key_field(path, "public")


def load_secret_key(path):
    """(public, secret) Z85 keys of a NAME.key_secret file written by `rdsim keygen`."""
    return _key_field(path, "public"), _key_field(path, "secret")


class Space:
    """The spec of a space: discrete (n) or a Box (shape, low, high, dtype)."""

    def __init__(self, discrete=False, n=0, shape=(), low=None, high=None, dtype=np.float32):
        self.discrete, self.n, self.shape = discrete, n, tuple(shape)
        self.low, self.high, self.dtype = low, high, dtype

    def sample(self, rng=np.random):
        if self.discrete:
            return int(rng.randint(self.n))
        return rng.uniform(self.low, self.high).astype(np.float32)

    def __repr__(self):
        return f"Discrete({self.n})" if self.discrete else f"Box({self.shape}, {np.dtype(self.dtype).name})"


class RemoteEnv:
    """One session on an `rdsim serve`: an env made from `env` (the "env" object of a training
    config, e.g. {"name": "jaka_button", "random_target": True}), driven Gymnasium-style.

    Without keys the link is plain text (servers started with --insecure, on loopback only).
    Every call raises RdsimError with the server's message when the server refuses it.
    """

    def __init__(self, address, env, server_key=None, client_key=None, timeout=60.0, context=None):
        self.address, self.timeout = address, float(timeout)
        self._context = context or zmq.Context.instance()
        self._socket = self._context.socket(zmq.DEALER)
        self._socket.setsockopt(zmq.LINGER, 200)
        if (server_key is None) != (client_key is None):
            raise RdsimError("give both server_key (the server's public key file) and client_key "
                             "(this client's secret key file), or neither")
        if server_key is not None:
            self._socket.curve_serverkey = load_public_key(server_key)
            self._socket.curve_publickey, self._socket.curve_secretkey = load_secret_key(client_key)
        self._socket.connect(address)
        self._next_id = 1
        header, arrays = self.request({"request": "hello", "protocol": PROTOCOL_VERSION, "env": env})
        self.server = header.get("server")
        self.env_config = header["env"]     # every key of the env with the value the server uses
        self.spec = header["spec"]
        self.robot = header["robot"]        # None for envs without a robot (cartpole)
        obs = self.spec["observation"]
        self.observation_space = Space(shape=obs["shape"], dtype=_DTYPES[obs["dtype"]],
                                       low=arrays.get("observation_low"), high=arrays.get("observation_high"))
        act = self.spec["action"]
        if act["discrete"]:
            self.action_space = Space(discrete=True, n=act["n"])
        else:
            self.action_space = Space(shape=(act["dim"],), low=arrays["action_low"], high=arrays["action_high"])
        if self.robot is not None:
            self.joint_names = [j["name"] for j in self.robot["joints"]]
            self.joint_lower, self.joint_upper = arrays["joint_lower"], arrays["joint_upper"]
            self.camera_names = [c["name"] for c in self.robot["cameras"]]
            self.workspace = (arrays["workspace_min"], arrays["workspace_max"])

    # -- the protocol ---------------------------------------------------------------------
    def request(self, header):
        """Sends one request (its "id" is set here) and returns (reply header, {name: array})."""
        header = dict(header, id=self._next_id)
        self._next_id += 1
        self._socket.send(json.dumps(header).encode("utf-8"))
        deadline_ms = int(self.timeout * 1000)
        while True:
            if not self._socket.poll(deadline_ms):
                raise RdsimError(f"{self.address}: no reply within {self.timeout:g} s "
                                 "(is `rdsim serve` running there, and are the keys right?)")
            frames = self._socket.recv_multipart()
            reply = json.loads(frames[0])
            if reply.get("id") is None and "error" in reply:
                raise RdsimError(f"{self.address}: {reply['error']}")
            if reply.get("id") == header["id"]:
                break  # else: the late reply of a request that timed out
        if "error" in reply:
            raise RdsimError(f"{self.address}: {reply['error']}")
        arrays = {}
        for spec, frame in zip(reply.pop("arrays", []), frames[1:]):
            arrays[spec["name"]] = np.frombuffer(frame, dtype=_DTYPES[spec["dtype"]]).reshape(spec["shape"])
        return reply, arrays

    @staticmethod
    def _info(header, arrays):
        info = dict(header["info"])
        info.update({k: v for k, v in arrays.items() if k != "observation"})
        return info

    def _step_reply(self, header):
        reply, arrays = self.request(header)
        return (arrays["observation"], reply["reward"], reply["terminated"], reply["truncated"],
                self._info(reply, arrays))

    # -- Gymnasium-style ------------------------------------------------------------------
    def reset(self, seed=None):
        """(observation, info). A seed makes the episode (and the resets after it) reproducible."""
        header = {"request": "reset"}
        if seed is not None:
            header["seed"] = int(seed)
        _, arrays = self.request(header)
        return arrays["observation"], {}

    def step(self, action):
        """(observation, reward, terminated, truncated, info) for the env's own action: an int for
        a Discrete space, a sequence of numbers for a Box."""
        if self.action_space.discrete:
            action = int(action)
        else:
            action = [float(a) for a in np.asarray(action, dtype=np.float64).ravel()]
        return self._step_reply({"request": "step", "action": action})

    # -- robot control (robot envs) -------------------------------------------------------
    def position(self, xyz):
        """One env step that drives the effector towards the absolute point xyz (world frame, m),
        returned as step() does; info also holds joint_positions and effector_position.

        The joint targets are set by IK for xyz (clipped into the workspace) and the world advances by
        one control period, as env.step does: the speed-limited joint drives cover only part of the
        way, so the effector has not arrived after one call. Call it again with the same point until
        info["effector_position"] is close enough (jaka_button: about 15 calls for 10 cm); every call
        is a step of the episode (reward, success, the step limit), as in RobotDrlSim's `position`."""
        return self._step_reply({"request": "position", "position": [float(v) for v in xyz]})

    def joints(self, targets):
        """Absolute targets for every joint (self.joint_names order, clamped to the limits): one env step."""
        return self._step_reply({"request": "joints", "joints": [float(v) for v in targets]})

    def cameras(self, width=224, height=224, names=None):
        """{camera name: uint8 array (height, width, 3)} of the robot's cameras (InMoov: left_eye,
        right_eye; Jaka: wrist; every robot env: scene, the main view), or only those in `names`."""
        header = {"request": "cameras", "width": int(width), "height": int(height)}
        if names is not None:
            header["cameras"] = list(names)
        return self.request(header)[1]

    def state(self):
        """{"steps": n, joint_positions, joint_velocities, joint_targets, effector_position,
        effector_orientation (x, y, z, w), target}."""
        header, arrays = self.request({"request": "state"})
        return dict(arrays, steps=header["steps"])

    def close(self):
        if self._socket is None:
            return
        try:
            self.request({"request": "close"})
        except RdsimError:
            pass
        self._socket.close()
        self._socket = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class ServerProcess:
    """`rdsim serve` as a child process on a free loopback port, stopped (SIGTERM) on exit:

        with ServerProcess("build/rdsim", keys="keys") as server:
            env = RemoteEnv(server.address, {"name": "cartpole"}, ...)

    Without keys it runs with --insecure (plain text, loopback only). Its stderr (the session log)
    goes to `log` (a path) when given. stop() returns the exit status.
    """

    def __init__(self, rdsim, keys=None, args=(), log=None, startup_timeout=30.0):
        import select
        import subprocess
        cmd = [rdsim, "serve", "--bind", "tcp://127.0.0.1:*"]
        cmd += ["--keys", keys] if keys else ["--insecure"]
        cmd += list(args)
        self._log = open(log, "wb") if log else subprocess.DEVNULL
        self.process = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=self._log)
        ready, _, _ = select.select([self.process.stdout], [], [], startup_timeout)
        line = self.process.stdout.readline().decode() if ready else ""
        if "listening on " not in line:
            self.stop()
            raise RdsimError(f"{' '.join(cmd)} did not start: {line.strip() or 'no output'}")
        self.address = line.split("listening on ", 1)[1].split()[0]
        self.pid = self.process.pid

    def alive(self):
        return self.process.poll() is None

    def stop(self, timeout=10.0):
        import signal
        import subprocess
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
                raise RdsimError(f"rdsim serve (pid {self.pid}) did not stop within {timeout:g} s of SIGTERM")
        if hasattr(self._log, "close"):
            self._log.close()
        self.process.stdout.close()
        return self.process.returncode

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()


def main(argv=None):
    p = argparse.ArgumentParser(description="Drive an env on an `rdsim serve` with random actions.")
    p.add_argument("address", help="tcp://HOST:PORT of the server")
    p.add_argument("--env", default="jaka_button", help="env name (or a JSON env object)")
    p.add_argument("--server-key", help="the server's public key file (NAME.key)")
    p.add_argument("--client-key", help="this client's secret key file (NAME.key_secret)")
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args(argv)
    env_config = json.loads(a.env) if a.env.startswith("{") else {"name": a.env}
    rng = np.random.RandomState(a.seed)
    with RemoteEnv(a.address, env_config, a.server_key, a.client_key) as env:
        print(f"{env.server}: {env.spec['env_name']}, observation {env.observation_space}, "
              f"actions {env.action_space}")
        obs, _ = env.reset(seed=a.seed)
        episode_return, episodes = 0.0, 0
        for _ in range(a.steps):
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample(rng))
            episode_return += reward
            if terminated or truncated:
                episodes += 1
                print(f"episode {episodes}: return {episode_return:.2f}, success {info['success']}")
                episode_return = 0.0
                obs, _ = env.reset()
        if env.robot is not None:
            for name, image in env.cameras(64, 64).items():
                print(f"camera {name}: {image.shape}, mean {image.mean():.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
