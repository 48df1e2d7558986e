"""`silcount render` and `silcount compare` from the command line: outputs, exit codes, errors."""

from __future__ import annotations

import numpy as np
import pytest
from common import shared_scenes
from PIL import Image

from silcount.cli.main import main
from silcount.render.masks import compare_masks, dilate, edge_pixels, write_mask


def scene_path(name):
    d = shared_scenes()
    return str(d / f"{name}.json")


def test_render_writes_mask_coverage_and_image_then_compare_agrees(tmp_path, capsys):
    s = scene_path("cube_on_floor")
    assert (
        main(
            [
                "render",
                s,
                "--method",
                "zfail",
                "--out",
                str(tmp_path / "z.png"),
                "--coverage",
                str(tmp_path / "c.png"),
                "--image",
                str(tmp_path / "i.png"),
            ]
        )
        == 0
    )
    assert main(["render", s, "--method", "raycast", "--out", str(tmp_path / "r.png")]) == 0
    mask = np.asarray(Image.open(tmp_path / "z.png"))
    assert mask.dtype == np.uint8 and mask.shape == (512, 512) and set(np.unique(mask)) == {0, 255}
    assert np.asarray(Image.open(tmp_path / "i.png")).shape == (512, 512, 3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.png", "i.png", "r.png", "z.png"]  # no temp files left
    capsys.readouterr()
    assert (
        main(["compare", str(tmp_path / "z.png"), str(tmp_path / "r.png"), "--coverage", str(tmp_path / "c.png")]) == 0
    )
    assert "match" in capsys.readouterr().out


def test_zpass_with_eye_in_shadow_warns_on_stderr(tmp_path, capsys):
    assert main(["render", scene_path("eye_in_shadow"), "--method", "zpass", "--out", str(tmp_path / "m.png")]) == 0
    assert "eye is inside a shadow volume" in capsys.readouterr().err


def test_compare_exit_codes(tmp_path, capsys):
    a = np.zeros((20, 20), dtype=bool)
    a[5:15, 5:15] = True
    b = a.copy()
    b[7:12, 7:12] = False  # a 5x5 hole: its centre is > 1 px from every edge of a and b (far)
    c = a.copy()
    c[5, 5:15] = False  # one row shaved off the edge: near an edge
    for name, m in (("a", a), ("b", b), ("c", c)):
        write_mask(tmp_path / f"{name}.png", m)
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--tol", "0.5"]) == 1
    out = capsys.readouterr().out
    assert "25 of 400" in out and "; 1 of them more than one pixel" in out
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "c.png"), "--tol", "0.05"]) == 0  # 10/400
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "c.png"), "--tol", "0.01"]) == 1
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "nope.png")]) == 3
    (tmp_path / "junk.png").write_bytes(b"not a png")
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "junk.png")]) == 3
    write_mask(tmp_path / "small.png", np.zeros((4, 4), dtype=bool))
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "small.png")]) == 2
    assert main(["compare", str(tmp_path / "a.png"), str(tmp_path / "a.png"), "--tol", "-1"]) == 2
    err = capsys.readouterr().err
    assert "nope.png" in err and "junk.png" in err


def test_render_bad_inputs(tmp_path, capsys):
    assert main(["render", str(tmp_path / "missing.json"), "--method", "zfail", "--out", str(tmp_path / "m.png")]) == 3
    (tmp_path / "bad.json").write_text("{not json")
    assert main(["render", str(tmp_path / "bad.json"), "--method", "zfail", "--out", str(tmp_path / "m.png")]) == 3
    (tmp_path / "other.json").write_text('{"spec": "something-else/2"}')
    assert main(["render", str(tmp_path / "other.json"), "--method", "zfail", "--out", str(tmp_path / "m.png")]) == 3
    assert main(["render", scene_path("cube_on_floor"), "--method", "zfail", "--out", "/proc/m.png"]) == 3
    err = capsys.readouterr().err
    assert "missing.json" in err and "bad.json" in err and "other.json" in err and "cannot write /proc/m.png" in err
    assert not (tmp_path / "m.png").exists()


