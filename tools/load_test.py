#!/usr/bin/python3
"""Idle and slow clients against a real `rdsim dashboard` and a real `rdsim serve`.

For each server, on loopback only: opens --idle TCP connections that never send a byte and
--slow clients that send one byte of a request every --slow-gap seconds, all at once, and holds
them for --seconds while a well-behaved client keeps asking (HTTP GETs of /api/runs; hello, reset
and steps over ZeroMQ). For `rdsim serve` one more client also sends --unread camera requests
(512 x 512) and never reads the replies. Then it stops the server with SIGINT (dashboard) or
SIGTERM (serve).

Checks, each a line of the report: the good client's p99 latency is below --max-latency seconds
and none of its requests failed; the server's peak resident memory (VmHWM) is below --max-rss-mb;
the server exits with status 0 within a second of the signal. Exit status 0 when all hold.

    /usr/bin/python3 tools/load_test.py --rdsim build/rdsim                      (the full load: 1000 + 50)
    /usr/bin/python3 tools/load_test.py --rdsim build/rdsim --idle 200 --slow 10 --seconds 2   (ctest)

Every socket and process it opens is closed or stopped before it exits; loops are bounded.
"""

import argparse
import json
import os
import re
import resource
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

import zmq


def raise_file_limit(needed):
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft != resource.RLIM_INFINITY and soft < needed:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, needed) if hard != resource.RLIM_INFINITY else needed, hard))


def vm_kib(pid, field):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith(field + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def open_sockets(pid):
    """Sockets the process holds now (its connections, listening sockets included)."""
    n = 0
    try:
        for fd in os.listdir(f"/proc/{pid}/fd"):
            try:
                n += os.readlink(f"/proc/{pid}/fd/{fd}").startswith("socket:")
            except OSError:
                pass
    except OSError:
        pass
    return n


class Crowd:
    """Idle connections and slow clients to 127.0.0.1:port, held until close()."""

    def __init__(self, port, idle, slow, slow_gap, slow_bytes):
        self.idle, self.slow = [], []
        for _ in range(idle):
            self.idle.append(self._connect(port))
        for _ in range(slow):
            self.slow.append([self._connect(port), 0])
        self.slow_bytes, self.gap = slow_bytes, slow_gap
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._trickle, daemon=True)
        self.thread.start()

    @staticmethod
    def _connect(port):
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        s.settimeout(5)
        try:
            s.connect(("127.0.0.1", port))
        except OSError:
            pass  # the server may refuse or drop some: that is its right
        s.setblocking(False)
        return s

    def _trickle(self):
        while not self.stop.wait(self.gap):
            for entry in self.slow:
                s, sent = entry
                if sent >= len(self.slow_bytes):
                    continue
                try:
                    s.send(self.slow_bytes[sent:sent + 1])
                    entry[1] += 1
                except OSError:
                    entry[1] = len(self.slow_bytes)  # dropped by the server

    def close(self):
        self.stop.set()
        self.thread.join()
        for s in self.idle + [e[0] for e in self.slow]:
            s.close()


def p99(values):
    if not values:
        return float("inf")
    v = sorted(values)
    return v[min(len(v) - 1, int(0.99 * len(v)))]


class Report:
    def __init__(self):
        self.failed = False

    def check(self, ok, text):
        print(("ok    " if ok else "FAIL  ") + text, flush=True)
        self.failed |= not ok


def stop_and_wait(proc, sig, report, name):
    start = time.monotonic()
    proc.send_signal(sig)
    try:
        code = proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        code = proc.wait()
    took = time.monotonic() - start
    report.check(code == 0 and took < 1.0, f"{name}: exit status {code} {took:.2f} s after {signal.Signals(sig).name}")


