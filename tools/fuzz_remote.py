#!/usr/bin/python3
"""Hostile messages against a real `rdsim serve`, then a well-behaved client.

Starts `rdsim serve` (CurveZMQ with fresh keys, or --insecure) on a free loopback port and sends
COUNT messages, one at a time, each awaiting its reply:
  - random bytes in 1-3 frames;
  - valid requests truncated, bit-flipped, with bytes inserted, deleted or repeated;
  - valid JSON with values of the wrong type, extreme numbers, NaN, long strings and lists, unknown
    keys, deep nesting;
  - wrong part counts: extra frames, empty frames, more frames than allowed, "arrays" that
    disagree with their frames;
  - camera requests of huge and of real (up to 1024x1024) sizes;
  - now and then a frame above the server's size limit (ZeroMQ drops that connection: no reply
    expected; the fuzzer reconnects) and a client that vanishes mid-episode;
interleaved with valid hello / reset / step / close sequences so that hostile requests also hit
open sessions. Every other message must get a reply (a JSON header with the request's id and
"reply" or "error") within --reply-timeout seconds (else: a hang).

Afterwards the server must still be running, a fresh client must get exactly the episode a client
got before the fuzzing (same seed, same actions), the server's resident memory must not have grown
by more than --max-growth-mb since the warm-up, and its log must hold no sanitizer report (for an
ASan/UBSan build: RDSIM_CMAKE_ARGS=-DRDSIM_SANITIZE=ON). Exit status 0 when all holds.

    /usr/bin/python3 tools/fuzz_remote.py --rdsim build/rdsim --count 10000
"""

import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import zmq

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rdsim_client import RemoteEnv, ServerProcess, load_public_key, load_secret_key  # noqa: E402

MAX_FRAME = 64 * 1024  # the server's max_request_frame_bytes (remote/protocol.hpp)

VALID = [
    {"request": "hello", "protocol": 1, "env": {"name": "jaka_button", "max_steps": 50}},
    {"request": "hello", "protocol": 1, "env": {"name": "cartpole"}},
    {"request": "hello", "protocol": 1, "env": {"name": "jaka_obstacle", "is_discrete": False}},
    {"request": "reset", "seed": 7},
    {"request": "reset"},
    {"request": "step", "action": 3},
    {"request": "step", "action": [0.5, -0.25, 1.0]},
    {"request": "position", "position": [0.5, 0.0, 0.1]},
    {"request": "joints", "joints": [0, 1.44, -1.85, 1.98, 1.5708, 0]},
    {"request": "cameras", "width": 32, "height": 24},
    {"request": "cameras", "width": 16, "height": 16, "cameras": ["wrist"]},
    {"request": "state"},
    {"request": "drop_caches"},
    {"request": "close"},
]

ODD_VALUES = [None, True, False, 0, -1, 1, 2**31, -2**63, 2**64 - 1, 2**64, 1e300, -1e-300, 0.5, "", "x" * 1000,
              "step", [], {}, [1, 2, 3], [[[]]], {"name": "cartpole"}, ["wrist"] * 9, list(range(300)),
              float("nan"), float("inf")]