@pytest.mark.parametrize("detector", ["gaussmap", "cones"])
def test_render_with_a_hierarchy_detector_gives_the_reference_mask(tmp_path, capsys, detector):
    # gaussmap and cones find exactly the reference's silhouette, so their shadow volumes and masks are its own
    s = scene_path("torus_self_shadow")
    for method in ("zpass", "zfail"):
        assert main(["render", s, "--method", method, "--out", str(tmp_path / f"ref.{method}.png")]) == 0
        out = tmp_path / f"{detector}.{method}.png"
        assert main(["render", s, "--method", method, "--detector", detector, "--out", str(out)]) == 0
        assert f"{detector} intended" in capsys.readouterr().out
        assert np.array_equal(np.asarray(Image.open(out)), np.asarray(Image.open(tmp_path / f"ref.{method}.png")))


# ---- the previous, hand-written numpy implementation of edge_pixels and dilate (before scipy.ndimage, issue 25),
# kept here as the oracle the scipy.ndimage versions must reproduce bit for bit ---------------------------------


def previous_edge_pixels(mask: np.ndarray) -> np.ndarray:
    """PREVIOUS IMPLEMENTATION of silcount.render.masks.edge_pixels (oracle)."""
    m = np.pad(mask, 1, mode="edge")
    H, W = mask.shape
    out = np.zeros_like(mask, dtype=bool)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            out |= m[1 + dr : 1 + dr + H, 1 + dc : 1 + dc + W] != mask
    return out


def previous_dilate(mask: np.ndarray) -> np.ndarray:
    """PREVIOUS IMPLEMENTATION of silcount.render.masks.dilate (oracle)."""
    m = np.pad(mask, 1)
    H, W = mask.shape
    out = np.zeros_like(mask, dtype=bool)
    for dr in (0, 1, 2):
        for dc in (0, 1, 2):
            out |= m[dr : dr + H, dc : dc + W]
    return out


def oracle_masks():
    """Random masks of several shapes and densities, all-false, all-true, 1xN, Nx1, 1x1, and masks set only
    on (or only off) the border pixels, a single corner, a line along one side."""
    rng = np.random.default_rng(25)
    shapes = [(1, 1), (1, 2), (2, 1), (1, 7), (7, 1), (2, 2), (3, 3), (2, 5), (5, 3), (16, 16), (31, 17), (64, 48)]
    for shape in shapes:
        yield np.zeros(shape, dtype=bool)
        yield np.ones(shape, dtype=bool)
        for p in (0.02, 0.5, 0.98):
            for _ in range(3):
                yield rng.random(shape) < p
        border = np.ones(shape, dtype=bool)
        border[1:-1, 1:-1] = False
        yield border
        yield ~border
        for r, c in ((0, 0), (0, -1), (-1, 0), (-1, -1)):
            corner = np.zeros(shape, dtype=bool)
            corner[r, c] = True
            yield corner
            yield ~corner
        side = np.zeros(shape, dtype=bool)
        side[:, -1] = True
        yield side
        yield side.T.copy()


def test_edge_pixels_and_dilate_are_the_previous_implementation_bit_for_bit():
    n = 0
    for m in oracle_masks():
        for layout in (m, np.asfortranarray(m), m[::-1, ::-1]):  # any memory layout or stride
            e, d = edge_pixels(layout), dilate(layout)
            want_e, want_d = previous_edge_pixels(layout), previous_dilate(layout)
            assert e.dtype == want_e.dtype == bool and d.dtype == want_d.dtype == bool
            assert e.shape == want_e.shape == d.shape == want_d.shape == layout.shape
            assert np.array_equal(e, want_e) and np.array_equal(d, want_d), m.astype(int)
            # compare_masks composes them: dilate(edge | edge)
            assert np.array_equal(dilate(e), previous_dilate(want_e))
            n += 1
    assert n > 500


def test_edge_pixels_at_the_border_repeat_the_border_and_dilate_pads_with_false():
    one = np.array([[True, False, False, False]])  # 1x4
    assert edge_pixels(one).tolist() == [[True, True, False, False]]  # past the border: the border repeated
    assert dilate(one).tolist() == [[True, True, False, False]]
    full = np.ones((3, 4), dtype=bool)
    assert not edge_pixels(full).any()  # the image border is no edge by itself (not padded with false)
    assert dilate(full).all() and not dilate(~full).any()  # nor is it grown from true past the border
    gray = np.array([[0, 1, 1], [1, 1, 1], [1, 1, 2]], dtype=np.uint8)  # any values: differs from a neighbour
    assert np.array_equal(edge_pixels(gray), previous_edge_pixels(gray))
    with pytest.raises(ValueError):
        edge_pixels(np.zeros(5, dtype=bool))
    with pytest.raises(ValueError):
        dilate(np.zeros((2, 2, 2), dtype=bool))


