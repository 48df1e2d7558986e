"""`silcount render` and `silcount compare` from the command line: outputs, exit codes, errors."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from silcount.cli.main import main
from silcount.cli.render import shared_scene_dir
from silcount.render.masks import write_mask


def scene_path(name):
    d = shared_scene_dir()
    if d is None:
        pytest.skip("shared scenes not found: set SILCOUNT_SCENE_DIR or provide ../shared/scenes")
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
    assert (
        main(["render", scene_path("cube_on_floor"), "--method", "zfail", "--out", str(tmp_path / "no" / "m.png")]) == 2
    )
    err = capsys.readouterr().err
    assert "missing.json" in err and "bad.json" in err and "other.json" in err
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
