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

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from meshfiles import EXT, FMTS, TETRA_F, TETRA_V, ply_bytes, tetra_bytes

from silcount import SilcountError, load_mesh
from silcount.cli.main import main
from silcount.errors import InvalidMesh
from silcount.mesh.formats import obj
from silcount.mesh.formats.strips import decode_strips
from silcount.mesh.model import Mesh, from_polygons

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


# the new syntaxes of issue 12, as seeds for mutation: continuation lines, strips, point clouds, split OFF records
_V = "".join(f"v {x} {y} {z}\n" for x, y, z in TETRA_V)
SEEDS = {
    "obj_cont": (".obj", (_V + "".join(f"f {a + 1} \\\n {b - 4}/1 \\\r\n{c + 1}//2\n" for a, b, c in TETRA_F)).encode(
    )),
    "ply_strips": (".ply", ply_bytes(TETRA_V, [], "ascii", strips=[[0, 1, 2, 3, -1, 2, 3, 0, 1]])),
    "ply_strips_bin": (".ply", ply_bytes(TETRA_V, [], "binary_big_endian", "int", "int", strips=[[0, 1, 2, 3, 0, 1]])),
    "ply_cloud": (".ply", ply_bytes(TETRA_V, [], "ascii", extra_vertex=True)),
    "ply_cloud_bin": (".ply", ply_bytes(TETRA_V, [], "binary_little_endian", extra_vertex=True)),
    "off_split": (".off", b"COFF 4 4\n0\n" + b"\n".join(b"%g %g\n%g 1 0 0 1" % tuple(v) for v in TETRA_V) + b"\n"
                  + b"".join(b"3\n%d %d %d 255 0 0\n" % tuple(f) for f in TETRA_F)),
}  # fmt: skip


@st.composite
def mutated(draw, fmt: str) -> bytes:
    """A valid tetrahedron file (or a seed of :data:`SEEDS`) with a few random byte edits, truncations or insertions."""
    data = bytearray(SEEDS[fmt][1] if fmt in SEEDS else tetra_bytes(fmt))
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


@pytest.mark.parametrize("seed", sorted(SEEDS))
@FUZZ
@given(data=st.data())
def test_mutated_new_syntax_never_crashes_the_loader(seed, data):
    _load_or_refuse(SEEDS[seed][0], data.draw(mutated(seed)))


def test_the_seeds_are_valid():
    tetra = from_polygons(TETRA_V, TETRA_F)
    for name, (ext, blob) in SEEDS.items():
        got = _load_or_refuse(ext, blob)
        if "cloud" in name:
            assert isinstance(got, InvalidMesh) and "no faces: a point cloud" in str(got)
        else:
            assert isinstance(got, Mesh) and got.n_faces == 4 and got.n_edges == tetra.n_edges, (name, got)


# ---- one mesh in random but valid syntax always reads the same -------------------------------
@st.composite
def obj_syntax(draw) -> str:
    """The tetrahedron as OBJ, each statement in a random legal form: relative or absolute indices, v/vt/vn
    forms, continuation lines, comments, blank and ignored lines, leading blanks, CRLF or LF."""
    end = draw(st.sampled_from(["\n", "\r\n"]))
    out, nv = [], 0
    order = draw(st.permutations(list(range(4))))
    faces = [f for f in TETRA_F.tolist()]
    pending = list(order)
    while pending or faces:
        ready = [f for f in faces if all(i in order[:nv] for i in f)]
        if pending and (not ready or draw(st.booleans())):
            i = pending.pop(0)
            x, y, z = TETRA_V[i].tolist()
            out.append(f"v {x!r} {y!r} {z!r}" + draw(st.sampled_from(["", " 1.0", " 0.2 0.3 0.4"])))
            nv += 1
            continue
        f = ready[0]
        faces.remove(f)
        toks = []
        for i in f:
            pos = order.index(i) + 1
            ref = str(pos if draw(st.booleans()) else pos - nv - 1)
            toks.append(draw(st.sampled_from(["{}", "{}/1", "{}//1", "{}/1/1"])).format(ref))
        line = "f"
        for t in toks:
            line += draw(st.sampled_from([" ", "  ", "\t", " \\" + end, " \\  " + end + "  "])) + t
        out.append(line)
    lines = []
    for ln in out:
        for _ in range(draw(st.integers(0, 2))):
            lines.append(
                draw(st.sampled_from(["", "# comment \\", "g part", "s 1", "usemtl m", "vt 0 0", "vn 0 0 1", "o x"]))
            )
        lines.append(draw(st.sampled_from(["", " ", "\t"])) + ln + draw(st.sampled_from(["", "  # note", " "])))
    return end.join(lines) + draw(st.sampled_from(["", end]))


@FUZZ
@given(text=obj_syntax())
def test_obj_syntax_variants_read_the_same_and_both_readers_agree(text):
    got = _load_or_refuse(".obj", text.encode())
    ref = from_polygons(TETRA_V, TETRA_F)
    assert isinstance(got, Mesh), got
    assert np.array_equal(got.vertices, ref.vertices) and got.n_faces == 4 and got.is_watertight
    lines = obj.logical_lines(text)
    fast, slow = obj._read_fast(lines), obj._read_slow(Path("x.obj"), lines)
    if fast is not None:
        for a, b in ((fast.vertices, slow.vertices), (fast.sizes, slow.sizes), (fast.corners, slow.corners)):
            assert np.array_equal(a, b)
        assert [fast.where(i) for i in range(4)] == [slow.where(i) for i in range(4)]


def _strips_reference(strips: list[int], restart: int) -> list[tuple[int, int, int]]:
    """Triangle strips decoded one triangle at a time (a second implementation for decode_strips)."""
    out, run = [], []
    for v in strips + [restart]:
        if v == restart:
            for j in range(len(run) - 2):
                t = (run[j], run[j + 1], run[j + 2]) if j % 2 == 0 else (run[j + 1], run[j], run[j + 2])
                if len(set(t)) == 3:
                    out.append(t)
            run = []
        else:
            run.append(v)
    return out


@FUZZ
@given(records=st.lists(st.lists(st.integers(-1, 6), max_size=12), min_size=1, max_size=4))
def test_strips_decode_as_one_triangle_at_a_time(records):
    counts = np.array([len(r) for r in records])
    flat = np.array([v for r in records for v in r], dtype=np.int64)
    got = [tuple(t) for t in decode_strips(flat, counts).tolist()]
    want = [t for r in records for t in _strips_reference(r, -1)]
    assert got == want


@FUZZ
@given(
    n=st.integers(1, 30),
    fmt=st.sampled_from(["ascii", "binary_little_endian", "binary_big_endian"]),
    extra=st.booleans(),
    face_element=st.booleans(),
    seed=st.integers(0, 2**16),
)
def test_point_clouds_are_no_faces(n, fmt, extra, face_element, seed):
    pts = np.random.default_rng(seed).normal(size=(n, 3)).astype(np.float32).astype(float)
    blob = ply_bytes(pts, [], fmt, extra_vertex=extra)
    if not face_element:
        blob = blob.replace(b"element face 0\nproperty list uchar int vertex_indices\n", b"")
    got = _load_or_refuse(".ply", blob)
    assert isinstance(got, InvalidMesh) and f"no faces: a point cloud: {n} vertices" in str(got)


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
