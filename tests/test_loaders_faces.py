"""A bad face is not a bad file; a bad file is diagnosed exactly (issue 12).

The rows of the issue's table go through the CLI (exit code, one stderr line naming the file); the bad-face
rules through :func:`silcount.mesh.formats.common.clean_faces` and the audit's JSON warnings.
"""

from __future__ import annotations

import io
import json
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
import pytest
from meshfiles import TETRA_F, TETRA_V, obj_text, off_text, ply_bytes, write

from silcount.cli.main import main
from silcount.errors import InvalidMesh
from silcount.mesh.io import load_mesh
from silcount.mesh.model import from_polygons

V4 = "".join(f"v {x} {y} {z}\n" for x, y, z in TETRA_V)


def cli(path, *extra: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    argv = ["audit", str(path), "--detectors", "reference", "--random-lights", "1", "--quiet", "--format", "json"]
    with redirect_stdout(out), redirect_stderr(err):
        rc = main(argv + list(extra))
    return rc, out.getvalue(), err.getvalue()


def refused(path, code: int) -> str:
    rc, out, err = cli(path)
    assert (rc, out) == (code, ""), err
    assert err.count("\n") == 1 and str(path) in err and "Traceback" not in err
    return err


# ---- the table, through the CLI ----------------------------------------------------
def test_table_obj_continuation_line_loads(tmp_path):
    rc, out, err = cli(write(tmp_path, "c.obj", V4 + "f 1 2 \\\n 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n"))
    assert (rc, err) == (0, "")
    assert json.loads(out)["mesh"]["faces"] == 4


def test_table_off_with_leading_whitespace_and_comments_loads(tmp_path):
    rc, out, err = cli(write(tmp_path, "l.off", "# by hand\n  " + off_text(TETRA_V, TETRA_F)))
    assert (rc, err) == (0, "")
    assert json.loads(out)["mesh"]["watertight"] is True


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian"])
def test_table_ply_point_cloud_is_no_faces_exit_4(tmp_path, fmt):
    err = refused(write(tmp_path, "pc.ply", ply_bytes(TETRA_V, [], fmt)), 4)
    assert "no faces: a point cloud" in err and "truncated" not in err


def test_table_ply_tristrips_load(tmp_path):
    rc, out, err = cli(
        write(tmp_path, "s.ply", ply_bytes(TETRA_V, [], "binary_little_endian", strips=[[0, 1, 2, 3, 0, 1]]))
    )
    assert (rc, err) == (0, "")
    assert json.loads(out)["mesh"]["faces"] == 4


def test_table_obj_two_vertex_face_among_good_faces_is_dropped_with_a_warning(tmp_path):
    rc, out, err = cli(write(tmp_path, "two.obj", obj_text(TETRA_V, TETRA_F) + "f 1 2\n"))
    assert (rc, err) == (0, "")
    doc = json.loads(out)
    assert doc["mesh"]["faces"] == 4 and doc["mesh"]["watertight"] is True
    assert doc["warnings"] == ["dropped 1 face with fewer than 3 distinct vertices (first: line 9)"]


# ---- the bad-face rules ------------------------------------------------------------------
def test_each_kind_of_bad_face_is_counted_once(tmp_path):
    text = obj_text(TETRA_V, TETRA_F) + "f 1 2 5\nf 1 2 9\nf 3 3 3\nf 1 2 2\nf 1 2 1 3\nf 1 2 3 1 4 2\n"
    m = load_mesh(write(tmp_path, "bad.obj", text))
    assert m.n_faces == 4
    assert m.load_warnings == (
        "dropped 2 faces indexing a missing vertex (first: line 9, vertex 5; the file has 4 vertices)",
        "dropped 2 faces with fewer than 3 distinct vertices (first: line 11)",
        "dropped 2 faces visiting a vertex twice (first: line 13)",
    )


def test_a_vertex_repeated_in_a_row_is_read_once(tmp_path):
    # a triangle written as a quad (1 2 3 3), and one whose repeat wraps around (1 1 2 3 ... last 1)
    text = V4 + "f 1 2 3 3\nf 1 1 4 2\nf 1 3 4 1\nf 2 4 3\n"
    m = load_mesh(write(tmp_path, "rep.obj", text))
    ref = from_polygons(TETRA_V, TETRA_F)
    assert np.array_equal(m.corners, ref.corners) and np.array_equal(m.face_start, ref.face_start)
    assert m.load_warnings == (
        "3 faces repeating a vertex in a row, read as the polygon of their distinct corners (first: line 5)",
    )


@pytest.mark.parametrize(
    "name,data,words",
    [
        ("all.obj", V4 + "f 1 2\nf 1 9 2\n", ["1 face indexing a missing vertex", "1 face with fewer than 3 distinct"]),
        ("all.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n2 0 1\n", ["2 faces with fewer than 3 distinct"]),
    ],
)
def test_a_file_with_no_usable_face_is_refused_saying_why(tmp_path, name, data, words):
    with pytest.raises(InvalidMesh, match="no usable face") as exc:
        load_mesh(write(tmp_path, name, data))
    for w in words:
        assert w in str(exc.value)


def test_the_audit_reports_the_loader_warnings_with_its_own(tmp_path):
    rc, out, err = cli(write(tmp_path, "w.obj", obj_text(TETRA_V, TETRA_F[:3]) + "f 1 2 7\n"))
    assert rc == 0
    warnings = json.loads(out)["warnings"]
    assert warnings[0].startswith("dropped 1 face indexing a missing vertex")
    assert any(w.startswith("open mesh: 3 boundary edges") for w in warnings)
    rc, text, _ = cli(write(tmp_path, "w.obj", obj_text(TETRA_V, TETRA_F[:3]) + "f 1 2 7\n"), "--format", "text")
    assert "- dropped 1 face indexing a missing vertex" in text


# ---- no message shows Python's own exception text -----------------------------------------
@pytest.mark.parametrize(
    "name,data",
    [
        ("a.obj", V4 + "f 1 2 \\"),
        ("b.obj", "v 1 2 3e\nf 1 1 1\n"),
        ("c.obj", V4 + "f 1 2 3.5\n"),
        ("d.obj", V4 + "f 1/2 /3 4\n"),
        ("e.off", "OFF\n4 x 0\n" + "0 0 0\n" * 4 + "3 0 1 2\n"),
        ("f.off", "OFF\n4 1 0\n" + "0 0 z\n" * 4 + "3 0 1 2\n" + "#" * 40),
        ("g.ply", ply_bytes(TETRA_V, TETRA_F).replace(b"element vertex 4", b"element vertex four")),
        ("h.ply", ply_bytes(TETRA_V, TETRA_F).replace(b"3 0 1 2", b"3 0 1 2e")),
        ("i.glb", b"glTF\x02\x00\x00\x00" + b"\xff" * 40),
    ],
)
def test_no_message_shows_python_exception_text(tmp_path, name, data):
    err = refused(write(tmp_path, name, data), 3)
    for leak in ("invalid literal", "could not convert", "unpack", "Errno", "object", "index out of", "Expecting"):
        assert leak not in err, err
