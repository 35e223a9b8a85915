#!/usr/bin/env python3
"""Runs every sh, bash and python code block of README.md and docs/*.md as a user would copy it.

Each page gets a scratch folder laid out like a checkout (build/rdsim, configs/, tools/, examples/,
.venv), and its blocks run there in page order (a later block may use what an earlier one made,
as a reader's session does). What would take hours or never end in CI is changed by the table
SUBSTITUTIONS below (each with its reason): training budgets become 2,048 steps, a server in the
foreground runs for a few seconds. Every process a block starts is stopped when the block ends.
A block the test cannot run (a cluster, a package build) is marked in the Markdown, right before
it, with `<!-- not run in CI: REASON -->`, and the page says why next to it.

Usage: test_doc_snippets.py --rdsim build/rdsim [--venv-python .venv/bin/python] [--list]
Exit status 0 when every block ran and passed.
"""
import argparse
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGES = ["README.md"] + sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))
LANGUAGES = ("sh", "bash", "python")
SKIP = re.compile(r"<!--\s*not run in CI:\s*(.+?)\s*-->")
TIMESTEPS = 2048  # one or two updates of a shipped config

# (pattern, replacement, why): applied to the text of sh and bash blocks, in this order.
SUBSTITUTIONS = [
    (r"bash tools/setup\.sh && ", "",
     "CI ran tools/setup.sh before the tests: it built the binary and the Python package under test"),
    (r"(?m)^bash tools/test\.sh$", "true", "the test suite itself, which this test is part of"),
    (r"(?m)^((?:mpirun [^\n#]*?)?build/rdsim train [^\n#&]*?)(\s*(?:#.*)?)$", r"\1 --timesteps %d\2" % TIMESTEPS,
     "a tiny training budget"),
    (r"(?m)^(python|\.venv/bin/python) (examples/\S+\.py [^\n#]*)--timesteps \d+", r"\1 \2--timesteps %d" % TIMESTEPS,
     "a tiny training budget"),
    (r"(?m)^mpirun ", "mpirun --oversubscribe ", "CI has 2 cores"),
    (r"(?m)^(build/rdsim dashboard [^\n#&]*?)(\s*(?:#.*)?)$", r"\1 --bind 127.0.0.1:0 --for 1\2",
     "a server in the foreground: 1 s, on a free port"),
    (r"(?m)^(build/rdsim serve [^\n#&]*?)(\s*(?:#.*)?)$", r"(timeout -s INT 3 \1 || test $? -eq 124)\2",
     "a server in the foreground: 3 s, then Ctrl-C"),
]

# Pages that use a file made by another page: what a reader has done before (with its budget).
PRELUDES = {
    "docs/python.md": "build/rdsim train --quiet --config configs/jaka_button.json --timesteps %d" % TIMESTEPS,
}


def blocks(page):
    """(line, language, text, skip reason or None) of each sh/bash/python block of a page."""
    lines = (ROOT / page).read_text().split("\n")
    found = []
    i = 0
    while i < len(lines):
        m = re.match(r"^\s*```(\w+)\s*$", lines[i])
        if not m:
            i += 1
            continue
        end = i + 1
        while end < len(lines) and not lines[end].strip().startswith("```"):
            end += 1
        if m.group(1) in LANGUAGES:
            before = next((lines[k] for k in range(i - 1, -1, -1) if lines[k].strip()), "")
            skip = SKIP.search(before)
            found.append((i + 1, m.group(1), "\n".join(lines[i + 1:end]), skip.group(1) if skip else None))
        i = end + 1
    return found


def substituted(text):
    for pattern, replacement, _ in SUBSTITUTIONS:
        text = re.sub(pattern, replacement, text)
    return text


