"""Issue 41: the stencil frame's stages, counted exactly (hand counts on one triangle over a floor at 8x8) and
checked against properties on the shared scenes."""

from __future__ import annotations

import json
import math
from pathlib import Path

import jsonschema
import numpy as np
import pandas as pd
import pytest
from common import run_cli, shared_scenes

import silcount
from silcount.detectors import detect
from silcount.mesh.lights import PointLight
from silcount.mesh.model import from_polygons
from silcount.render.raster import DEPTH, ZFAIL, rasterize
from silcount.render.scene import Scene, SceneObject, load_scene
from silcount.render.stages import COLUMNS, frame_stages
from silcount.render.stencil import STAGES, render_stencil

SCHEMAS = Path(__file__).resolve().parent.parent / "docs" / "schemas"


def triangle_scene() -> Scene:
    """One triangle over a floor at 8x8, seen from straight above (see :func:`test_hand_counts`)."""
    floor = from_polygons(np.array([[-10, 0, -10], [10, 0, -10], [10, 0, 10], [-10, 0, 10.0]]), [[0, 3, 2], [0, 2, 1]])
    tri = from_polygons(np.array([[-1.6, 5, -1.6], [-1.6, 5, 1.8], [1.8, 5, -1.6]]), [[0, 1, 2]])
    return Scene(
        Path("triangle.json"),
        8,
        8,
        np.array([0, 10, 0.0]),
        np.zeros(3),
        np.array([0, 0, -1.0]),
        math.degrees(2 * math.atan(0.4)),
        0.1,
        PointLight((0, 8, 0)),
        [SceneObject("floor", floor, False), SceneObject("triangle", tri, True)],
    )


def _ops(add=0, mul=0, cmp=0, read=0, write=0, fragments=0, stencil_updates=0):
    return {"add": add, "mul": mul, "cmp": cmp, "read": read, "write": write, "div": 0}, fragments, stencil_updates


DEPTH_STAGE = _ops(add=533, mul=484, cmp=85, read=85, write=298, fragments=85)
LIT_STAGE = _ops(cmp=128, read=128, write=128, fragments=64)
FINAL_STAGE = _ops(read=64, write=128)
HAND = {
    "zpass": {
        "volume": _ops(add=248, mul=297, cmp=1, read=88, write=72),
        "stencil": _ops(add=90, mul=60, cmp=15, read=30, write=79, fragments=15, stencil_updates=15),
    },
    "zfail": {
        "volume": _ops(add=248, mul=297, cmp=1, read=100, write=84),
        "stencil": _ops(add=201, mul=144, cmp=36, read=57, write=85, fragments=36, stencil_updates=21),
    },
    "pertriangle": {
        "detection": _ops(),
        "volume": _ops(add=95, mul=105, cmp=1, read=112, write=96),
        "stencil": _ops(add=417, mul=288, cmp=72, read=129, write=121, fragments=72, stencil_updates=57),
    },
}