class Fuzzer:
    def __init__(self, address, keys, rng, reply_timeout):
        self.address, self.keys, self.rng, self.timeout_ms = address, keys, rng, int(reply_timeout * 1000)
        self.ctx = zmq.Context.instance()
        self.socket = None
        self.next_id = 1
        self.stats = {"sent": 0, "replies": 0, "errors": 0, "dropped_by_design": 0, "reconnects": 0}
        self.connect()

    def connect(self):
        if self.socket is not None:
            self.socket.close(0)
            self.stats["reconnects"] += 1
        s = self.ctx.socket(zmq.DEALER)
        s.setsockopt(zmq.LINGER, 0)
        if self.keys:
            s.curve_serverkey = load_public_key(self.keys[0])
            s.curve_publickey, s.curve_secretkey = load_secret_key(self.keys[1])
        s.connect(self.address)
        self.socket = s

    # -- message makers ---------------------------------------------------------------------
    def header(self):
        h = dict(self.rng.choice(VALID))
        h["id"] = self.next_id
        self.next_id += 1
        return h

    def dumps(self, h):
        return json.dumps(h, allow_nan=True).encode()

    def random_bytes(self, n):
        return bytes(self.rng.getrandbits(8) for _ in range(n))

    def mutate(self, data):
        data = bytearray(data)
        for _ in range(self.rng.randint(1, 4)):
            op = self.rng.randrange(5)
            if not data:
                data += self.random_bytes(4)
            i = self.rng.randrange(len(data))
            if op == 0:
                del data[i:]
            elif op == 1:
                data[i] ^= 1 << self.rng.randrange(8)
            elif op == 2:
                data.insert(i, self.rng.getrandbits(8))
            elif op == 3:
                del data[i]
            else:
                data[i:i] = data[i:i + self.rng.randint(1, 16)] * self.rng.randint(1, 8)
        return bytes(data)

    def odd_json(self):
        h = self.header()
        keys = list(h) + ["extra", "arrays"]
        for _ in range(self.rng.randint(1, 3)):
            h[self.rng.choice(keys)] = self.rng.choice(ODD_VALUES)
        return [self.dumps(h)]

    def deep(self):
        depth = self.rng.choice([7, 8, 9, 50, 5000])
        h = self.header()
        h["env"] = json.loads("[" * depth + "]" * depth) if depth < 900 else None
        text = self.dumps(h)
        if depth >= 900:
            text = text.replace(b"null", b"[" * depth + b"]" * depth)
        return [text]

    def wrong_parts(self):
        h = self.dumps(self.header())
        kind = self.rng.randrange(5)
        if kind == 0:
            return [h, self.random_bytes(self.rng.randint(0, 64))]
        if kind == 1:
            return [b"", b"", h]
        if kind == 2:
            return [h] * self.rng.randint(17, 40)
        if kind == 3:
            d = json.loads(h)
            d["arrays"] = [{"name": "action", "dtype": self.rng.choice(["float32", "uint8", "f64"]),
                            "shape": [self.rng.choice([3, -1, 2**40])]}]
            return [self.dumps(d), self.random_bytes(self.rng.choice([0, 12, 13]))]
        return [b""]

    def cameras(self):
        h = {"id": self.next_id, "request": "cameras"}
        self.next_id += 1
        side = self.rng.choice([0, 1, 1024, 1025, 10**6, 2**31])
        h["width"], h["height"] = side, self.rng.choice([1, side])
        return [self.dumps(h)]

    def message(self):
        r = self.rng.random()
        if r < 0.15:
            return [self.random_bytes(self.rng.randint(0, 300)) for _ in range(self.rng.randint(1, 3))]
        if r < 0.50:
            return [self.mutate(self.dumps(self.header()))]
        if r < 0.70:
            return self.odd_json()
        if r < 0.75:
            return self.deep()
        if r < 0.87:
            return self.wrong_parts()
        if r < 0.89:
            return self.cameras()
        return [self.dumps(self.header())]  # valid: keeps sessions open and moving

    # -- sending ----------------------------------------------------------------------------
    def exchange(self, frames):
        self.socket.send_multipart(frames)
        self.stats["sent"] += 1
        if not self.socket.poll(self.timeout_ms):
            raise SystemExit(f"FAIL: no reply within {self.timeout_ms / 1000:g} s (a hang) to {frames!r:.300}")
        parts = self.socket.recv_multipart()
        if len(parts) > 1 and parts[0] == b"":
            parts = parts[1:]  # the delimiter of a request that started with an empty frame
        try:
            reply = json.loads(parts[0])
        except ValueError:
            reply = None
        if not isinstance(reply, dict) or "id" not in reply or ("error" not in reply and "reply" not in reply):
            raise SystemExit(f"FAIL: malformed reply {parts[0]!r:.300} to {frames!r:.300}")
        self.stats["replies"] += 1
        self.stats["errors"] += "error" in reply

    def oversized(self):
        """A frame above the limit: ZeroMQ drops this connection (no reply by design)."""
        self.socket.send(b" " * (MAX_FRAME + self.rng.randint(1, 1000)))
        self.stats["sent"] += 1
        self.stats["dropped_by_design"] += 1
        if self.socket.poll(200):
            raise SystemExit("FAIL: a frame above the size limit got a reply")
        self.connect()

    def vanish(self):
        """Opens a session, steps, and disappears without close."""
        self.exchange([self.dumps({"id": 0, "request": "hello", "protocol": 1, "env": {"name": "cartpole"}})])
        self.connect()

    def run(self, count, on_progress):
        for n in range(count):
            r = self.rng.random()
            if r < 0.005:
                self.oversized()
            elif r < 0.01:
                self.vanish()
            else:
                self.exchange(self.message())
            on_progress(n + 1)


def rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def reference_episode(address, keys):
    """A well-behaved client's episode: fixed seed and actions."""
    kw = {"server_key": keys[0], "client_key": keys[1]} if keys else {}
    with RemoteEnv(address, {"name": "jaka_button", "random_target": True}, **kw) as env:
        out = [env.reset(seed=5)[0]]
        for t in range(100):
            obs, reward, terminated, truncated, _ = env.step(t % 6)
            out += [obs, np.float32([reward, terminated, truncated])]
            if terminated or truncated:
                out.append(env.reset()[0])
        images = env.cameras(32, 32)["wrist"]
    return np.concatenate([np.ravel(o).astype(np.float32) for o in out]), images


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--rdsim", default="build/rdsim")
    p.add_argument("--count", type=int, default=10000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--insecure", action="store_true", help="plain text instead of CurveZMQ")
    p.add_argument("--reply-timeout", type=float, default=30.0, help="s before a missing reply counts as a hang")
    p.add_argument("--max-growth-mb", type=float, default=64.0)
    a = p.parse_args()

    workdir = tempfile.mkdtemp(prefix="rdsim_fuzz_")
    log = os.path.join(workdir, "serve.log")
    keys = None
    server_keys = None
    try:
        if not a.insecure:
            server_keys = os.path.join(workdir, "keys")
            for name, where in (("server", server_keys), ("fuzzer", workdir)):
                subprocess.run([a.rdsim, "keygen", name, "--dir", where], check=True, stdout=subprocess.DEVNULL)
            os.makedirs(os.path.join(server_keys, "clients"))
            shutil.copy(os.path.join(workdir, "fuzzer.key"), os.path.join(server_keys, "clients"))
            keys = (os.path.join(server_keys, "server.key"), os.path.join(workdir, "fuzzer.key_secret"))
        server = ServerProcess(a.rdsim, keys=server_keys, log=log, args=["--max-sessions", "8", "--idle-timeout", "5"])
        try:
            before, before_images = reference_episode(server.address, keys)
            fuzzer = Fuzzer(server.address, keys, random.Random(a.seed), a.reply_timeout)
            warm = max(1, a.count // 10)
            start = time.time()
            marks = {}

            def progress(n):
                if n == warm:
                    marks["rss_warm"] = rss_kb(server.pid)
                if n % 1000 == 0:
                    print(f"fuzz: {n}/{a.count} messages, server RSS {rss_kb(server.pid) / 1024:.1f} MiB", flush=True)
                if not server.alive():
                    raise SystemExit(f"FAIL: the server died after {n} messages")

            marks["rss_start"] = rss_kb(server.pid)
            fuzzer.run(a.count, progress)
            elapsed = time.time() - start
            rss_end = rss_kb(server.pid)
            after, after_images = reference_episode(server.address, keys)
            alive = server.alive()
        finally:
            status = server.stop()
        with open(log, errors="replace") as f:
            log_text = f.read()
        s = fuzzer.stats
        growth = (rss_end - marks.get("rss_warm", rss_end)) / 1024
        print(f"fuzz: {s['sent']} hostile messages in {elapsed:.1f} s: {s['replies']} replies ({s['errors']} errors), "
              f"{s['dropped_by_design']} oversized frames (connection dropped, by design), {s['reconnects']} reconnects")
        print(f"fuzz: server RSS {marks['rss_start'] / 1024:.1f} MiB at start, {marks.get('rss_warm', 0) / 1024:.1f} MiB "
              f"after {max(1, a.count // 10)} messages, {rss_end / 1024:.1f} MiB at the end (growth {growth:+.1f} MiB)")
        failures = []
        if not alive:
            failures.append("the server died")
        if not (np.array_equal(before, after) and np.array_equal(before_images, after_images)):
            failures.append("a well-behaved client got a different episode after the fuzzing")
        if growth > a.max_growth_mb:
            failures.append(f"memory grew by {growth:.1f} MiB (limit {a.max_growth_mb:g})")
        for marker in ("ERROR: AddressSanitizer", "runtime error:", "ERROR: LeakSanitizer"):
            if marker in log_text:
                failures.append(f"sanitizer report in the server log ({marker})")
        if status != 0:
            failures.append(f"the server exited with status {status} on SIGTERM")
        if failures:
            print("fuzz: FAIL: " + "; ".join(failures))
            print(log_text[-4000:])
            return 1
        print("fuzz: OK: 0 crashes, 0 hangs; a well-behaved client got the same episode and images as before; "
              "clean exit on SIGTERM")
        return 0
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
