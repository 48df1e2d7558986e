"""ASCII PLY files whose record lines carry more values than the header declares (issue 23), as MeshLab writes them.

VCGLIB (MeshLab, MeshMemory) declares a face's ``texcoord`` list and four ``uchar`` colour properties, then
writes the colour as a list (``4 r g b a``): one value per face line more than the header declares.  Read as
the specification's stream of numbers, every face after the first is misaligned; read one record a line, as
the file was written, the faces are the ones trimesh (an independent reader) finds.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from meshfiles import ply_bytes, write

from silcount.errors import UnreadableInput
from silcount.mesh.io import load_mesh
from silcount.mesh.model import from_polygons

# a unit cube, 8 vertices and 12 triangles wound outwards
CUBE_V = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
CUBE_T = np.array(
    [[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
     [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]]
)  # fmt: skip


def vcglib_ply(extra: list[int] | None = None, drop_last: int = 0, vertices=CUBE_V, faces=CUBE_T) -> bytes:
    """The cube (or ``vertices``, ``faces``) as VCGLIB writes an ASCII PLY with wedge texcoords and face colours.

    ``extra[i]``: how many values face line ``i`` carries past its declared properties (default: one each, the
    colour written as the list ``4 r g b a``); ``drop_last``: face lines cut off the end (a short body)."""
    extra = [1] * len(faces) if extra is None else extra
    head = [
        "ply", "format ascii 1.0", "comment VCGLIB generated",
        f"element vertex {len(vertices)}", "property float x", "property float y", "property float z",
        f"element face {len(faces)}", "property list uchar int vertex_indices", "property list uchar float texcoord",
        "property uchar red", "property uchar green", "property uchar blue", "property uchar alpha", "end_header",
    ]  # fmt: skip
    lines = [" ".join(repr(float(c)) for c in v) for v in vertices]
    for i, (f, k) in enumerate(zip(faces, extra)):
        uv = " ".join(f"{0.599829 - 0.0001 * i:g} {0.25 + 0.01 * j:g}" for j in range(3))
        colour = ["128", "64", "32", "255"] if k == 0 else (["4"] + ["128", "64", "32", "255"] + ["255"] * (k - 1))
        lines.append(f"3 {f[0]} {f[1]} {f[2]} 6 {uv} " + " ".join(colour))
    if drop_last:
        lines = lines[:-drop_last]
    return ("\n".join(head + lines) + "\n").encode()


def test_vcglib_face_lines_with_extra_values_load_with_one_warning(tmp_path):
    path = write(tmp_path, "cube.ply", vcglib_ply())
    m = load_mesh(path)
    want = from_polygons(CUBE_V, CUBE_T)
    assert np.array_equal(m.vertices, want.vertices)
    assert np.array_equal(m.face_start, want.face_start)
    assert np.array_equal(m.corners, want.corners)
    assert m.is_watertight
    assert len(m.load_warnings) == 1
    assert m.load_warnings[0].startswith(
        "ASCII PLY: 12 records carry 12 values past the properties the header declares"
    )
    assert "first: element 'face' record 0, line 24" in m.load_warnings[0]  # 15 header lines, 8 vertex lines


def test_a_thousand_face_vcglib_file_is_read_not_misaligned(tmp_path):
    # the shape of the issue's file: read as a stream, face 1 starts at face 0's alpha (255 indices), and the
    # reader stopped at a texture coordinate read as a list length ("list length 0.599829 is not a count")
    sphere = trimesh.creation.icosphere(subdivisions=3)
    v = np.asarray(sphere.vertices, dtype=np.float32).astype(float)
    f = np.asarray(sphere.faces)[:1000]
    path = write(tmp_path, "sphere.ply", vcglib_ply(vertices=v, faces=f))
    m = load_mesh(path)
    assert m.n_faces == 1000
    assert np.array_equal(m.vertices[m.corners.reshape(-1, 3)], v[f])
    assert m.load_warnings[0].startswith("ASCII PLY: 1000 records carry 1000 values past the properties")
    t = trimesh.load(path, process=False)
    assert np.array_equal(np.asarray(t.vertices)[np.asarray(t.faces)], v[f])


def test_vcglib_file_reads_as_trimesh_reads_it(tmp_path):
    path = write(tmp_path, "cube.ply", vcglib_ply())
    # trimesh splits each vertex per wedge texture coordinate (36 vertices); the corners' positions must agree
    t = trimesh.load(path, process=False)
    theirs = np.asarray(t.vertices)[np.asarray(t.faces)]
    assert theirs.shape == (12, 3, 3)
    assert np.array_equal(theirs, CUBE_V[CUBE_T])
    m = load_mesh(path)
    assert np.array_equal(m.vertices[m.corners.reshape(-1, 3)], theirs)


def test_extra_values_are_counted_per_value_and_per_record(tmp_path):
    extra = [0, 3, 0, 1, 0, 0, 2, 0, 0, 0, 0, 0]
    m = load_mesh(write(tmp_path, "cube.ply", vcglib_ply(extra)))
    assert np.array_equal(m.corners.reshape(-1, 3), CUBE_T)
    assert len(m.load_warnings) == 1
    assert "3 records carry 6 values past" in m.load_warnings[0]
    assert "first: element 'face' record 1, line 25" in m.load_warnings[0]


def test_records_on_their_own_lines_without_extras_load_silently(tmp_path):
    m = load_mesh(write(tmp_path, "cube.ply", vcglib_ply([0] * len(CUBE_T))))
    assert np.array_equal(m.corners.reshape(-1, 3), CUBE_T)
    assert m.load_warnings == ()


def test_the_stream_is_still_read_when_records_span_lines(tmp_path):
    # the specification's stream: line breaks anywhere, several records on one line
    data = ply_bytes(CUBE_V, CUBE_T, "ascii")
    head, body = data.split(b"end_header\n")
    tokens = body.split()
    body = b"\n".join(b" ".join(tokens[i : i + 5]) for i in range(0, len(tokens), 5)) + b"\n"
    m = load_mesh(write(tmp_path, "stream.ply", head + b"end_header\n" + body))
    assert np.array_equal(m.corners.reshape(-1, 3), CUBE_T)
    assert m.load_warnings == ()
    one_line = head + b"end_header\n" + b" ".join(tokens) + b"\n"
    m = load_mesh(write(tmp_path, "one.ply", one_line))
    assert np.array_equal(m.corners.reshape(-1, 3), CUBE_T)
    assert m.load_warnings == ()


@pytest.mark.parametrize("drop_last,done", [(1, 11), (5, 7), (12, 0)])
def test_a_short_body_with_extra_values_gets_the_strict_one_line_error(tmp_path, drop_last, done):
    path = write(tmp_path, "short.ply", vcglib_ply(drop_last=drop_last))
    with pytest.raises(UnreadableInput) as err:
        load_mesh(path)
    msg = str(err.value)
    assert msg == (
        f"{path}: truncated ASCII PLY: element 'face' ran short: the body ends after {done} of the 12 records "
        "the header promises"
    )
    assert "\n" not in msg


def test_a_last_line_cut_short_gets_the_strict_error(tmp_path):
    data = vcglib_ply()
    data = data[: data.rstrip().rindex(b" 6 ")] + b"\n"  # the last face line keeps only its vertex_indices
    with pytest.raises(UnreadableInput, match="element 'face' ran short: the body ends after 11 of the 12 records"):
        load_mesh(write(tmp_path, "cut.ply", data))


def test_a_short_plain_body_keeps_its_diagnosis(tmp_path):
    data = ply_bytes(CUBE_V, CUBE_T, "ascii")
    data = data[: data.rstrip().rindex(b"\n") + 1]
    with pytest.raises(UnreadableInput, match="element 'face' ran short: the body ends after 11 of the 12 records"):
        load_mesh(write(tmp_path, "short.ply", data))
