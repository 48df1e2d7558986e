"""Each syntax of each specification that silcount reads, one test each, on small files written here.

Expected meshes come from :func:`silcount.mesh.model.from_polygons` on the vertex and face lists the file was
written from (the meshes are hand-sized: a tetrahedron, a quad cube, a hexagonal prism), so a reader that
misplaces one index fails.  The issue-12 table's rows are the tests marked ``# issue 12 table``.
"""

from __future__ import annotations

import struct

import numpy as np
import pytest
from meshfiles import TETRA_F, TETRA_V, obj_text, off_text, ply_bytes, tetra_bytes, write

from silcount.errors import InvalidMesh, UnreadableInput
from silcount.mesh.io import load_mesh
from silcount.mesh.model import Mesh, from_polygons

CUBE_V = [[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
CUBE_F = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
# a hexagonal prism: two hexagons and six quads (polygons of two sizes), closed, 12 vertices, 18 edges
_ANG = np.arange(6) * np.pi / 3
HEX_V = np.vstack([np.c_[np.cos(_ANG), np.sin(_ANG), np.zeros(6)], np.c_[np.cos(_ANG), np.sin(_ANG), np.ones(6)]])
HEX_F = [list(range(5, -1, -1)), list(range(6, 12))] + [[i, (i + 1) % 6, (i + 1) % 6 + 6, i + 6] for i in range(6)]


def same(a: Mesh, b: Mesh) -> None:
    assert np.array_equal(a.vertices, b.vertices)
    assert np.array_equal(a.face_start, b.face_start)
    assert np.array_equal(a.corners, b.corners)


def tetra() -> Mesh:
    return from_polygons(TETRA_V, TETRA_F)


def load(tmp_path, name: str, data: bytes | str) -> Mesh:
    return load_mesh(write(tmp_path, name, data))


# ---- OBJ ---------------------------------------------------------------------------------
def test_obj_continuation_line(tmp_path):  # issue 12 table
    text = obj_text(TETRA_V, TETRA_F).replace("f 1 2 3\n", "f 1 \\\n  2 \\\r\n 3\n")
    m = load(tmp_path, "cont.obj", text)
    same(m, tetra())
    assert m.load_warnings == ()


def test_obj_continuation_keeps_line_numbers_in_messages(tmp_path):
    text = "v 0 0 0\nf 1 \\\n 2 3\nv 1 x 0\n"
    with pytest.raises(UnreadableInput, match="line 4: coordinate 'x' is not a number"):
        load(tmp_path, "c.obj", text)


def test_obj_backslash_in_a_comment_does_not_continue(tmp_path):
    text = "# a path C:\\models\\\n" + obj_text(TETRA_V, TETRA_F)
    same(load(tmp_path, "c.obj", text), tetra())


def test_obj_negative_indices_are_relative_to_the_vertices_before_the_face(tmp_path):
    # each face written right after all four vertices: -4 is vertex 1, -1 vertex 4
    v = "".join(f"v {x} {y} {z}\n" for x, y, z in TETRA_V)
    f = "".join("f " + " ".join(str(i - 4) for i in face) + "\n" for face in TETRA_F)
    same(load(tmp_path, "neg.obj", v + f), tetra())
    # interleaved: a face after only three vertices uses -3..-1 for them
    text = "".join(f"v {x} {y} {z}\n" for x, y, z in TETRA_V[:3]) + "f -3 -2 -1\n"
    text += f"v {TETRA_V[3][0]} {TETRA_V[3][1]} {TETRA_V[3][2]}\nf 1 -1 2\nf 1 3 -1\nf 2 -1 3\n"
    same(load(tmp_path, "neg2.obj", text), tetra())


@pytest.mark.parametrize("form", ["{v}/{v}/{v}", "{v}//{v}", "{v}/{v}"])
def test_obj_vertex_texture_normal_forms(tmp_path, form):
    v = "".join(f"v {x} {y} {z}\n" for x, y, z in TETRA_V)
    v += "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvn 0 0 1\nvn 0 1 0\nvn 1 0 0\nvn 1 1 1\n"
    f = "".join("f " + " ".join(form.format(v=i + 1) for i in face) + "\n" for face in TETRA_F)
    same(load(tmp_path, "vtn.obj", v + f), tetra())


def test_obj_grouping_material_and_smoothing_statements_are_ignored(tmp_path):
    lines = obj_text(TETRA_V, TETRA_F).splitlines()
    text = "mtllib a.mtl\no thing\ng body\n" + "\n".join(lines[:4]) + "\nusemtl red\ns 1\n"
    text += "\n".join(lines[4:6]) + "\ng lid\ns off\nmg 1 0.5\n" + "\n".join(lines[6:]) + "\n"
    same(load(tmp_path, "groups.obj", text), tetra())


def test_obj_old_fo_statement_is_a_face(tmp_path):
    same(load(tmp_path, "fo.obj", obj_text(TETRA_V, TETRA_F).replace("f 1 2 3", "fo 1 2 3")), tetra())


@pytest.mark.parametrize(
    "body,words",
    [
        ("l 1 2\nl 2 3 4\np 1\n", ("2 line ('l')", "1 point ('p')")),
        ("p 1 2 3\n", ("1 point ('p')",)),
        ("cstype bspline\ndeg 3\ncurv 0.0 1.0 1 2 3 4\nparm u 0 0 0 0 1 1 1 1\nend\n", ("1 curve ('curv')",)),
    ],
)
def test_obj_line_and_point_elements_are_no_faces(tmp_path, body, words):
    text = "".join(f"v {x} {y} {z}\n" for x, y, z in TETRA_V) + body
    with pytest.raises(InvalidMesh, match="no faces") as err:
        load(tmp_path, "lp.obj", text)
    for w in words:
        assert w in str(err.value)


def test_obj_comments_anywhere_and_leading_blanks(tmp_path):
    lines = obj_text(TETRA_V, TETRA_F).splitlines()
    text = (
        "# header\n\n" + "\n".join(f"  \t{ln}   # note {i}" if i % 2 else ln for i, ln in enumerate(lines)) + "\n#end"
    )
    same(load(tmp_path, "comm.obj", text), tetra())


def test_obj_crlf(tmp_path):
    same(load(tmp_path, "crlf.obj", obj_text(TETRA_V, TETRA_F).replace("\n", "\r\n")), tetra())


def test_obj_polygons_of_any_size_are_kept(tmp_path):
    m = load(tmp_path, "hex.obj", obj_text(HEX_V, HEX_F))
    same(m, from_polygons(HEX_V, HEX_F))
    assert sorted(np.diff(m.face_start).tolist()) == [4] * 6 + [6, 6]
    assert (m.n_edges, m.is_watertight) == (18, True)


def test_obj_vertex_weights_and_colours_are_ignored(tmp_path):
    lines = obj_text(TETRA_V, TETRA_F).splitlines()
    lines[0] += " 1.0"
    lines[1] += " 0.5 0.5 0.5"
    same(load(tmp_path, "w.obj", "\n".join(lines)), tetra())


# ---- OFF ---------------------------------------------------------------------------------
def _off(keyword: str, per_vertex: str = "", per_face: str = "", counts_on_header: bool = False) -> str:
    head = f"{keyword} 4 4 0\n" if counts_on_header else f"{keyword}\n4 4 0\n"
    verts = "".join(f"{x} {y} {z}{per_vertex}\n" for x, y, z in TETRA_V)
    faces = "".join(f"3 {a} {b} {c}{per_face}\n" for a, b, c in TETRA_F)
    return head + verts + faces


@pytest.mark.parametrize(
    "keyword,per_vertex",
    [
        ("OFF", ""),
        ("COFF", " 255 0 0 255"),
        ("NOFF", " 0 0 1"),
        ("STOFF", " 0.5 0.5"),
        ("CNOFF", " 0 0 1 1 0 0 1"),
        ("STCNOFF", " 0 0 1 1 0 0 1 0.5 0.5"),
    ],
)
def test_off_header_keywords(tmp_path, keyword, per_vertex):
    same(load(tmp_path, "k.off", _off(keyword, per_vertex)), tetra())


def test_off_homogeneous_4off_divides_by_w(tmp_path):
    text = "4OFF\n4 4 0\n" + "".join(f"{2 * x} {2 * y} {2 * z} 2\n" for x, y, z in TETRA_V)
    text += "".join(f"3 {a} {b} {c}\n" for a, b, c in TETRA_F)
    same(load(tmp_path, "h.off", text), tetra())


def test_off_counts_on_the_header_line(tmp_path):
    same(load(tmp_path, "c.off", _off("OFF", counts_on_header=True)), tetra())


def test_off_modelnet_counts_glued_to_the_keyword(tmp_path):
    same(load(tmp_path, "g.off", _off("OFF", counts_on_header=True).replace("OFF 4", "OFF4", 1)), tetra())


def test_off_without_the_optional_keyword(tmp_path):
    same(load(tmp_path, "n.off", _off("OFF").split("\n", 1)[1]), tetra())


def test_off_header_after_leading_whitespace_and_comments(tmp_path):  # issue 12 table
    same(load(tmp_path, "lead.off", "# made by hand\n\n   \t" + _off("OFF")), tetra())


def test_off_comments_and_blank_lines_anywhere(tmp_path):
    lines = _off("OFF").splitlines()
    text = "\n\n".join(f"{ln}  # {i}" if i % 3 else f"# line {i}\n{ln}" for i, ln in enumerate(lines))
    same(load(tmp_path, "cb.off", text.replace("\n", "\r\n")), tetra())


@pytest.mark.parametrize("colour", [" 255 0 0", " 1.0 0.0 0.0 0.5", " 3", ""])
def test_off_colours_after_face_records(tmp_path, colour):
    same(load(tmp_path, "fc.off", _off("OFF", per_face=colour)), tetra())


def test_off_records_split_over_lines(tmp_path):
    # the spec's token stream: vertices two numbers per line, faces broken after the count; colours still end a line
    nums = " ".join(str(x) for x in TETRA_V.reshape(-1)).split()
    verts = "\n".join(" ".join(nums[i : i + 2]) for i in range(0, len(nums), 2))
    faces = "".join(f"3\n{a} {b}\n{c} 255 0 0\n" for a, b, c in TETRA_F)
    same(load(tmp_path, "split.off", f"OFF\n4 4\n0\n{verts}\n{faces}"), tetra())


def test_off_all_on_one_line_is_the_token_stream(tmp_path):
    text = "OFF 4 4 0 " + " ".join(str(x) for x in TETRA_V.reshape(-1)) + "\n"
    text += "".join(f"3 {a} {b} {c}\n" for a, b, c in TETRA_F)
    same(load(tmp_path, "one.off", text), tetra())


def test_off_polygons_kept(tmp_path):
    same(load(tmp_path, "hex.off", off_text(HEX_V, HEX_F)), from_polygons(HEX_V, HEX_F))


_PAD = "#" * 80 + "\n"  # a comment, so that the header's counts fit in the file and the body is read


@pytest.mark.parametrize(
    "text,words",
    [
        ("OFF BINARY\n", "binary OFF"),
        ("nOFF\n4\n1 1 0\n0 0 0 0\n", "4-dimensional"),
        ("OFF\n4 4 0\n1 1 1\n1 -1 -1\n" + _PAD, "ends after 2 vertices"),
        (_off("OFF").rsplit("\n", 3)[0] + _PAD, "ends after 2 faces"),
        ("OFF\n4 4 0\n" + "0 0 0\n" * 4 + "3 0 1\n" + _PAD, "ends inside face 0"),
    ],
)
def test_off_refused_on_purpose_or_truncated(tmp_path, text, words):
    with pytest.raises(UnreadableInput, match=words):
        load(tmp_path, "bad.off", text)


# ---- PLY ---------------------------------------------------------------------------------
PLY_FORMATS = ("ascii", "binary_little_endian", "binary_big_endian")


@pytest.mark.parametrize("fmt", PLY_FORMATS)
@pytest.mark.parametrize(
    "count_type,index_type",
    [("uchar", "int"), ("int", "uint"), ("ushort", "short"), ("uint8", "int32"), ("char", "uint16"), ("uint", "int8")],
)
def test_ply_formats_and_list_types(tmp_path, fmt, count_type, index_type):
    data = ply_bytes(TETRA_V, TETRA_F, fmt, count_type, index_type)
    same(load(tmp_path, "t.ply", data), tetra())


@pytest.mark.parametrize("fmt", PLY_FORMATS)
@pytest.mark.parametrize("coord_type", ["float", "double", "short", "int8"])
def test_ply_coordinate_types_and_extra_properties(tmp_path, fmt, coord_type):
    data = ply_bytes(TETRA_V, TETRA_F, fmt, coord_type=coord_type, extra_vertex=True, extra_face=True)
    same(load(tmp_path, "x.ply", data), tetra())


@pytest.mark.parametrize("fmt", PLY_FORMATS)
def test_ply_polygons_of_two_sizes_are_kept(tmp_path, fmt):
    m = load(tmp_path, "hex.ply", ply_bytes(HEX_V, HEX_F, fmt, coord_type="double", extra_face=True))
    same(m, from_polygons(HEX_V, HEX_F))
    assert m.n_edges == 18


@pytest.mark.parametrize("fmt", PLY_FORMATS)
def test_ply_tristrips(tmp_path, fmt):  # issue 12 table
    # one strip 0 1 2 3 0 1 gives (0,1,2) (2,1,3) (2,3,0) (0,3,1): the tetrahedron, consistently wound
    m = load(tmp_path, "s.ply", ply_bytes(TETRA_V, [], fmt, index_type="int", strips=[[0, 1, 2, 3, 0, 1]]))
    same(m, from_polygons(TETRA_V, [[0, 1, 2], [2, 1, 3], [2, 3, 0], [0, 3, 1]]))
    assert m.is_watertight
    # the same faces as two strips in one record (restart -1) and as two records
    for strips in ([[0, 1, 2, 3, -1, 2, 3, 0, 1]], [[0, 1, 2, 3], [2, 3, 0, 1]]):
        m2 = load(tmp_path, "s2.ply", ply_bytes(TETRA_V, [], fmt, index_type="int", strips=strips))
        same(m2, from_polygons(TETRA_V, [[0, 1, 2], [2, 1, 3], [2, 3, 0], [0, 3, 1]]))


def test_ply_tristrips_with_unsigned_indices_restart_at_the_type_maximum(tmp_path):
    strips = [[0, 1, 2, 3, 0xFFFF, 2, 3, 0, 1]]
    m = load(tmp_path, "u.ply", ply_bytes(TETRA_V, [], "binary_little_endian", index_type="ushort", strips=strips))
    same(m, from_polygons(TETRA_V, [[0, 1, 2], [2, 1, 3], [2, 3, 0], [0, 3, 1]]))


@pytest.mark.parametrize("fmt", PLY_FORMATS)
@pytest.mark.parametrize("with_face_element", [False, True])
def test_ply_point_cloud_is_no_faces_not_truncated(tmp_path, fmt, with_face_element):  # issue 12 table
    data = (
        ply_bytes(TETRA_V, [], fmt)
        if with_face_element
        else ply_bytes(TETRA_V, [], fmt).replace(b"element face 0\nproperty list uchar int vertex_indices\n", b"")
    )
    with pytest.raises(InvalidMesh, match="no faces: a point cloud: 4 vertices") as err:
        load(tmp_path, "pc.ply", data)
    assert "truncated" not in str(err.value)


@pytest.mark.parametrize("fmt", ["binary_little_endian", "binary_big_endian"])
def test_ply_truncated_binary_names_the_element(tmp_path, fmt):
    data = ply_bytes(HEX_V, HEX_F, fmt, coord_type="double")
    with pytest.raises(UnreadableInput, match="element 'face' ran short: the body ends after 7 of the 8 records"):
        load(tmp_path, "t.ply", data[:-3])
    with pytest.raises(UnreadableInput, match="element 'vertex' ran short"):
        load(tmp_path, "t.ply", data[: data.index(b"end_header\n") + 11 + 12 * 24 - 10])  # 12 doubles x, y, z


def test_ply_truncated_ascii_names_the_element(tmp_path):
    data = ply_bytes(HEX_V, HEX_F, "ascii")
    with pytest.raises(
        UnreadableInput, match="truncated ASCII PLY: element 'face' ran short: the body ends after 7 of the 8"
    ):
        load(tmp_path, "t.ply", data[: data.rindex(b"\n4 ") + 5])


@pytest.mark.parametrize(
    "change,words",
    [
        ((b"format ascii 1.0", b"format ascii 1.0\nproperty float w"), "a property before any element"),
        ((b"property float x", b"property int64 x"), "malformed line"),
        ((b"3 0 1 2", b"3 0 1.5 2"), "is not an integer"),
        ((b"3 0 1 2", b"3 0 one 2"), "'one' is not a number"),
    ],
)
def test_ply_corrupt(tmp_path, change, words):
    data = ply_bytes(TETRA_V, TETRA_F, "ascii").replace(*change)
    with pytest.raises(UnreadableInput, match=words):
        load(tmp_path, "c.ply", data)


# ---- STL ---------------------------------------------------------------------------------
@pytest.mark.parametrize("fmt", ["stl", "stl_bin"])
def test_stl_ascii_and_binary(tmp_path, fmt):
    same(load(tmp_path, "t.stl", tetra_bytes(fmt)), tetra())


def test_binary_stl_whose_header_starts_with_solid(tmp_path):
    data = tetra_bytes("stl_bin")
    data = b"solid exported by a CAD tool".ljust(80, b" ") + data[80:]
    same(load(tmp_path, "s.stl", data), tetra())


def test_ascii_stl_with_two_solids_and_upper_case_keywords(tmp_path):
    def facets(faces, up: bool) -> str:
        out = ""
        for f in faces:
            corners = "".join(f"   vertex {x} {y} {z}\n" for x, y, z in TETRA_V[f])
            out += f" facet normal 0 0 0\n  outer loop\n{corners}  endloop\n endfacet\n"
        return out.upper() if up else out

    text = (
        "solid a\n" + facets(TETRA_F[:2], False) + "endsolid a\nSOLID B\n" + facets(TETRA_F[2:], True) + "ENDSOLID B\n"
    )
    same(load(tmp_path, "two.stl", text), tetra())


def test_stl_binary_truncated(tmp_path):
    with pytest.raises(UnreadableInput, match="promises 4 triangles"):
        load(tmp_path, "t.stl", tetra_bytes("stl_bin")[:-7])


def test_stl_zero_facets_is_no_faces(tmp_path):
    with pytest.raises(InvalidMesh, match="no faces"):
        load(tmp_path, "z.stl", struct.pack("<80sI", b"binary", 0))