@pytest.mark.parametrize("method", ["zpass", "zfail", "pertriangle"])
def test_hand_counts(method):
    """Counted on paper.  Camera at (0, 10, 0) looking down, ``tan(fov/2) = 0.4``: on the floor (distance 10)
    one pixel is one unit, at the triangle's height 5 half a unit; pixel ``(col, row)`` has its centre at
    ``(c + 0.5, r + 0.5)`` in pixel units, ``px = 4 + x / (0.1 d)`` at distance ``d``.

    * Triangle, in pixel units: (0.8, 0.8), (7.6, 0.8), (0.8, 7.6); centres inside: ``c, r >= 1``,
      ``c + r + 1 < 8.4``: 6 + 5 + 4 + 3 + 2 + 1 = 21.  The floor (two triangles past the screen) covers all
      64.  No centre lies on an edge (0.1 pixel away at least).
    * Light (0, 8, 0): the far points ``p - L`` project to ``4 + (x / 3) / 0.4 * 4``: (-1.33, -1.33),
      (10, -1.33), (-1.33, 10); centres inside: ``c + r <= 7``: 36.  The floor shadow, scale 8/3 about the
      axis: (-0.27, -0.27), (8.8, -0.27), (-0.27, 8.8), the same 36 centres, 21 of them behind the
      triangle, so 15 visible shadow pixels (row 0 and column 0).  The eye is outside every side plane
      (e.g. the side through x = -1.6: ``(1.6, 5) . (3, -1.6) = -3.2 < 0`` while the floor's centre gives
      +12.8), so the sides are front faces on the 36 - 21 = 15 pixels between the two outlines, and each
      passes depth there (its floor point is in shadow, inside the volume).

    Stages, with the costs of :mod:`silcount.render.stages`:

    * depth: 9 vertices (16 mul, 12 add each: 144, 108), 85 fragments (64 floor, then 21 triangle, nearer:
      every one passes; 5 add, 4 mul, 1 read, 1 cmp each: 425, 340, 85, 85), 85 depth writes (2 writes:
      170), 2 x 64 pixels cleared (128 writes): add 533, mul 484, cmp 85, read 85, write 298.
    * volume (silhouette): the 3 boundary edges; 1 facing test (14 add, 9 mul, 1 cmp, 16 read: e1, e2,
      their cross product, L - p0, the dot product; 4 index and 9 + 3 coordinate reads), 6 ends extruded
      (3 add: 18), 6 side triangles (18 vertices: 288 mul, 216 add), emitted with 12 reads and writes
      each: zpass 6 triangles (72, 72), zfail 6 + the light cap (84, 84); no unlit face, no dark cap:
      add 248, mul 297.
    * volume (pertriangle): 1 facing test, 3 vertices extruded (9 add), 6 points transformed (96 mul,
      72 add), 6 sides + light cap + dark cap = 8 triangles (96, 96): add 95, mul 105, read 112, write 96.
    * stencil, 64 pixels cleared (64 writes) plus, per fragment 5 add 4 mul 1 read 1 cmp and per update
      1 read 1 add 1 write: zpass: the 15 side fragments pass, 15 updates; zfail: 15 side fragments pass
      and the light cap's 21 fail (equal depth): 36, 21 updates; pertriangle: 15 + 21 + the dark cap's 36
      (at infinity, all fail): 72, 57 updates.
    * lit: 64 coverage tests and 64 stencil tests (1 read, 1 cmp, 1 write each); final: 64 cleared, 64 mask
      writes (1 read, 1 write).
    """
    sc = triangle_scene()
    table = frame_stages(sc, method).set_index("stage")
    assert list(table.index) == list(STAGES)
    hand = {"depth": DEPTH_STAGE, "lit": LIT_STAGE, "final": FINAL_STAGE} | HAND[method]
    for stage, (ops, fragments, updates) in hand.items():
        row = table.loc[stage]
        assert {k: int(row[k]) for k in ops} == ops, stage
        assert (int(row["fragments"]), int(row["stencil_updates"])) == (fragments, updates), stage
    if method != "pertriangle":  # the detection stage is the detector's own count
        tally = detect(sc.objects[1].mesh, sc.light, "reference", engine="fast").true_tally
        assert {k: int(table.loc["detection", k]) for k in tally} == tally
    else:
        assert table.loc["detection", "seconds"] == 0.0 and table.loc["detection", "detector"] == ""


@pytest.mark.parametrize("method", ["zpass", "pertriangle"])
def test_hand_mask(method):
    """The 15 visible shadow pixels of :func:`test_hand_counts`: row 0 and column 0 (z-fail on the open
    triangle has no dark cap and is wrong there, as its warning says)."""
    want = np.zeros((8, 8), dtype=bool)
    want[0, :] = want[:, 0] = True
    assert np.array_equal(render_stencil(triangle_scene(), method).mask, want)


