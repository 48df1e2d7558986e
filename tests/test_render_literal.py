"""The stencil paper's literal steps, measured in pixels (issue 10, Sec. 5): the printed final test
``If (~Stencil % 2)`` and the volumes truncated at the receiver by the "new pixel" formula.

Expectations are independent of the rasteriser: C's integer semantics emulated with numpy's ``fmod``,
hand-computed points whose light segments cross the boxes (Moller-Trumbore), the camera's projection of
a world point to its pixel, and the ray caster as ground truth.  Built-in scenes only (no shared files).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from silcount.cli.main import main
from silcount.mesh.lights import DirectionalLight, PointLight
from silcount.render import builtin
from silcount.render.builtin import BUILTIN, builtin_scene, scene_document, write_scene_files
from silcount.render.camera import Camera
from silcount.render.experiments import stencil_step_evidence
from silcount.render.masks import compare_masks, read_mask
from silcount.render.methods import render_method
from silcount.render.scene import load_scene
from silcount.render.stencil import render_stencil, segment_blocked, shadow_from_stencil
from silcount.render.volumes import to_receiver

REPO = Path(__file__).resolve().parents[1]
RES = 160
_cache: dict = {}


def scene(name):
    if name not in _cache:
        _cache[name] = builtin_scene(name, RES)
    return _cache[name]


def truth(name):
    if ("rc", name) not in _cache:
        _cache[("rc", name)] = render_method(scene(name), "raycast")
    return _cache[("rc", name)]


def pixel_of(sc, point):
    """(row, col) of the pixel whose area contains the world point's projection (the camera's matrices)."""
    h = Camera.of(sc).view_projection @ np.append(point, 1.0)
    x, y = h[0] / h[3], h[1] / h[3]
    return int((1 - y) / 2 * sc.height), int((x + 1) / 2 * sc.width)


def box_triangles(sc, name):
    return next(o.triangles for o in sc.objects if o.name == name)


def test_parity_is_the_c_reading_of_the_printed_test():
    s = np.arange(-5, 7, dtype=np.int32)
    # C: (~s) % 2 with two's complement ~ and truncating %; the lit pass draws where it is non-zero
    lit_in_c = np.fmod(~s, 2) != 0
    assert np.array_equal(shadow_from_stencil(s, "parity"), ~lit_in_c)
    assert shadow_from_stencil(s, "parity").tolist() == [bool(v % 2) for v in s.tolist()]
    # an 8-bit stencil that wrapped (-1 -> 255): C promotes to int, ~255 = -256, even: still shadow (odd)
    assert np.fmod(~np.int32(255), 2) == 0 and shadow_from_stencil(np.array([255]), "parity")[0]
    assert shadow_from_stencil(s, "nonzero").tolist() == [v != 0 for v in s.tolist()]


def test_two_overlapping_shadows_give_stencil_two_nonzero_shadow_parity_lit_raycast_shadow():
    sc = scene("overlapping_shadows")
    q, light = np.array([0.7, 0.0, 0.0]), np.asarray(sc.light.position)
    # by hand (builtin.py docstring): the segment from q to the light crosses box B, then box A
    assert segment_blocked(q, light, box_triangles(sc, "box_b"))
    assert segment_blocked(q, light, box_triangles(sc, "box_a"))
    r, c = pixel_of(sc, q)
    assert sc.triangle_object[truth("overlapping_shadows").tri_id[r, c]] == 0  # the floor is what the pixel sees
    assert truth("overlapping_shadows").mask[r, c]
    for method in ("zpass", "zfail"):
        res = render_stencil(sc, method)
        assert res.stencil[r, c] == 2
        assert res.mask[r, c]
        assert not render_stencil(sc, method, shadow_test="parity").mask[r, c]


def test_parity_mismatches_raycast_exactly_where_two_volumes_overlap():
    sc, t = scene("overlapping_shadows"), truth("overlapping_shadows")
    nonzero = render_stencil(sc, "zfail")
    parity = render_method(sc, "zfail", shadow_test="parity")
    good = compare_masks(nonzero.mask, t.mask, t.coverage)
    bad = compare_masks(parity.mask, t.mask, t.coverage)
    assert good.far == 0 and good.fraction <= 0.005, good.describe()
    assert bad.far > 20 and bad.fraction > 0.005, bad.describe()
    differ = nonzero.mask != parity.mask
    assert np.array_equal(differ, nonzero.coverage & (nonzero.stencil != 0) & (nonzero.stencil % 2 == 0))
    assert (nonzero.stencil[differ] == 2).all()


def test_new_pixel_moves_each_vertex_along_the_light_ray_onto_the_plane():
    # plane y = 0.25, light (1, 5, 2), F = (0.5, 2, -1): alpha = (0.25 - 5) / (2 - 5) = 4.75 / 3 by hand
    L, F = np.array([1.0, 5.0, 2.0]), np.array([0.5, 2.0, -1.0])
    n = np.array([0.0, 1.0, 0.0])
    got = to_receiver(np.array([F, [0.0, 0.1, 0.0]]), PointLight(L), n, 0.25)
    assert np.allclose(got[0], np.append(L + 4.75 / 3 * (F - L), 1.0))
    assert got[1].tolist() == [-1.0, 0.1 - 5.0, -2.0, 0.0]  # below the plane: no receiver, stays at infinity
    d = np.array([0.0, 2.0, 1.0])  # towards the light: F goes down along -d by t = (2 - 0.25) / 2
    got = to_receiver(F[None], DirectionalLight(d), n, 0.25)
    assert np.allclose(got[0], np.append(F - 0.875 * d, 1.0))


def test_truncated_volume_loses_the_shadow_beyond_the_clipping_plane():
    sc, t = scene("ledge"), truth("ledge")
    q = np.array([3.0, -2.0, 0.0])  # on the lower floor, behind the box from the light (-4, 6, 0)
    light = np.asarray(sc.light.position)
    assert segment_blocked(q, light, box_triangles(sc, "box"))
    r, c = pixel_of(sc, q)
    assert sc.objects[sc.triangle_object[t.tri_id[r, c]]].name == "lower_floor" and t.mask[r, c]
    # the eye segment to q is outside the volume wherever it is above the plane y = 0: no counted crossing
    eye = sc.eye
    s = np.linspace(0.0, 1.0, 2001)
    pts = eye + s[:, None] * (q - eye)
    assert not any(segment_blocked(p, light, box_triangles(sc, "box")) for p in pts[pts[:, 1] > 0])
    trunc = render_method(sc, "zpass", volume="truncated")
    assert not trunc.mask[r, c]
    assert render_method(sc, "zpass").mask[r, c]
    bad = compare_masks(trunc.mask, t.mask, t.coverage)
    assert bad.far > 20, bad.describe()


def test_truncated_volume_is_exact_when_every_receiver_is_on_the_lights_side():
    sc, t = scene("overlapping_shadows"), truth("overlapping_shadows")
    c = compare_masks(render_method(sc, "zpass", volume="truncated").mask, t.mask, t.coverage)
    assert c.far == 0 and c.fraction <= 0.005, c.describe()


@pytest.mark.parametrize("name", ["ledge", "overlapping_shadows"])
def test_zfail_without_caps_miscounts_exactly_the_casters_own_faces(name):
    # the EESD paper's z-fail: z-pass's volume (the silhouette's quads) with the stencil steps changed.  A
    # point on a caster is counted by the caps behind it: the dark cap (its unlit faces at infinity) for an unlit
    # face, the light cap (its lit faces) for a lit one; without them the count is off by one there and only there
    sc, t = scene(name), truth(name)
    capped, sides = render_stencil(sc, "zfail"), render_stencil(sc, "zfail", volume="sides")
    differ = t.coverage & (capped.stencil != sides.stencil)
    casters = {k for k, o in enumerate(sc.objects) if o.casts_shadow and o.name.startswith("box")}
    assert differ.any()
    assert set(sc.triangle_object[t.tri_id[differ]].tolist()) <= casters
    assert np.all(np.abs(capped.stencil[differ] - sides.stencil[differ]) == 1)
    assert compare_masks(capped.mask, t.mask, t.coverage).far == 0
    assert compare_masks(sides.mask, t.mask, t.coverage).mismatched > 0


def test_stencil_step_evidence_is_deterministic_and_measures_each_literal_step():
    ev = stencil_step_evidence()
    assert set(ev) == {"shadow_test_parity", "volume_truncated", "zfail_uncapped", "planar_literal"}
    for value in ev.values():
        assert set(value) == {"scenes", "summary"} and isinstance(value["summary"], str)
        assert set(value["scenes"]) == set(BUILTIN)
        for m in value["scenes"].values():
            assert set(m) == {"mismatch_fraction", "far_mismatches"}
            assert isinstance(m["mismatch_fraction"], float) and isinstance(m["far_mismatches"], int)
    assert ev["shadow_test_parity"]["scenes"]["overlapping_shadows"]["far_mismatches"] > 0
    assert ev["shadow_test_parity"]["scenes"]["ledge"]["far_mismatches"] == 0  # one volume: stencil <= 1
    assert ev["volume_truncated"]["scenes"]["ledge"]["far_mismatches"] > 0
    assert ev["volume_truncated"]["scenes"]["overlapping_shadows"]["far_mismatches"] == 0
    assert all(m["far_mismatches"] > 0 for m in ev["zfail_uncapped"]["scenes"].values())
    assert all(m["far_mismatches"] > 0 for m in ev["planar_literal"]["scenes"].values())
    assert json.loads(json.dumps(ev)) == stencil_step_evidence()


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_scene_files_in_data_are_the_generated_scenes(tmp_path, name):
    write_scene_files(tmp_path)
    for p in sorted(tmp_path.rglob("*")):
        if p.is_file():
            assert (REPO / "data" / "scenes" / p.relative_to(tmp_path)).read_bytes() == p.read_bytes(), p
    on_disk = load_scene(REPO / "data" / "scenes" / f"{name}.json")
    assert np.array_equal(on_disk.triangles, builtin_scene(name).triangles)
    assert json.loads((REPO / "data" / "scenes" / f"{name}.json").read_text()) == scene_document(name)


def test_cli_shadow_test_and_volume(tmp_path, capsys):
    s = str(REPO / "data" / "scenes" / "overlapping_shadows.json")
    out = tmp_path / "p.png"
    assert main(["render", s, "--method", "zfail", "--shadow-test", "parity", "--out", str(out)]) == 0
    assert "parity test" in capsys.readouterr().out
    expected = render_method(load_scene(s), "zfail", shadow_test="parity").mask
    assert np.array_equal(read_mask(out), expected)
    assert main(["render", s, "--method", "raycast", "--volume", "truncated", "--out", str(out)]) == 2
    assert "--volume apply to zpass, zfail and pertriangle" in capsys.readouterr().err


def test_render_report_summary_follows_its_schema(tmp_path, monkeypatch):
    import jsonschema

    from silcount.cli import render as render_cli

    monkeypatch.setattr(builtin, "builtin_scene", lambda name: builtin_scene(name, 64))  # read by report()
    monkeypatch.setattr(render_cli, "shared_scene_dir", lambda: None)
    written = render_cli.report(tmp_path)
    summary = json.loads((tmp_path / "renders" / "summary.json").read_text())
    schema = json.loads((REPO / "docs" / "schemas" / "render-summary.schema.json").read_text())
    jsonschema.validate(summary, schema)
    assert set(summary["scenes"]) == set(BUILTIN)
    assert set(summary["scenes"]["ledge"]["literal_steps"]) == {
        "zfail-parity",
        "zpass-parity",
        "zpass-truncated",
        "zfail-truncated",
        "zfail-uncapped",
    }
    assert "The papers' literal steps" in (tmp_path / "renders" / "summary.md").read_text()
    assert all(p.exists() for p in written)
    jsonschema.validate(json.loads((REPO / "reports" / "renders" / "summary.json").read_text()), schema)


def test_render_report_without_shared_scenes_keeps_an_existing_summary(tmp_path, monkeypatch, capsys):
    # A clone without ../shared/scenes re-renders the built-in scenes' images only: the summary it cannot
    # recompute (its shared scenes' rows) is left byte for byte, and the report says so.
    from silcount.cli import render as render_cli

    monkeypatch.setattr(builtin, "builtin_scene", lambda name: builtin_scene(name, 64))  # read by report()
    monkeypatch.setattr(render_cli, "shared_scene_dir", lambda: None)
    (tmp_path / "renders").mkdir()
    committed = {name: (REPO / "reports" / "renders" / name).read_bytes() for name in ("summary.json", "summary.md")}
    for name, data in committed.items():
        (tmp_path / "renders" / name).write_bytes(data)
    written = render_cli.report(tmp_path)
    assert {name: (tmp_path / "renders" / name).read_bytes() for name in committed} == committed
    assert "summary left as it is" in capsys.readouterr().err
    assert written and all(p.name.startswith(tuple(BUILTIN)) for p in written)
