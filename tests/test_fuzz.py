"""Fuzzing the loaders and the CLI: any input ends in a Mesh or a SilcountError, never another exception.

Every crash hypothesis finds is fixed and its input kept in ``tests/regressions/``
(replayed by :func:`test_regressions_load_cleanly`).
"""

from __future__ import annotations

import io
import os
import tempfile
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from meshfiles import EXT, FMTS, tetra_bytes

from silcount import SilcountError, load_mesh
from silcount.cli.main import main
from silcount.mesh.model import Mesh

REGRESSIONS = Path(__file__).parent / "regressions"
FUZZ = settings(
    max_examples=int(os.environ.get("SILCOUNT_FUZZ_EXAMPLES", "60")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)


def _load_or_refuse(ext: str, data: bytes) -> Mesh | SilcountError:
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / f"fuzz{ext}"
        p.write_bytes(data)
        try:
            return load_mesh(p, max_memory=1 << 28)
        except SilcountError as exc:
            assert str(p) in str(exc), "the message names the file"
            assert "\n" not in str(exc), "one line"
            return exc


@st.composite
def mutated(draw, fmt: str) -> bytes:
    """A valid tetrahedron file with a few random byte edits, truncations or insertions."""
    data = bytearray(tetra_bytes(fmt))
    for _ in range(draw(st.integers(1, 4))):
        op = draw(st.sampled_from(("flip", "truncate", "insert", "delete")))
        i = draw(st.integers(0, max(len(data) - 1, 0)))
        if op == "flip" and data:
            data[i] = draw(st.integers(0, 255))
        elif op == "truncate":
            del data[i:]
        elif op == "insert":
            data[i:i] = draw(
                st.binary(min_size=1, max_size=8)
                | st.sampled_from(
                    [b"nan", b"-1", b"1e308", b"99999999999999999999", b" ", b"\n", b"\x00", b"f 1 2 3\n", b"inf"]
                )
            )
        elif data:
            del data[i : i + draw(st.integers(1, 16))]
    return bytes(data)


@pytest.mark.parametrize("ext", sorted(set(EXT.values()) | {".glb", ".gltf"}))
@FUZZ
@given(data=st.binary(max_size=400))
def test_random_bytes_never_crash_the_loader(ext, data):
    _load_or_refuse(ext, data)


@pytest.mark.parametrize("fmt", FMTS)
@FUZZ
@given(data=st.data())
def test_mutated_files_never_crash_the_loader(fmt, data):
    _load_or_refuse(EXT[fmt], data.draw(mutated(fmt)))


@settings(
    max_examples=int(os.environ.get("SILCOUNT_FUZZ_CLI_EXAMPLES", "25")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(fmt=st.sampled_from(FMTS), data=st.data(), light=st.text(alphabet="0123456789,.-eEinfa ", max_size=12))
def test_cli_never_shows_a_traceback(fmt, data, light):
    blob = data.draw(mutated(fmt))
    out, err_buf = io.StringIO(), io.StringIO()
    with tempfile.TemporaryDirectory() as d, redirect_stdout(out), redirect_stderr(err_buf):
        p = Path(d) / f"fuzz{EXT[fmt]}"
        p.write_bytes(blob)
        try:
            rc = main(
                [
                    "audit",
                    str(p),
                    "--light",
                    light,
                    "--random-lights",
                    "1",
                    "--detectors",
                    "reference",
                    "--format",
                    "json",
                    "--max-memory",
                    "256M",
                    "--quiet",
                ]
            )
        except SystemExit as exc:  # argparse's own one-line usage errors (e.g. "--light -E")
            rc = exc.code
    err = err_buf.getvalue()
    assert rc in (0, 2, 3, 4)
    assert (rc == 0) == (err == ""), err
    assert "Traceback" not in err and err.count("\n") <= 1


def test_regressions_load_cleanly():
    files = sorted(p for p in REGRESSIONS.iterdir() if p.is_file() and p.suffix != ".md")
    assert files, "the regression corpus is empty"
    for p in files:
        _load_or_refuse(p.suffix, p.read_bytes())