def test_columns_and_public_name():
    t = silcount.frame_stages(triangle_scene(), "zfail", "ta", resolution=(16, 12))
    assert tuple(t.columns) == COLUMNS and list(t["stage"]) == list(STAGES)
    assert set(t["detector"]) == {"ta"} and set(t["method"]) == {"zfail"}
    assert t["frame_seconds"].nunique() == 1
    assert t["seconds"].sum() <= t["frame_seconds"].iloc[0]  # disjoint intervals inside the frame
    assert t.loc[t["stage"] == "lit", "fragments"].item() == 16 * 12  # the floor covers every pixel


@pytest.fixture(scope="module")
def cube():
    return load_scene(shared_scenes() / "cube_on_floor.json").with_resolution(64, 48)


@pytest.mark.parametrize("method", ["zfail", "pertriangle"])
def test_zfail_updates_are_the_volume_fragments_that_fail_depth(cube, method):
    """Each volume triangle drawn alone (DEPTH mode, into a buffer cleared to infinity: its own fragments
    and depths) against the scene's depth: the fragments at or behind it are z-fail's updates."""
    res = render_stencil(cube, method)
    table = frame_stages(cube, method).set_index("stage")
    fragments = failing = 0
    for tri in res.volume_clip:
        depth = np.full(res.scene.depth.shape, np.inf)
        ids = np.full(depth.shape, -1, dtype=np.int64)
        rasterize(tri[None], np.zeros(1, dtype=np.int64), DEPTH, depth, np.zeros((1, 1), dtype=np.int32), ids)
        drawn = ids >= 0
        fragments += int(drawn.sum())
        failing += int((depth[drawn] >= res.scene.depth[drawn]).sum())
    assert table.loc["stencil", "fragments"] == fragments
    assert table.loc["stencil", "stencil_updates"] == failing
    assert failing > 0


def test_depth_fragments_are_each_triangles_covered_samples(cube):
    """The depth pass's fragments: the covered samples of each scene triangle drawn alone, summed; the
    lit pass's: the covered pixels."""
    res = render_stencil(cube, "zfail")
    total = 0
    for tri in res.scene.clip:
        depth, ids = np.full(res.scene.depth.shape, np.inf), np.full(res.scene.depth.shape, -1, dtype=np.int64)
        rasterize(tri[None], np.zeros(1, dtype=np.int64), DEPTH, depth, np.zeros((1, 1), dtype=np.int32), ids)
        total += int((ids >= 0).sum())
    table = frame_stages(cube, "zfail").set_index("stage")
    assert table.loc["depth", "fragments"] == total > res.coverage.sum()
    assert table.loc["lit", "fragments"] == res.coverage.sum()


def test_zpass_and_uncapped_zfail_split_the_same_fragments(cube):
    """The same side triangles: each fragment passes (a z-pass update) or fails (a z-fail update)."""
    zp = frame_stages(cube, "zpass").set_index("stage").loc["stencil"]
    zf = frame_stages(cube, "zfail", volume="sides").set_index("stage").loc["stencil"]
    assert zp["fragments"] == zf["fragments"] == zp["stencil_updates"] + zf["stencil_updates"]
    assert zp["stencil_updates"] > 0 and zf["stencil_updates"] > 0


def test_counts_are_deterministic_and_independent_of_threads(cube):
    res = render_stencil(cube, "pertriangle")
    counts = []
    for parts in (1, 2, 3):
        stencil = np.zeros(res.stencil.shape, dtype=np.int32)
        got = rasterize(res.volume_clip, np.zeros(len(res.volume_clip), dtype=np.int64), ZFAIL,
                        res.scene.depth, stencil, res.scene.tri_id, parts=parts)  # fmt: skip
        assert np.array_equal(stencil, res.stencil)
        counts.append(got.tolist())
    assert counts[0] == counts[1] == counts[2]
    a, b = frame_stages(cube, "zfail"), frame_stages(cube, "zfail")
    cols = [c for c in COLUMNS if "seconds" not in c]
    assert a[cols].equals(b[cols])