def test_compare_masks_matches_the_previous_implementation_on_random_masks():
    rng = np.random.default_rng(7)
    for shape in ((1, 9), (9, 1), (40, 30)):
        for _ in range(20):
            a = rng.random(shape) < 0.5
            b = a ^ (rng.random(shape) < 0.1)
            cov = rng.random(shape) < 0.9
            c = compare_masks(a, b, cov)
            near = previous_dilate(previous_edge_pixels(a) | previous_edge_pixels(b))
            diff = (a != b) & cov
            assert (c.covered, c.mismatched, c.far) == (int(cov.sum()), int(diff.sum()), int((diff & ~near).sum()))


# ---- sizes: the memory estimate is checked before any buffer is allocated (issue 44) -------------------------
def scene_at(tmp_path, resolution, name="cube_on_floor") -> str:
    """The shared scene ``name`` with another ``resolution`` (its mesh paths made absolute)."""
    import json
    from pathlib import Path

    src = Path(scene_path(name))
    doc = json.loads(src.read_text())
    doc["resolution"] = resolution
    for obj in doc["objects"]:
        obj["mesh"] = str(src.parent / obj["mesh"])
    out = tmp_path / f"{name}.{len(list(tmp_path.glob('*.json')))}.json"
    out.write_text(json.dumps(doc))
    return str(out)


def test_a_huge_render_is_refused_in_one_line_before_allocating(tmp_path, capsys):
    s = scene_at(tmp_path, [100000, 100000])
    for method in ("zpass", "zfail", "planar", "raycast"):  # numpy's _ArrayMemoryError ("74.5 GiB") before
        assert main(["render", s, "--method", method, "--out", str(tmp_path / "m.png"), "--max-memory", "64G"]) == 4
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "100000x100000" in err and "over the limit of 64.0 GiB" in err, err
        assert "--max-memory" in err and "Traceback" not in err
    assert not (tmp_path / "m.png").exists()


def test_the_memory_limit_can_be_raised(tmp_path, capsys, monkeypatch):
    s = scene_at(tmp_path, [64, 48])
    out = str(tmp_path / "m.png")
    # the meshes need 4 KiB and 16 KiB (tests/test_bad_input.py's rule), the 64x48 render more than 50 KiB
    assert main(["render", s, "--method", "zfail", "--out", out, "--max-memory", "50K"]) == 4
    assert "64x48 by zfail needs about" in capsys.readouterr().err
    monkeypatch.setenv("SILCOUNT_MAX_MEMORY", "50K")
    assert main(["render", s, "--method", "zfail", "--out", out]) == 4
    assert "over the limit of 50.0 KiB" in capsys.readouterr().err
    assert main(["render", s, "--method", "zfail", "--out", out, "--max-memory", "1G"]) == 0
    assert Image.open(out).size == (64, 48)
    assert main(["render", s, "--method", "zfail", "--out", out, "--max-memory", "lots"]) == 2


def test_a_large_render_is_announced(tmp_path, capsys):
    from silcount.cli.render import check_memory
    from silcount.render.scene import load_scene

    scene = load_scene(scene_at(tmp_path, [64, 64])).with_resolution(20000, 20000)
    check_memory(scene, "zfail", False, 1 << 40)  # it ran 53 s and took 14.3 GB without a word
    assert "20000x20000 by zfail needs about" in capsys.readouterr().err
    check_memory(scene.with_resolution(512, 512), "zfail", False, 1 << 40)
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("resolution", [[512.5, 512], [512, "512"], [True, 512], [512], 512])
def test_a_resolution_that_is_not_two_whole_numbers_is_refused(tmp_path, capsys, resolution):
    s = scene_at(tmp_path, resolution)
    assert main(["render", s, "--method", "raycast", "--out", str(tmp_path / "m.png")]) == 3  # 512.5 drew 512
    err = capsys.readouterr().err
    assert "resolution must be [width, height], two whole numbers of pixels" in err and s in err
