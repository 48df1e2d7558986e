"""`silcount corpus --scheduler tcp://...` on a real dask.distributed cluster on localhost.

The test starts ``dask scheduler`` and two ``dask worker`` processes (the
venv's ``dask`` command, on 127.0.0.1 with free ports, in a folder of their
own), sends a small corpus to them and stops them; the document must equal
the in-process run's, field for field, and the local ``processes``
scheduler's with two workers too.  A worker killed (SIGKILL) in the middle of a
sweep loses nothing: the scheduler runs its unit again on the other worker and
the document is the in-process run's.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from silcount.study import corpus

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "data"
DASK = Path(sys.executable).parent / "dask"
SETTINGS = dict(lights=2, subdivide=(0, 1), timing=False, quiet=True, cache=False)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_workers(address: str, n: int, procs: list[subprocess.Popen], timeout: float = 60.0) -> None:
    from distributed import Client

    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if any(p.poll() is not None for p in procs):
            raise AssertionError(f"a dask process exited early: {[p.returncode for p in procs]}")
        try:
            with Client(address, timeout="5s") as client:
                client.wait_for_workers(n, timeout=max(deadline - time.monotonic(), 1.0))
                return
        except (OSError, TimeoutError):
            time.sleep(0.5)
    raise AssertionError(f"{n} workers did not join {address} within {timeout} s")


@pytest.fixture
def cluster(tmp_path):
    if not DASK.exists():
        pytest.skip(f"no dask command beside {sys.executable}")
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    workdir = tmp_path / "cluster"
    workdir.mkdir()
    common = dict(cwd=workdir, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    procs = [
        subprocess.Popen(
            [str(DASK), "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"], **common
        )
    ]
    for _ in range(2):
        procs.append(
            subprocess.Popen(
                [
                    str(DASK),
                    "worker",
                    address,
                    "--host",
                    "127.0.0.1",
                    "--nthreads",
                    "1",
                    "--no-dashboard",
                    "--no-nanny",
                ],
                **common,
            )
        )
    try:
        wait_for_workers(address, 2, procs)
        yield address, procs
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def test_a_real_cluster_gives_the_in_process_results(cluster, tmp_path):
    address, _ = cluster
    folder = tmp_path / "meshes"
    folder.mkdir()
    for name in ("tetrahedron.obj", "quad_cube.obj", "icosphere1.obj", "torus.obj"):
        shutil.copy(DATA / name, folder / name)
    (folder / "broken.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    here = corpus([folder], scheduler="threads", workers=1, **SETTINGS)
    there = corpus([folder], scheduler=address, **SETTINGS)
    assert there.document == here.document
    assert there.rows.equals(here.rows) and there.meshes.equals(here.meshes)
    assert here.failed == 2 and len(here.rows) == 4 * 2 * 2 * 7  # broken.off at both levels; seven detectors
    local = corpus([folder], scheduler="processes", workers=2, **SETTINGS)
    assert local.document == here.document


def test_a_worker_killed_mid_sweep_loses_nothing(cluster, tmp_path):
    address, procs = cluster
    folder = tmp_path / "meshes"
    folder.mkdir()
    names = ("icosphere3.obj", "torus.obj", "icosphere2.obj", "quad_cube.obj", "icosphere1.obj", "tetrahedron.obj")
    for name in names:
        shutil.copy(DATA / name, folder / name)
    settings = {**SETTINGS, "lights": 4, "subdivide": (0, 1), "cache": None}
    here = corpus([folder], scheduler="threads", workers=1, **settings)
    cache = tmp_path / "cache"
    got: dict = {}

    def run() -> None:
        got["r"] = corpus([folder], scheduler=address, **{**settings, "cache": cache})

    sweep = threading.Thread(target=run)
    sweep.start()
    deadline = time.monotonic() + 120
    while not list(cache.glob("*.json")) and time.monotonic() < deadline:  # the first unit has finished
        time.sleep(0.05)
    done_at_kill = len(list(cache.glob("*.json")))
    procs[1].kill()  # a worker, with units still to run: one of them is on it
    procs[1].wait()
    sweep.join(timeout=300)
    assert not sweep.is_alive() and 1 <= done_at_kill < 2 * len(names)
    there = got["r"]
    assert there.failed == 0, there.meshes["error"].dropna().tolist()
    assert there.document == here.document
    assert there.rows.equals(here.rows) and there.meshes.equals(here.meshes)