def test_truncated_volumes_are_refused():
    with pytest.raises(silcount.BadArgument, match="truncated"):
        frame_stages(triangle_scene(), "zfail", volume="truncated")
    with pytest.raises(silcount.BadArgument, match="pertriangle"):
        render_stencil(triangle_scene(), "pertriangle", volume="sides")


def _scene_file(tmp_path: Path) -> Path:
    """:func:`triangle_scene` as a silcount-scene/1 file."""
    sc = triangle_scene()
    for obj in sc.objects:
        lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in obj.mesh.vertices.tolist()]
        lines += ["f " + " ".join(str(i + 1) for i in f) for f in obj.mesh.faces.tolist()]
        (tmp_path / f"{obj.name}.obj").write_text("\n".join(lines) + "\n")
    doc = {
        "spec": "silcount-scene/1",
        "resolution": [8, 8],
        "camera": {"eye": [0, 10, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": sc.fov_y_deg, "near": 0.1},
        "light": {"position": [0, 8, 0]},
        "objects": [{"name": o.name, "mesh": f"{o.name}.obj", "casts_shadow": o.casts_shadow} for o in sc.objects],
    }
    path = tmp_path / "triangle.json"
    path.write_text(json.dumps(doc))
    return path


@pytest.mark.parametrize("suffix", [".csv", ".json", ".parquet"])
def test_render_writes_the_stage_table(tmp_path, suffix):
    scene = _scene_file(tmp_path)
    out = tmp_path / "sub" / f"stages{suffix}"
    rc, _, err = run_cli("render", str(scene), "--method", "pertriangle", "--out", str(tmp_path / "m.png"),
                         "--stages", str(out))  # fmt: skip
    assert rc == 0, err
    if suffix == ".csv":
        table = pd.read_csv(out, keep_default_na=False)
    elif suffix == ".json":
        doc = json.loads(out.read_text())
        jsonschema.validate(doc, json.loads((SCHEMAS / "render-stages.schema.json").read_text()))
        table = pd.DataFrame(doc)
    else:
        table = pd.read_parquet(out)
    stencil = table.set_index("stage").loc["stencil"]
    assert (stencil["fragments"], stencil["stencil_updates"], stencil["add"]) == (72, 57, 417)  # the hand count
    assert sorted(p.name for p in out.parent.iterdir()) == [out.name]  # no temporary file left


@pytest.mark.parametrize(
    ("args", "code", "words"),
    [
        (["--method", "raycast", "--stages", "s.csv"], 2, "--stages applies to zpass, zfail and pertriangle"),
        (["--method", "zfail", "--stages", "s.txt"], 2, "extension must be one of .csv, .json, .parquet"),
        (["--method", "zfail", "--volume", "truncated", "--stages", "s.csv"], 2, "not truncated"),
        (["--method", "zfail", "--stages", "blocker/s.csv"], 3, "is a file, not a folder"),
    ],
)
def test_render_stages_refuses_in_one_line(tmp_path, args, code, words):
    scene = _scene_file(tmp_path)
    (tmp_path / "blocker").write_text("")
    argv = ["render", str(scene), "--out", str(tmp_path / "m.png")]
    argv += [str(tmp_path / a) if a.startswith(("s.", "blocker")) else a for a in args]
    rc, _, err = run_cli(*argv)
    assert rc == code and words in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "m.png").exists()  # refused before the render


def test_software_counts_equal_the_gl_hand_count():
    """The OpenGL side's hand scene (``test_render_opengl.hand_scene``; its docstring counts GL's samples
    passed by hand: depth 67, stencil 13, lit 59).  The software frame draws the same samples: the depth
    pass's 64 floor and 3 caster fragments all pass (67); z-fail's stencil updates are GL's samples passed
    of its stencil pass (13); and the lit pass's visible samples less those in shadow are GL's lit samples
    (59), per-triangle as GL draws it.  (The open triangle's silhouette volume has no dark cap: z-fail
    with a detector misses the 4 updates of the samples that leave the volume through it, 9.)"""
    from test_render_opengl import hand_scene

    res = render_stencil(hand_scene(), "pertriangle")
    table = frame_stages(hand_scene(), "pertriangle").set_index("stage")
    assert res.log.events["depth"]["depth_passed"] == table.loc["depth", "fragments"] == 67
    assert table.loc["stencil", "stencil_updates"] == 13
    assert table.loc["lit", "fragments"] - int(res.mask.sum()) == 59
    assert frame_stages(hand_scene(), "zfail").set_index("stage").loc["stencil", "stencil_updates"] == 9


def test_a_reused_framebuffer_draws_what_new_buffers_draw(cube):
    """A frame drawn into a framebuffer that holds another scene's frame clears it first: its mask, stencil,
    depth, ids and counts equal those of the frame drawn into new buffers, bit for bit."""
    from silcount.render.stencil import Framebuffer

    fb = Framebuffer.of(cube.width, cube.height)
    render_stencil(triangle_scene().with_resolution(cube.width, cube.height), "pertriangle", framebuffer=fb)
    for method in ("zpass", "zfail", "pertriangle"):
        fresh = render_stencil(cube, method)
        reused = render_stencil(cube, method, framebuffer=fb)
        assert reused.stencil is fb.stencil and reused.scene.depth is fb.depth
        for a, b in ((fresh.mask, reused.mask), (fresh.stencil, reused.stencil), (fresh.scene.tri_id, fb.tri_id)):
            assert np.array_equal(a, b)
        assert np.array_equal(fresh.scene.depth, fb.depth, equal_nan=False)
        assert fresh.log.events == reused.log.events


def test_a_framebuffer_of_another_size_is_refused(cube):
    from silcount.errors import BadArgument
    from silcount.render.stencil import Framebuffer

    with pytest.raises(BadArgument, match="framebuffer cannot hold"):
        render_stencil(cube, "zfail", framebuffer=Framebuffer.of(cube.width + 1, cube.height))


def test_given_scene_clip_coordinates_change_only_the_depth_stage_transforms(cube):
    """A frame given the scene's clip coordinates (as the GL frame uploads them once) draws the same bits; its
    depth stage counts no vertex transform: on the hand scene, the hand count less its 9 vertices' 144 mul
    and 108 add (:func:`test_hand_counts`), every other stage unchanged."""
    from silcount.render.opengl import scene_clip

    for sc in (triangle_scene(), cube):
        clip = scene_clip(sc)
        for method in ("zpass", "zfail", "pertriangle"):
            fresh, given = render_stencil(sc, method), render_stencil(sc, method, scene_clip=clip)
            for part in ("mask", "stencil"):
                assert np.array_equal(getattr(fresh, part), getattr(given, part))
            assert np.array_equal(fresh.scene.depth, given.scene.depth)
            assert fresh.log.events["depth"]["vertices_transformed"] == 3 * len(clip)
            assert given.log.events["depth"]["vertices_transformed"] == 0
            for stage, events in fresh.log.events.items():
                others = {k: n for k, n in events.items() if k != "vertices_transformed"}
                assert {k: n for k, n in given.log.events[stage].items() if k != "vertices_transformed"} == others
    ops, fragments, _ = DEPTH_STAGE
    row = frame_stages(triangle_scene(), "zfail", scene_clip=scene_clip(triangle_scene())).set_index("stage")
    assert {k: int(row.loc["depth", k]) for k in ops} == ops | {"add": 533 - 108, "mul": 484 - 144}
    assert int(row.loc["depth", "fragments"]) == fragments


def test_scene_clip_coordinates_of_another_scene_are_refused(cube):
    from silcount.errors import BadArgument
    from silcount.render.opengl import scene_clip

    with pytest.raises(BadArgument, match="scene_clip"):
        render_stencil(cube, "zfail", scene_clip=scene_clip(triangle_scene()))
