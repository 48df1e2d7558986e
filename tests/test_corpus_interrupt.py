"""Ctrl-C on `silcount corpus` with process workers: one line, exit 130, no worker left behind (issue 44).

A terminal's Ctrl-C is SIGINT to the whole foreground process group, the workers included; here the
command runs in a session of its own and the signal goes to its group, as a terminal would send it.
Before the fix, a Ctrl-C while the workers were starting printed their ``KeyboardInterrupt`` tracebacks
(67 lines) after ``silcount: interrupted``.  That the sweep resumes from the cache afterwards is
``tests/test_corpus.py``'s ``test_an_interrupted_sweep_resumes_from_the_cache``.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import psutil
import pytest

DATA = Path(__file__).resolve().parent.parent / "data"


def spawned_workers(pid: int) -> list[psutil.Process]:
    """The multiprocessing workers among ``pid``'s descendants (not its resource tracker)."""
    try:
        found = psutil.Process(pid).children(recursive=True)
    except psutil.Error:
        return []
    out = []
    for p in found:
        try:
            if "spawn_main" in " ".join(p.cmdline()):
                out.append(p)
        except psutil.Error:
            continue
    return out


@pytest.mark.slow
@pytest.mark.parametrize("after,group", [(0.0, True), (0.3, True), (1.0, True), (1.0, False)])
def test_ctrl_c_while_the_workers_start_is_one_line(tmp_path, after, group):
    # group=False: `kill -INT` of the client alone, which must then stop the workers itself
    for name in ("tetrahedron.obj", "quad_cube.obj", "icosphere3.obj"):
        shutil.copy(DATA / name, tmp_path / name)
    # level 4 (icosphere3 at 327,680 faces) keeps the sweep running seconds after ``after``: on a quiet machine
    # three meshes as they are finished within a second of the workers' start, before the Ctrl-C
    argv = ["corpus", str(tmp_path), "--no-cache", "--no-time", "--quiet", "--workers", "2", "--subdivide", "0,4"]
    proc = subprocess.Popen(
        [sys.executable, "-m", "silcount.cli.main", *argv, "--scheduler", "processes"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    deadline = time.monotonic() + 120
    while not spawned_workers(proc.pid) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)
    assert proc.poll() is None, "the sweep ended before its workers were seen"
    time.sleep(after)  # the workers are starting: importing numpy, numba and silcount take a second or more
    everyone = psutil.Process(proc.pid).children(recursive=True)
    if group:
        os.killpg(proc.pid, signal.SIGINT)
    else:
        os.kill(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130 and err == "silcount: interrupted\n", err
    gone, alive = psutil.wait_procs(everyone, timeout=10)
    assert not alive, alive
