"""Hostile meshes (issue 44): piles of overlapping triangles, a work limit, Ctrl-C during long kernels.

A run whose work passes ``--max-work`` is refused with one line naming it, the other detectors reported;
the chunk runner (:mod:`silcount.mesh.chunks`) lets Ctrl-C end an audit within a second or two; EESD's
answers on piles of triangles are the naive engine's (the printed loops, every pair).
"""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
import time
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pytest

import silcount
from silcount.cli.main import main
from silcount.errors import BadArgument, TooMuchWork
from silcount.mesh.chunks import Meter, limit_work, parse_work, run_chunks, work_limit


def fan_obj(path: Path, copies: int) -> Path:
    """``copies`` copies of one triangle turned about its centre, each its own vertices, stacked 1e-3 apart."""
    big = np.array([[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]])
    lines = []
    for k, a in enumerate(2 * np.pi * np.arange(copies) / copies):
        c, s = np.cos(a), np.sin(a)
        lines += [f"v {x * c - y * s:.17g} {x * s + y * c:.17g} {k * 1e-3:.17g}" for x, y in big]
    lines += [f"f {3 * k + 1} {3 * k + 2} {3 * k + 3}" for k in range(copies)]
    path.write_text("\n".join(lines) + "\n")
    return path


def run_cli(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        rc = main(list(argv))
    return rc, out.getvalue(), err.getvalue()


def test_a_run_over_the_work_limit_is_refused_and_the_others_reported(tmp_path):
    # 300 turned copies: EESD casts about 1,800 rays through the pile (far more than 1,000 ray-triangle
    # tests); the reference and TA do no such tests.  The audit reports them and names eesd in one line.
    path = fan_obj(tmp_path / "fan.obj", 300)
    common = ("audit", str(path), "--detectors", "reference,ta,eesd", "--random-lights", "2", "--quiet")
    rc, out, err = run_cli(*common, "--format", "json", "--max-work", "1000")
    assert rc == 4 and "Traceback" not in err
    (line,) = err.strip().splitlines()
    assert line.startswith(f"silcount audit: error: {path}: eesd refused: eesd: its rays: over 1,000 ")
    assert "--max-work" in line
    got = json.loads(out)
    assert sorted(got["detectors"]) == ["reference", "ta"] and list(got["refused"]) == ["eesd"]
    assert all(sorted(pl["detectors"]) == ["reference", "ta"] for pl in got["per_light"])
    rc, text, _ = run_cli(*common, "--max-work", "1000")
    assert rc == 4 and "## Refused" not in text and "Refused (not in the tables below)" in text
    assert "- eesd: eesd: its rays: over 1,000" in text
    rc, out, err = run_cli(*common, "--format", "json")  # the default limit: every run reported
    full = json.loads(out)
    assert rc == 0 and err == "" and "refused" not in full and sorted(full["detectors"]) == ["eesd", "reference", "ta"]
    assert full["detectors"]["ta"] == got["detectors"]["ta"] | {"time_s": full["detectors"]["ta"]["time_s"]}


def test_literal_plane_tests_are_refused_alone(tmp_path):
    # --variant both: only eesd:literal's plane walk passes a limit that its rays stay under.
    path = fan_obj(tmp_path / "fan.obj", 40)
    rc, out, err = run_cli(
        "audit", str(path), "--detectors", "eesd", "--variant", "both", "--random-lights", "1", "--quiet",
        "--format", "json", "--max-work", "2000",
    )  # fmt: skip
    got = json.loads(out)
    assert rc == 4 and list(got["refused"]) == ["eesd:literal"] and list(got["detectors"]) == ["eesd"]
    assert err.count("\n") == 1 and "eesd:literal refused: eesd:literal: its plane tests: over 2,000" in err


def test_bad_work_limits_are_bad_arguments(tmp_path, monkeypatch):
    path = fan_obj(tmp_path / "fan.obj", 3)
    for bad in ("lots", "0", "-5", "nan", "1e40"):
        rc, out, err = run_cli("audit", str(path), "--quiet", "--max-work", bad)
        assert rc == 2 and out == "" and err.count("\n") == 1 and "--max-work" in err
    monkeypatch.setenv("SILCOUNT_MAX_WORK", "some")
    with pytest.raises(BadArgument, match="SILCOUNT_MAX_WORK"):
        work_limit()
    monkeypatch.setenv("SILCOUNT_MAX_WORK", "2.5e3")
    assert work_limit() == 2500
    with limit_work(7):
        assert work_limit() == 7 and Meter("x").limit == 7
    assert work_limit() == 2500 and parse_work("12", "n") == 12


def test_chunks_cover_the_range_in_order_and_the_meter_stops_between_them():
    seen: list[tuple[int, int]] = []
    run_chunks(10_000, lambda lo, hi: seen.append((lo, hi)) or 0)
    assert seen[0] == (0, 16) and seen[-1][1] == 10_000
    assert all(a[1] == b[0] and a[0] < a[1] for a, b in zip(seen, seen[1:], strict=False))
    assert seen[1][1] - seen[1][0] == 32  # fast chunks double
    calls: list[int] = []
    with limit_work(100), pytest.raises(TooMuchWork, match="piles: over 100 elementary tests \\(112 done"):
        run_chunks(1000, lambda lo, hi: calls.append(lo) or 7 * (hi - lo), Meter("piles"))
    assert calls == [0]  # stopped after the first chunk (16 items, 112 tests)


def test_slow_chunks_shrink():
    sizes: list[int] = []

    def slow(lo: int, hi: int) -> int:
        sizes.append(hi - lo)
        time.sleep(0.6 if len(sizes) == 1 else 0.0)
        return 0

    run_chunks(100, slow)
    assert sizes[0] == 16 and sizes[1] < 16


@pytest.mark.parametrize("variant", ["intended", "literal"])
def test_piles_of_triangles_naive_equals_fast(variant):
    # Stacked copies of one triangle and turned copies (a pile every ray crosses), through the coarsened
    # grid: the fast engine's edges, steps and tallies are the naive loops'.
    rng = np.random.default_rng(2)
    tri = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    stacked = silcount.from_polygons(tri, [[0, 1, 2]] * 12, name="stacked")
    turned = []
    for k, a in enumerate(rng.uniform(0, 2 * np.pi, 10)):
        c, s = np.cos(a), np.sin(a)
        turned += [[x * c - y * s, x * s + y * c, 0.01 * k] for x, y, _ in tri - 0.3]
    fan = silcount.from_polygons(np.array(turned), [[3 * k, 3 * k + 1, 3 * k + 2] for k in range(10)], name="fan")
    for mesh in (stacked, fan):
        for light in (silcount.PointLight((0.2, 0.3, 2.0)), silcount.PointLight((3.0, -1.0, 0.5))):
            fast = silcount.detect(mesh, light, "eesd", variant, "fast")
            naive = silcount.detect(mesh, light, "eesd", variant, "naive")
            assert np.array_equal(fast.edge_ids, naive.edge_ids)
            assert fast.steps == naive.steps and fast.tally == naive.tally
            assert {k: v for k, v in fast.notes.items() if k != "rays_cast"} == naive.notes


DRIVER = (
    "import sys; from silcount.cli.main import main; print('ready', file=sys.stderr, flush=True); "
    "sys.exit(main(sys.argv[1:]))"
)


def sigint_as_in_a_terminal() -> None:
    """The child's SIGINT at its default, so that Python installs its handler: a test run started in the
    background (``cmd &``) has SIGINT ignored, which a child inherits, and then no Ctrl-C reaches it."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_ctrl_c_ends_an_audit_of_a_pile_within_seconds(tmp_path):
    # 8,000 turned copies of one triangle: EESD casts 384,000 rays, each through much of the pile, for
    # many seconds.  SIGINT two seconds after the command began (its imports done): the process ends
    # within a few seconds with one line, exit 130, no traceback.
    path = fan_obj(tmp_path / "fan.obj", 8000)
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parent.parent))
    cmd = [sys.executable, "-c", DRIVER, "audit", str(path), "--detectors", "eesd", "--quiet", "--format", "json"]
    proc = subprocess.Popen(
        cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, text=True, preexec_fn=sigint_as_in_a_terminal
    )
    try:
        assert proc.stderr is not None and proc.stderr.readline() == "ready\n"
        time.sleep(2.0)
        assert proc.poll() is None, "the audit ended before the signal: the test needs a bigger pile"
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        rest = proc.communicate(timeout=60)[1]
        took = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130 and took < 4.0, (proc.returncode, took)
    assert "Traceback" not in rest and rest.strip().splitlines() == ["silcount: interrupted"]
