"""silcount.threads: the thread count of a parallel kernel fitted to the cores that other work leaves free."""

from __future__ import annotations

import os

import numba
import pytest

from silcount import threads


@pytest.fixture
def loadavg(tmp_path, monkeypatch):
    """Write a /proc/loadavg line with ``running`` runnable threads and point silcount.threads at it."""
    opened: list[int] = []

    def write(running: int) -> None:
        path = tmp_path / "loadavg"
        path.write_text(f"1.50 0.90 0.70 {running}/171 4242\n")
        opened.append(os.open(path, os.O_RDONLY))
        monkeypatch.setattr(threads, "_fd", [opened[-1]])

    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1, 2, 3})
    yield write
    for fd in opened:
        os.close(fd)


@pytest.mark.parametrize(("running", "free"), [(1, 4), (2, 3), (4, 1), (5, 1), (40, 1)])
def test_free_cores_counts_the_caller_out(loadavg, running, free):
    loadavg(running)  # 4 cores; the caller is one of the runnable threads
    assert threads.free_cores() == free


def test_without_the_file_every_core_is_free(monkeypatch):
    monkeypatch.setattr(threads, "_fd", [])
    monkeypatch.setattr(threads, "LOADAVG", "/nonexistent/loadavg")
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1, 2})
    assert threads.free_cores() == 3


def test_fitted_lowers_the_count_inside_and_restores_it(loadavg):
    before = numba.get_num_threads()
    loadavg(4)  # three others: one core free
    with threads.fitted() as n:
        assert n == 1 and numba.get_num_threads() == 1
    assert numba.get_num_threads() == before


def test_fitted_never_raises_the_callers_count(loadavg):
    before = numba.get_num_threads()
    loadavg(1)  # every core free
    numba.set_num_threads(1)  # a corpus worker's one thread
    try:
        with threads.fitted() as n:
            assert n == 1 and numba.get_num_threads() == 1
    finally:
        numba.set_num_threads(before)


def test_passive_wait_is_the_default():
    assert os.environ.get("OMP_WAIT_POLICY") == "passive"  # set by import silcount unless the user chose


def test_detect_runs_its_kernels_on_the_free_cores(monkeypatch):
    import silcount
    from silcount.detectors import reference

    seen: list[int] = []
    engine = reference._fast

    def spy(mesh, light):
        seen.append(numba.get_num_threads())
        return engine(mesh, light)

    monkeypatch.setattr(reference, "_fast", spy)
    monkeypatch.setattr(threads, "free_cores", lambda: 1)  # another process holds every other core
    before = numba.get_num_threads()
    mesh = silcount.builtin_mesh("torus")
    silcount.detect(mesh, silcount.DirectionalLight((0.0, 0.0, 1.0)), "reference")
    assert seen == [1] and numba.get_num_threads() == before