def checkout(scratch, rdsim, venv_python):
    """A folder laid out like the checkout: the binary under test as build/rdsim (and the policy
    library's example beside it), and the rest."""
    (scratch / "build").mkdir()
    (scratch / "build" / "rdsim").symlink_to(rdsim)
    example = pathlib.Path(rdsim).parent / "rdsim_policy_example"  # built beside it (docs/export.md)
    if example.exists():
        (scratch / "build" / "rdsim_policy_example").symlink_to(example)
    shutil.copytree(ROOT / "configs", scratch / "configs")
    for name in ("tools", "examples", "assets", "python"):
        if (ROOT / name).exists():
            (scratch / name).symlink_to(ROOT / name)
    if venv_python:
        (scratch / ".venv").symlink_to(pathlib.Path(venv_python).parent.parent)


def run(command, scratch, timeout):
    """Runs `command` (argv) in its own process group, which is killed when the command ends: a
    server the block left running in the background goes with it."""
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", MPLBACKEND="Agg")
    env.pop("RDSIM_ROOT", None)  # as a user runs them: the binary finds the assets itself
    # Stable-Baselines3's logger would make a folder tempdir/SB3-<date-time> per learn(): in the
    # page's scratch folder instead, removed with it.
    env["SB3_LOGDIR"] = str(pathlib.Path(scratch) / "sb3_logs")
    start = time.monotonic()
    with tempfile.TemporaryFile(mode="w+") as out:
        proc = subprocess.Popen(command, cwd=scratch, env=env, stdout=out, stderr=subprocess.STDOUT, text=True,
                                start_new_session=True)
        try:
            code = proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            code = 124
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        proc.wait()
        out.seek(0)
        text = out.read() + ("\n(timed out after %d s)" % timeout if code == 124 else "")
    return code, text, time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rdsim", required=True, help="the rdsim binary under test")
    parser.add_argument("--venv-python", default=str(ROOT / ".venv/bin/python"),
                        help="the project venv's python (with the rdsim package: tools/setup.sh)")
    parser.add_argument("--list", action="store_true", help="print the blocks as they would run, run nothing")
    parser.add_argument("--timeout", type=int, default=120, help="s per block")
    a = parser.parse_args()
    rdsim = str(pathlib.Path(a.rdsim).resolve())

    ran, failed, not_run = 0, [], []
    for page in PAGES:
        page_blocks = blocks(page)
        if not page_blocks:
            continue
        with tempfile.TemporaryDirectory(prefix="rdsim_docs_") as tmp:
            scratch = pathlib.Path(tmp)
            checkout(scratch, rdsim, a.venv_python)
            if page in PRELUDES and not a.list:
                code, out, _ = run(["bash", "-c", PRELUDES[page]], scratch, a.timeout)
                if code != 0:
                    failed.append("%s: prelude `%s` failed:\n%s" % (page, PRELUDES[page], out))
                    continue
            for line, language, text, skip in page_blocks:
                where = "%s:%d" % (page, line)
                if skip:
                    not_run.append("%s (%s)" % (where, skip))
                    continue
                if language == "python":
                    (scratch / "snippet.py").write_text(text + "\n")
                    command = [str(scratch / ".venv/bin/python"), "snippet.py"]
                    shown = text
                else:
                    shown = substituted(text)
                    command = ["bash", "-e", "-o", "pipefail", "-c", shown]
                if a.list:
                    print("==== %s [%s]\n%s" % (where, language, shown))
                    continue
                code, out, seconds = run(command, scratch, a.timeout)
                ran += 1
                status = "ok" if code == 0 else "FAILED (exit %d)" % code
                print("%s [%s] %s in %.1f s" % (where, language, status, seconds), flush=True)
                if code != 0:
                    failed.append("%s [%s] exit %d\n--- as run:\n%s\n--- output (last 3000 characters):\n%s" %
                                  (where, language, code, shown, out[-3000:]))
    for f in failed:
        print("\n" + f)
    print("\ndoc snippets: %d run, %d failed, %d marked not run in CI%s" %
          (ran, len(failed), len(not_run), "".join("\n  not run: " + n for n in not_run)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
