#!/usr/bin/python3
"""tools/rdsim_client.py against a real `rdsim serve` (CurveZMQ, keys from `rdsim keygen`) on a
free loopback port; the server is stopped with SIGTERM at the end and must exit cleanly.

Run by ctest: /usr/bin/python3 tests/remote/test_python_client.py --rdsim build/rdsim
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import zmq

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from rdsim_client import RdsimError, RemoteEnv, ServerProcess, load_public_key, load_secret_key  # noqa: E402

RDSIM = None


class PythonClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="rdsim_pyclient_")
        keys = os.path.join(cls.dir, "keys")
        for name, where in (("server", keys), ("alice", cls.dir), ("mallory", cls.dir)):
            subprocess.run([RDSIM, "keygen", name, "--dir", where], check=True, stdout=subprocess.DEVNULL)
        os.makedirs(os.path.join(keys, "clients"))
        shutil.copy(os.path.join(cls.dir, "alice.key"), os.path.join(keys, "clients"))
        cls.server_key = os.path.join(keys, "server.key")
        cls.alice = os.path.join(cls.dir, "alice.key_secret")
        cls.log = os.path.join(cls.dir, "serve.log")
        cls.server = ServerProcess(RDSIM, keys=keys, log=cls.log)

    @classmethod
    def tearDownClass(cls):
        status = cls.server.stop()
        with open(cls.log) as f:
            log = f.read()
        shutil.rmtree(cls.dir, ignore_errors=True)
        assert status == 0, f"rdsim serve exited with {status}:\n{log}"
        assert "stopped after" in log, log
        # Clients are logged by their key file's name in DIR/clients/, not by the raw Z85 key.
        assert "opened: jaka_button for client alice.key from 127.0.0.1" in log, log

    def env(self, config, key=None, timeout=30.0):
        return RemoteEnv(self.server.address, config, server_key=self.server_key, client_key=key or self.alice,
                         timeout=timeout)

    def test_gymnasium_style_reset_and_step(self):
        with self.env({"name": "jaka_button", "random_target": True}) as env:
            self.assertEqual(env.spec["env_name"], "jaka_button")
            self.assertTrue(env.action_space.discrete)
            self.assertEqual(env.action_space.n, 6)
            self.assertEqual(env.env_config["max_steps"], 200)  # the env's published default
            obs, info = env.reset(seed=4)
            self.assertEqual(obs.dtype, np.float32)
            self.assertEqual(obs.shape, (6,))
            self.assertEqual(info, {})
            self.assertTrue(np.all(obs >= env.observation_space.low) and np.all(obs <= env.observation_space.high))
            obs, reward, terminated, truncated, info = env.step(3)
            self.assertIsInstance(reward, float)
            self.assertIsInstance(terminated, bool)
            self.assertIsInstance(truncated, bool)
            self.assertAlmostEqual(reward, -info["distance"], places=6)
            self.assertEqual(set(info), {"success", "collision", "out_of_bounds", "distance"})

    def test_same_seed_same_episode_in_two_sessions(self):
        def run():
            with self.env({"name": "jaka_obstacle", "is_discrete": False, "random_target": True}) as env:
                self.assertEqual(env.action_space.shape, (3,))
                rng = np.random.RandomState(0)
                trace = [env.reset(seed=11)[0]]
                for _ in range(50):
                    obs, reward, terminated, truncated, _ = env.step(env.action_space.sample(rng))
                    trace += [obs, np.float32(reward)]
                    if terminated or truncated:
                        trace.append(env.reset()[0])
                return np.concatenate([np.atleast_1d(t) for t in trace])
        np.testing.assert_array_equal(run(), run())

    def test_robot_control_position_joints_cameras_state(self):
        with self.env({"name": "inmoov_tomato"}) as env:
            self.assertEqual(len(env.joint_names), 54)
            self.assertEqual(env.camera_names, ["left_eye", "right_eye", "scene"])
            env.reset(seed=1)
            goal = env.state()["effector_position"] + np.array([0.05, -0.05, 0.03])
            for _ in range(120):
                obs, reward, terminated, truncated, info = env.position(goal)
            self.assertLess(np.linalg.norm(info["effector_position"] - goal), 0.01)
            self.assertEqual(info["joint_positions"].shape, (54,))
            state = env.state()
            self.assertEqual(state["steps"], 120)
            self.assertEqual(state["effector_orientation"].shape, (4,))
            targets = state["joint_targets"].copy()
            targets[env.joint_names.index("neck_yaw")] = 0.5
            env.joints(targets)
            images = env.cameras(96, 64)
            self.assertEqual(set(images), {"left_eye", "right_eye", "scene"})
            self.assertEqual(images["left_eye"].shape, (64, 96, 3))
            self.assertEqual(images["left_eye"].dtype, np.uint8)
            self.assertGreater(images["left_eye"].std(), 1.0)  # a picture, not a blank
            only = env.cameras(32, 32, names=["right_eye"])
            self.assertEqual(list(only), ["right_eye"])

    def test_position_is_one_step_towards_the_point_repeated_until_there(self):
        # What the module docstring says: one call moves part of the way, repeated calls arrive.
        with self.env({"name": "jaka_button"}) as env:
            env.reset(seed=2)
            start = env.state()["effector_position"]
            goal = start + np.array([0.0, 0.1, 0.0])
            obs, reward, terminated, truncated, info = env.position(goal)
            first = np.linalg.norm(info["effector_position"] - goal)
            self.assertLess(first, 0.1)                   # it moved towards the point ...
            self.assertGreater(first, 0.02)               # ... but one step does not get there
            calls = 1
            while np.linalg.norm(info["effector_position"] - goal) >= 0.005 and calls < 100:
                obs, reward, terminated, truncated, info = env.position(goal)
                calls += 1
            self.assertLess(np.linalg.norm(info["effector_position"] - goal), 0.005)
            self.assertEqual(env.state()["steps"], calls)  # every call was an env step
            print(f"position: 10 cm in {calls} calls", file=sys.stderr)

    def test_a_missing_key_file_names_the_keygen_command(self):
        with self.assertRaisesRegex(RdsimError, r"nowhere/keys/server\.key: no such file; make it with: rdsim keygen server --dir nowhere/keys"):
            load_public_key("nowhere/keys/server.key")

    def test_errors_are_replies_with_the_config_messages(self):
        with self.assertRaisesRegex(RdsimError, r"hello: env\.max_steps: expected an integer in \[1, 1e8\], got 0"):
            self.env({"name": "jaka_button", "max_steps": 0})
        with self.assertRaisesRegex(RdsimError, r"unknown environment \"pong\""):
            self.env({"name": "pong"})
        with self.env({"name": "cartpole"}) as env:
            with self.assertRaisesRegex(RdsimError, "send reset first"):
                env.step(0)
            env.reset(seed=0)
            with self.assertRaisesRegex(RdsimError, r"expected an integer in 0\.\.1"):
                env.step(7)
            with self.assertRaisesRegex(RdsimError, "cartpole has no robot"):
                env.cameras(8, 8)
            with self.assertRaisesRegex(RdsimError, r"cameras: width: expected an integer in \[1, 1024\]"):
                env.cameras(100000, 8)
            # NaN is not JSON: Python's json writes it anyway, the server refuses it.
            with self.assertRaisesRegex(RdsimError, "not valid JSON"):
                env.request({"request": "step", "action": float("nan")})
            env.step(1)  # the session goes on

    def test_protocol_version_mismatch_and_req_sockets(self):
        ctx = zmq.Context.instance()
        s = ctx.socket(zmq.REQ)  # REQ adds an empty delimiter frame; the server returns it
        s.setsockopt(zmq.LINGER, 0)
        s.curve_serverkey = load_public_key(self.server_key)
        s.curve_publickey, s.curve_secretkey = load_secret_key(self.alice)
        s.connect(self.server.address)
        s.send(json.dumps({"id": 1, "request": "hello", "protocol": 99, "env": {"name": "cartpole"}}).encode())
        self.assertTrue(s.poll(10000))
        reply = json.loads(s.recv())
        self.assertEqual(reply["id"], 1)
        self.assertIn("this server speaks protocol 1, the client 99", reply["error"])
        s.close()

    def test_an_unauthorised_key_gets_nothing(self):
        with self.assertRaisesRegex(RdsimError, "no reply within"):
            self.env({"name": "cartpole"}, key=os.path.join(self.dir, "mallory.key_secret"), timeout=2.0)
        mallory = load_public_key(os.path.join(self.dir, "mallory.key")).decode()
        with open(self.log) as f:
            self.assertIn(f"refused client key {mallory} from 127.0.0.1", f.read())


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--rdsim", required=True)
    args, rest = parser.parse_known_args()
    RDSIM = os.path.abspath(args.rdsim)
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
