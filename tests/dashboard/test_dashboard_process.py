#!/usr/bin/python3
"""`rdsim dashboard` and `rdsim train --dashboard` as processes with a slow client connected: the
dashboard stops within a second of SIGINT, and a training run exits when its work is done.

    /usr/bin/python3 tests/dashboard/test_dashboard_process.py --rdsim build/rdsim   (from the source folder)
"""

import argparse
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

failed = False


def check(ok, text):
    global failed
    print(("ok    " if ok else "FAIL  ") + text, flush=True)
    failed |= not ok


class SlowClient:
    """Sends one byte of a GET every 0.2 s until closed."""

    def __init__(self, port):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=5)
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        request = b"GET /api/runs HTTP/1.1\r\nHost: 127.0.0.1\r\n" + b"X-Slow: " + b"a" * 2000
        for k in range(len(request)):
            if self.stop.wait(0.2):
                return
            try:
                self.sock.send(request[k:k + 1])
            except OSError:
                return

    def close(self):
        self.stop.set()
        self.thread.join()
        self.sock.close()


def port_in(line):
    m = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    return int(m.group(1)) if m else -1


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--rdsim", required=True)
    a = p.parse_args()
    with tempfile.TemporaryDirectory(prefix="rdsim_dashboard_process_") as work:
        # Before: the dashboard ignored SIGINT while a slow socket was connected.
        os.makedirs(os.path.join(work, "runs"))
        proc = subprocess.Popen([a.rdsim, "dashboard", os.path.join(work, "runs"), "--bind", "127.0.0.1:0"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        port = port_in(proc.stdout.readline())
        slow = [SlowClient(port) for _ in range(6)]
        time.sleep(1.0)
        start = time.monotonic()
        proc.send_signal(signal.SIGINT)
        try:
            code = proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            code = proc.wait()
        took = time.monotonic() - start
        for s in slow:
            s.close()
        check(code == 0 and took < 1.0, f"rdsim dashboard with 6 slow clients: exit {code} {took:.2f} s after SIGINT")

        # Before: the logs were complete at 1.7 s and the process still alive at 40 s.
        run = os.path.join(work, "run")
        proc = subprocess.Popen([a.rdsim, "train", "--config", "configs/cartpole_ppo.json", "--timesteps", "4096",
                                 "--log-dir", run, "--dashboard", "127.0.0.1:0"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = proc.stderr.readline()
        port = port_in(line)
        slow = SlowClient(port) if port > 0 else None
        threading.Thread(target=proc.stderr.read, daemon=True).start()  # the progress lines
        model = os.path.join(run, "model.bin")
        done_at = None
        deadline = time.monotonic() + 120
        while proc.poll() is None and time.monotonic() < deadline:
            if done_at is None and os.path.exists(model):
                done_at = time.monotonic()
            time.sleep(0.01)
        if proc.poll() is None:
            proc.kill()
        code = proc.wait()
        if done_at is None and os.path.exists(model):
            done_at = time.monotonic()
        lag = time.monotonic() - done_at if done_at else float("inf")
        if slow:
            slow.close()
        # Nothing waits for the slow client once the work is done.
        check(port > 0 and code == 0 and lag < 3.0,
              f"train --dashboard with a slow client: exit {code} {lag:.2f} s after model.bin was written ({line.strip()})")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
