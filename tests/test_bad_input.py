"""Bad input, case by case: one line on stderr naming the file and the problem, a documented exit code
(2 bad arguments, 3 unreadable input, 4 invalid mesh), no traceback, no half-written output.
Dubious but usable meshes and lights are audited, with warnings in the report (exit 0).

Every bad file is generated here, in tmp_path.
"""

from __future__ import annotations

import json
import struct
import subprocess
import sys
from pathlib import Path

import pytest
from common import run_cli
from meshfiles import TETRA_F, TETRA_V, obj_text, tetra_bytes, write

from silcount.atomic import write_text

QUAD_CUBE_V = [[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
QUAD_CUBE_F = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]


def audit(path: Path, *extra: str) -> tuple[int, str, str]:
    return run_cli("audit", str(path), "--detectors", "reference", "--random-lights", "2", "--quiet", *extra)


def assert_refused(path: Path, code: int, *words: str, extra: tuple[str, ...] = ()) -> str:
    """Exit ``code``, nothing on stdout, one stderr line naming the file and containing each of ``words``."""
    rc, out, err = audit(path, *extra)
    assert rc == code, err
    assert out == ""
    assert err.count("\n") == 1 and err.endswith("\n"), err
    assert "Traceback" not in err
    assert str(path) in err, err
    for w in words:
        assert w in err, err
    return err


def audit_json(path: Path, *extra: str) -> dict:
    rc, out, err = audit(path, "--format", "json", *extra)
    assert rc == 0, err
    return json.loads(out)


# ---- unreadable input: exit 3 ------------------------------------------------------------
def test_missing_file(tmp_path):
    assert_refused(tmp_path / "nope.obj", 3, "no such file")


def test_directory(tmp_path):
    d = tmp_path / "dir.obj"
    d.mkdir()
    assert_refused(d, 3, "directory")


def test_empty_file(tmp_path):
    assert_refused(write(tmp_path, "e.obj", b""), 3, "empty")


def test_unknown_extension(tmp_path):
    assert_refused(write(tmp_path, "m.xyz", tetra_bytes("obj")), 3, "unknown extension")


@pytest.mark.parametrize(
    "name,data,word",
    [
        ("corrupt.obj", "v 1 2 x\nf 1 2 3\n", "line 1"),
        ("trunc.off", "OFF\n4 4 0\n1 1 1\n1 -1 -1\n", "promises 4 vertices and 4 faces"),
        ("trunc.stl", tetra_bytes("stl")[:-40], "ASCII STL"),
        ("trunc2.stl", b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 1 2 3\n", "truncated ASCII STL"),
        ("corrupt.stl", b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 1 2\n", "vertex needs 3 coordinates"),
        ("trunc_bin.stl", tetra_bytes("stl_bin")[:-7], "promises 4 triangles"),
        ("short_bin.stl", b"\x01" * 50, "truncated STL"),
        ("trunc_bin.ply", tetra_bytes("ply_bin")[:-10], "truncated binary PLY"),
        ("nomagic.ply", b"plx\nformat ascii 1.0\nend_header\n", "not a PLY file"),
        ("badformat.ply", tetra_bytes("ply").replace(b"format ascii", b"format weird"), "unknown format"),
        ("trunc.ply", tetra_bytes("ply")[:-30], "truncated ASCII PLY: element 'face' ran short"),
    ],
)
def test_truncated_or_corrupt_files(tmp_path, name, data, word):
    assert_refused(write(tmp_path, name, data), 3, word)


@pytest.mark.parametrize(
    "name,data,word",
    [
        ("png.obj", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(40), "binary data"),
        ("readme.obj", "# Title\n\nSome prose about meshes.\n", "no vertex ('v') or face ('f') statements"),
        ("json.off", '{"not": "a mesh"}\n', "no OFF header"),
        ("text.ply", "hello\n", "not a PLY file"),
        (
            "text.stl",
            "hello world, this is not an STL file at all; it is long enough to look binary" * 2,
            "corrupt or truncated binary STL",
        ),
    ],
)
def test_a_file_that_is_not_a_mesh(tmp_path, name, data, word):
    assert_refused(write(tmp_path, name, data), 3, word)


# ---- invalid mesh: exit 4 ----------------------------------------------------------------
@pytest.mark.parametrize("bad", ["nan", "inf", "-inf"])
def test_nan_or_inf_coordinates(tmp_path, bad):
    text = obj_text(TETRA_V, TETRA_F).replace("v 1.0 1.0 1.0", f"v 1.0 {bad} 1.0")
    assert_refused(write(tmp_path, "nan.obj", text), 4, "NaN or Inf")


def test_nan_in_binary_stl(tmp_path):
    data = bytearray(tetra_bytes("stl_bin"))
    data[84 + 12 : 84 + 16] = struct.pack("<f", float("nan"))  # first vertex x of the first triangle
    assert_refused(write(tmp_path, "nan.stl", bytes(data)), 4, "NaN or Inf")


@pytest.mark.parametrize(
    "name,data,where",
    [
        ("idx.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4, vertex 4"),
        ("neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "line 4, vertex -4"),
        ("idx.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "face 0, vertex 3"),
    ],
)
def test_a_file_whose_only_face_indexes_a_missing_vertex_is_refused(tmp_path, name, data, where):
    assert_refused(write(tmp_path, name, data), 4, "no usable face", "missing vertex", where, "the file has 3 vertices")


def test_faces_index_missing_vertices_in_ply_are_dropped_with_a_warning(tmp_path):
    text = tetra_bytes("ply").decode().replace("3 1 3 2", "3 1 3 7")
    doc = audit_json(write(tmp_path, "idx.ply", text))
    assert doc["mesh"]["faces"] == 3
    assert (
        "dropped 1 face indexing a missing vertex (first: face 3, vertex 7; the file has 4 vertices)" in doc["warnings"]
    )


def test_a_truncated_obj_face_is_dropped_not_the_file(tmp_path):
    # OBJ has no counts: a file cut inside its last face ("f 2 ") is a file with one bad face
    doc = audit_json(write(tmp_path, "trunc.obj", obj_text(TETRA_V, TETRA_F)[:-4]))
    assert doc["mesh"]["faces"] == 3
    assert "dropped 1 face with fewer than 3 distinct vertices (first: line 8)" in doc["warnings"]


@pytest.mark.parametrize(
    "name,data",
    [
        ("verts.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
        ("zero.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"),
        ("zero.stl", struct.pack("<80sI", b"binary", 0)),
    ],
)
def test_zero_faces(tmp_path, name, data):
    assert_refused(write(tmp_path, name, data), 4, "no faces")


def test_every_face_degenerate(tmp_path):
    assert_refused(write(tmp_path, "deg.obj", "v 0 0 0\nv 1 0 0\nv 0 0 0\nf 1 2 3\n"), 4, "degenerate")


def test_too_large_for_memory_refused_early_with_the_estimate(tmp_path, monkeypatch):
    p = write(tmp_path, "big.obj", tetra_bytes("obj"))
    err = assert_refused(p, 4, "too large", "4 faces", extra=("--max-memory", "1K"))
    # by hand: 4 vertices x 512 B + 4 faces x 1 KiB = 6144 B, against 1024 B (it said "0.0 MiB" of both)
    assert "need about 6.0 KiB, over the limit of 1.0 KiB" in err
    monkeypatch.setenv("SILCOUNT_MAX_MEMORY", "2K")
    assert_refused(p, 4, "too large")
    monkeypatch.setenv("SILCOUNT_MAX_MEMORY", "64M")
    assert audit(p)[0] == 0


def test_too_large_binary_stl_refused_from_its_header_alone(tmp_path):
    # 10 million triangles promised in the header, and exactly that many bytes: a sparse file, never parsed
    n = 10_000_000
    p = tmp_path / "huge.stl"
    with open(p, "wb") as fh:
        fh.write(struct.pack("<80sI", b"binary", n))
        fh.truncate(84 + 50 * n)
    assert_refused(p, 4, "too large", f"{n} faces", extra=("--max-memory", "1G"))


def test_too_large_ply_refused_from_its_header(tmp_path):
    head = (
        b"ply\nformat binary_little_endian 1.0\nelement vertex 500000\nproperty float x\nproperty float y\n"
        b"property float z\nelement face 1000000\nproperty list uchar int vertex_indices\nend_header\n"
    )
    p = tmp_path / "huge.ply"
    with open(p, "wb") as fh:  # a sparse file exactly as long as the header's counts need
        fh.write(head)
        fh.truncate(len(head) + 500000 * 12 + 1000000 * 13)
    assert_refused(p, 4, "too large", "1000000 faces", extra=("--max-memory", "100M"))


@pytest.mark.parametrize(
    "name,data",
    [
        ("lying.off", "OFF\n999999999 1 0\n0 0 0\n"),
        (
            "lying.ply",
            b"ply\nformat ascii 1.0\nelement vertex 50000000\nproperty float x\nproperty float y\n"
            b"property float z\nelement face 100000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
        ),
    ],
)
def test_header_counts_that_cannot_fit_in_the_file_are_corrupt_not_large(tmp_path, name, data):
    assert_refused(write(tmp_path, name, data), 3, "more than a")


# ---- bad arguments: exit 2 ---------------------------------------------------------------
@pytest.mark.parametrize("value", ["1,2", "a,b,c", "1,2,3,4", "", "nan,0,0", "1;2;3"])
def test_malformed_light(tmp_path, value):
    p = write(tmp_path, "t.obj", tetra_bytes("obj"))
    rc, out, err = run_cli("audit", str(p), "--light", value)
    assert rc == 2 and out == "" and err.count("\n") == 1 and "--light" in err and "X,Y,Z" in err


def test_zero_direction(tmp_path):
    p = write(tmp_path, "t.obj", tetra_bytes("obj"))
    rc, out, err = run_cli("audit", str(p), "--directional", "0,0,0")
    assert rc == 2 and out == "" and err.count("\n") == 1 and "zero vector" in err


def test_unknown_detector_and_bad_memory_size(tmp_path):
    p = write(tmp_path, "t.obj", tetra_bytes("obj"))
    assert run_cli("audit", str(p), "--detectors", "magic")[0] == 2
    assert run_cli("audit", str(p), "--max-memory", "lots")[0] == 2
    assert run_cli("audit", str(p), "--cycles", "no-such-profile")[0] == 2


# ---- usable but dubious: audited, with warnings ------------------------------------------
def test_degenerate_faces_are_warned(tmp_path):
    # the tetrahedron plus a zero-area sliver on three collinear points far away
    v = TETRA_V.tolist() + [[5, 0, 0], [6, 0, 0], [7, 0, 0]]
    f = TETRA_F.tolist() + [[4, 5, 6]]
    doc = audit_json(write(tmp_path, "deg.obj", obj_text(v, f)))
    assert doc["mesh"]["degenerate_faces"] == 1
    assert "1 degenerate (zero-area) faces" in "\n".join(doc["warnings"])


def test_duplicate_faces_are_warned(tmp_path):
    f = TETRA_F.tolist() + [TETRA_F[0].tolist()]
    doc = audit_json(write(tmp_path, "dup.obj", obj_text(TETRA_V, f)))
    assert doc["mesh"]["duplicate_faces"] == 1
    # the duplicated face makes its three edges valence 3: non-manifold
    assert doc["mesh"]["nonmanifold_edges"] == 3
    assert "1 duplicate faces" in "\n".join(doc["warnings"])


def test_nonmanifold_edges_are_warned(tmp_path):
    # three triangles sharing the edge (0,1): a fin
    v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]]
    f = [[0, 1, 2], [1, 0, 3], [0, 1, 4]]
    doc = audit_json(write(tmp_path, "fin.obj", obj_text(v, f)))
    assert doc["mesh"]["nonmanifold_edges"] == 1
    assert "1 non-manifold edges" in "\n".join(doc["warnings"])


def test_open_boundaries_are_warned(tmp_path):
    doc = audit_json(write(tmp_path, "open.obj", obj_text(TETRA_V, TETRA_F[:3])))
    assert doc["mesh"]["boundary_edges"] == 3  # the removed face's three edges
    assert "open mesh: 3 boundary edges" in "\n".join(doc["warnings"])


def test_inconsistent_winding_is_warned(tmp_path):
    f = TETRA_F.copy()
    f[3] = f[3][::-1]  # one face flipped: its 3 edges are traversed twice the same way
    doc = audit_json(write(tmp_path, "flip.obj", obj_text(TETRA_V, f)))
    assert doc["mesh"]["inconsistent_edges"] == 3
    assert "inconsistent winding: 3 edges" in "\n".join(doc["warnings"])


def test_light_on_a_face_plane_is_a_warned_tie(tmp_path):
    # quad cube: the point (2, 0, 0.5) lies on the plane z = 0.5 of the top face
    p = write(tmp_path, "cube.obj", obj_text(QUAD_CUBE_V, QUAD_CUBE_F))
    doc = audit_json(p, "--light", "2,0,0.5", "--random-lights", "0")
    assert doc["lights"][0]["ties"] == 1
    assert "light 0: on the plane of 1 faces" in "\n".join(doc["warnings"])


def test_light_inside_the_mesh_is_warned(tmp_path):
    p = write(tmp_path, "cube.obj", obj_text(QUAD_CUBE_V, QUAD_CUBE_F))
    doc = audit_json(p, "--light", "0.1,0.2,0.3", "--random-lights", "0")
    assert doc["lights"][0]["inside"] is True
    assert doc["detectors"]["reference"]["silhouette_edges"] == 0  # every face sees its back: no silhouette
    assert "light 0: inside the mesh" in "\n".join(doc["warnings"])


# ---- no half-written output ----------------------------------------------------------------
def test_failed_audit_leaves_no_output_file(tmp_path):
    out = tmp_path / "report.json"
    rc, _, _ = run_cli("audit", str(write(tmp_path, "c.obj", "v 1 2 x\n")), "--out", str(out), "--quiet")
    assert rc == 3 and not out.exists() and list(tmp_path.iterdir()) == [tmp_path / "c.obj"]


def test_atomic_write_keeps_the_old_file_when_writing_fails(tmp_path):
    target = tmp_path / "a.txt"
    target.write_text("old")

    with pytest.raises(TypeError):
        write_text(target, 12345)  # type: ignore[arg-type]  # fails inside the write
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]


def test_real_process_prints_one_line_and_no_traceback(tmp_path):
    p = write(tmp_path, "c.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nend_header\n")
    proc = subprocess.run([sys.executable, "-m", "silcount.cli.main", "audit", str(p)], capture_output=True, text=True)
    assert proc.returncode == 3
    assert proc.stdout == "" and proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert str(p) in proc.stderr


@pytest.mark.parametrize("ext", [".glb", ".gltf"])
def test_valid_gltf_loads_as_the_mesh_it_was_written_from(tmp_path, ext):
    # A second implementation writes the file (trimesh's exporter); silcount reads it back.
    import trimesh

    import silcount

    ico = silcount.builtin_mesh("icosahedron")
    path = tmp_path / f"ico{ext}"
    trimesh.Trimesh(ico.vertices, ico.faces, process=False).export(path)
    loaded = silcount.load_mesh(path)
    assert (loaded.n_vertices, loaded.n_faces, loaded.n_edges) == (12, 20, 30)
    assert loaded.is_watertight


# ---- messages that name the real problem (issue 44) ----------------------------------------------
def test_the_nan_vertex_is_counted_from_one_as_obj_users_count(tmp_path):
    text = obj_text(TETRA_V, TETRA_F)
    assert "v -1.0 -1.0 1.0" in text  # the 4th vertex of the file (its 4th line); it said "vertex 3"
    p = write(tmp_path, "nan4.obj", text.replace("v -1.0 -1.0 1.0", "v -1.0 nan 1.0"))
    assert_refused(p, 4, "NaN or Inf", "first: vertex 4, counting from 1")


def test_a_symbolic_link_loop_is_not_a_missing_file(tmp_path):
    (tmp_path / "a.obj").symlink_to(tmp_path / "b.obj")
    (tmp_path / "b.obj").symlink_to(tmp_path / "a.obj")
    err = assert_refused(tmp_path / "a.obj", 3, "Too many levels of symbolic links")
    assert "no such file" not in err
    (tmp_path / "dangling.obj").symlink_to(tmp_path / "gone.obj")
    assert_refused(tmp_path / "dangling.obj", 3, f"a symbolic link to {tmp_path / 'gone.obj'}, which does not exist")


def test_a_gltf_whose_buffer_file_is_missing_names_it(tmp_path):
    import trimesh

    files = trimesh.Trimesh(TETRA_V, TETRA_F, process=False).export(file_type="gltf")  # a second implementation
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
    buffers = sorted(n for n in files if n.endswith(".bin"))
    assert buffers and run_cli("audit", str(tmp_path / "model.gltf"), "--quiet")[0] == 0
    (tmp_path / buffers[0]).unlink()
    err = assert_refused(tmp_path / "model.gltf", 3, f"the file {buffers[0]} it refers to is missing")
    assert "not a valid" not in err