def http_get(port, path, timeout):
    with socket.create_connection(("127.0.0.1", port), timeout=timeout) as s:
        s.sendall(f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n".encode())
        data = b""
        while True:
            chunk = s.recv(65536)
            if not chunk:
                break
            data += chunk
    return int(data.split(b" ", 2)[1]) if data.startswith(b"HTTP/1.1 ") else 0


def load_dashboard(a, work, report):
    runs = os.path.join(work, "runs", "run")
    os.makedirs(runs)
    with open(os.path.join(runs, "config.json"), "w") as f:
        json.dump({"algorithm": "ppo", "env": {"name": "cartpole"}, "seed": 1}, f)
    with open(os.path.join(runs, "progress.csv"), "w") as f:
        f.write("timesteps,mean_return\n" + "".join(f"{i * 100},{i}\n" for i in range(1, 200)))
    proc = subprocess.Popen([a.rdsim, "dashboard", os.path.join(work, "runs"), "--bind", "127.0.0.1:0"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        m = re.search(r"http://127\.0\.0\.1:(\d+)/", proc.stdout.readline())
        if not m:
            report.check(False, "dashboard: no address printed")
            return
        port = int(m.group(1))
        crowd = Crowd(port, a.idle, a.slow, a.slow_gap, f"GET /api/runs HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n".encode())
        time.sleep(0.5)
        print(f"info  dashboard: {open_sockets(proc.pid)} sockets open in the server with the crowd connected", flush=True)
        latencies, failures = [], 0
        end = time.monotonic() + a.seconds
        while time.monotonic() < end:
            t = time.monotonic()
            try:
                failures += http_get(port, "/api/runs", 5) != 200
            except OSError:
                failures += 1
            latencies.append(time.monotonic() - t)
            time.sleep(0.02)
        rss = vm_kib(proc.pid, "VmHWM") / 1024
        crowd.close()
        report.check(failures == 0 and p99(latencies) < a.max_latency,
                     f"dashboard: {len(latencies)} GETs while {a.idle} idle and {a.slow} slow clients were connected: "
                     f"p99 {p99(latencies) * 1000:.1f} ms, max {max(latencies) * 1000:.1f} ms, {failures} failed")
        report.check(rss < a.max_rss_mb, f"dashboard: peak resident memory {rss:.1f} MiB (limit {a.max_rss_mb} MiB)")
        stop_and_wait(proc, signal.SIGINT, report, "dashboard")
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def zmq_call(sock, header, timeout_ms):
    sock.send(json.dumps(header).encode())
    if not sock.poll(timeout_ms):
        return None
    parts = sock.recv_multipart()
    return json.loads(parts[0])


def load_server(a, work, report):
    proc = subprocess.Popen([a.rdsim, "serve", "--insecure", "--bind", "tcp://127.0.0.1:*", "--max-sessions", "8"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    ctx = zmq.Context()
    try:
        m = re.search(r"listening on tcp://127\.0\.0\.1:(\d+)", proc.stdout.readline())
        if not m:
            report.check(False, "serve: no address printed")
            return
        port = int(m.group(1))
        endpoint = f"tcp://127.0.0.1:{port}"
        # The start of a ZeroMQ greeting, a byte at a time.
        crowd = Crowd(port, a.idle, a.slow, a.slow_gap, b"\xff" + b"\x00" * 8 + b"\x7f\x03\x00NULL")
        time.sleep(0.5)
        print(f"info  serve: {open_sockets(proc.pid)} sockets open in the server with the crowd connected", flush=True)
        unread = ctx.socket(zmq.DEALER)
        unread.setsockopt(zmq.LINGER, 0)
        unread.setsockopt(zmq.RCVHWM, 1)
        unread.setsockopt(zmq.RCVBUF, 65536)
        unread.connect(endpoint)
        zmq_call(unread, {"id": 1, "request": "hello", "protocol": 1, "env": {"name": "jaka_button"}}, 30000)
        for k in range(a.unread):
            unread.send(json.dumps({"id": 2 + k, "request": "cameras", "width": 512, "height": 512}).encode())
        good = ctx.socket(zmq.DEALER)
        good.setsockopt(zmq.LINGER, 0)
        good.connect(endpoint)
        hello = zmq_call(good, {"id": 1, "request": "hello", "protocol": 1, "env": {"name": "cartpole"}}, 30000)
        latencies, failures, n = [], 0 if hello and "reply" in hello else 1, 2
        end = time.monotonic() + a.seconds
        while time.monotonic() < end:
            t = time.monotonic()
            header = {"id": n, "request": "reset", "seed": 1} if n % 50 == 2 else {"id": n, "request": "step", "action": n % 2}
            reply = zmq_call(good, header, 5000)
            latencies.append(time.monotonic() - t)
            failures += reply is None or reply.get("id") != n
            n += 1
            time.sleep(0.005)
        time.sleep(1.0)  # the unread client's camera replies are being made meanwhile
        rss = vm_kib(proc.pid, "VmHWM") / 1024
        crowd.close()
        report.check(failures == 0 and p99(latencies) < a.max_latency,
                     f"serve: {len(latencies)} requests while {a.idle} idle and {a.slow} slow connections and a client "
                     f"not reading {a.unread} camera replies were connected: p99 {p99(latencies) * 1000:.1f} ms, "
                     f"max {max(latencies) * 1000:.1f} ms, {failures} failed")
        report.check(rss < a.max_rss_mb, f"serve: peak resident memory {rss:.1f} MiB (limit {a.max_rss_mb} MiB)")
        good.close(0)
        unread.close(0)
        stop_and_wait(proc, signal.SIGTERM, report, "serve")
    finally:
        ctx.destroy(0)
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rdsim", required=True)
    p.add_argument("--idle", type=int, default=1000)
    p.add_argument("--slow", type=int, default=50)
    p.add_argument("--slow-gap", type=float, default=0.5)
    p.add_argument("--seconds", type=float, default=20.0)
    p.add_argument("--unread", type=int, default=200)
    p.add_argument("--max-latency", type=float, default=1.0)
    p.add_argument("--max-rss-mb", type=float, default=400.0)
    p.add_argument("--only", choices=["dashboard", "serve"])
    a = p.parse_args()
    raise_file_limit(2 * (a.idle + a.slow) + 256)
    report = Report()
    work = tempfile.mkdtemp(prefix="rdsim_load_")
    try:
        if a.only != "serve":
            load_dashboard(a, work, report)
        if a.only != "dashboard":
            load_server(a, work, report)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if report.failed else 0


if __name__ == "__main__":
    sys.exit(main())
