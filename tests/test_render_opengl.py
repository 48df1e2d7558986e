"""The software stencil rasteriser against a real OpenGL stencil pipeline (Mesa llvmpipe), pixel by pixel.

:class:`silcount.render.opengl.GLFrame` draws the very triangles silcount rasterises (same clip
coordinates, float32 on the GL side) with GL's own depth test and two-sided stencil
operations, so the masks are an independent implementation of the stencil steps
(stencil paper Sec. 5; scene README "Comparing two masks").  It agrees where the
method is right and also where it is wrong: z-pass with the eye inside a volume
gives the same wrong mask in GL.  Skips, saying why, without moderngl and PyOpenGL
(the ``gl`` extra) or without an EGL driver.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest
from common import shared_scenes

from silcount.errors import NoOpenGL
from silcount.mesh.lights import DirectionalLight, PointLight
from silcount.mesh.model import from_polygons
from silcount.render.masks import compare_masks
from silcount.render.methods import render_method
from silcount.render.opengl import GLFrame, gl_frame, scene_clip
from silcount.render.scene import Scene, SceneObject, load_scene
from silcount.render.stencil import render_stencil


def gl_stencil():
    """``tests/oracles/gl_stencil.py``, imported when first asked for (its numpy volume builder)."""
    return importlib.import_module("oracles.gl_stencil")


SCENES = ("cube_on_floor", "icosahedron_on_floor", "torus_self_shadow", "cow_and_cubes", "eye_in_shadow")


def open_gl(width, height):
    """A :class:`GLFrame`, or a skip saying why there is none (the gl extra or an EGL driver missing)."""
    pytest.importorskip("moderngl", reason="moderngl not installed (pip install -e '.[gl]')")
    pytest.importorskip("OpenGL", reason="PyOpenGL not installed (pip install -e '.[gl]')")
    try:
        return GLFrame(width, height)
    except NoOpenGL as err:  # no EGL driver on this machine: a skip that says so, not a result dropped
        pytest.skip(str(err))


@pytest.fixture(scope="module")
def gl_context():
    return open_gl(512, 512)


def scene(name):
    d = shared_scenes()
    return load_scene(d / f"{name}.json")


def stencil_frame(gl, sc, method):
    res = render_stencil(sc, method)
    assert (sc.width, sc.height) == (gl.width, gl.height)
    gl.set_scene(res.scene.clip)
    gl.frame(res.volume_clip, method)
    coverage, stencil = gl.coverage(), gl.stencil()
    return res, coverage, coverage & (stencil != 0), stencil


@pytest.mark.parametrize("method", ["zfail", "zpass"])
@pytest.mark.parametrize("name", SCENES)
def test_masks_match_llvmpipe(gl_context, name, method):
    res, coverage, mask, stencil = stencil_frame(gl_context, scene(name), method)
    cov = compare_masks(coverage, res.coverage)
    assert cov.mismatched <= 2, cov.describe()  # the depth pass: float32 vs float64 at a pixel centre or two
    c = compare_masks(res.mask, mask, res.coverage)
    assert c.far == 0 and c.mismatched <= 20, c.describe()
    assert res.mask.sum() > 1000  # there is a shadow to agree on
    same = stencil.astype(np.int32) == res.stencil
    assert same.mean() > 0.9995, f"{(~same).sum()} stencil counts differ"


def test_zpass_with_the_eye_in_shadow_is_wrong_in_opengl_too(gl_context):
    sc = scene("eye_in_shadow")
    res, _, mask, _ = stencil_frame(gl_context, sc, "zpass")
    truth = render_method(sc, "raycast")
    assert compare_masks(res.mask, mask, res.coverage).ok  # silcount's z-pass is GL's z-pass ...
    assert not compare_masks(mask, truth.mask, truth.coverage).ok  # ... and both are wrong here
    _, _, zfail, _ = stencil_frame(gl_context, sc, "zfail")
    assert compare_masks(zfail, truth.mask, truth.coverage).ok  # z-fail is right in GL as in silcount


def test_a_numpy_silhouette_and_volume_on_opengl_give_the_same_mask(gl_context, tmp_path):
    # gl_stencil.volume_clip finds the silhouette and builds the volume with its own numpy code from the
    # faces alone (the benchmark's whole llvmpipe process): a second implementation of both steps.
    bake, volume_clip = gl_stencil().bake, gl_stencil().volume_clip

    sc = scene("cow_and_cubes")
    bake(sc, str(tmp_path / "scene.npz"))
    baked = dict(np.load(tmp_path / "scene.npz"))
    res = render_stencil(sc, "zfail")
    gl_context.set_scene(res.scene.clip)
    gl_context.frame(volume_clip(baked, "zfail"), "zfail")
    mask = gl_context.coverage() & (gl_context.stencil() != 0)
    c = compare_masks(res.mask, mask, res.coverage)
    assert c.far == 0 and c.mismatched <= 20, c.describe()


# ---- the frame stage by stage (issue 41): silcount.render.opengl.gl_frame


@pytest.mark.parametrize("name", SCENES)
def test_per_triangle_volumes_on_opengl_equal_ray_casting(gl_context, name):
    """Each light-facing triangle extruded on its own (no silhouette), z-fail on llvmpipe: the ray-cast mask,
    0 far mismatches, on every shared scene (the eye inside a volume included: z-fail counts from infinity)."""
    sc = scene(name)
    gl_context.set_scene(scene_clip(sc))
    res = gl_frame(sc, "pertriangle", gl=gl_context)
    truth = render_method(sc, "raycast")
    c = compare_masks(res.mask, truth.mask, truth.coverage)
    assert c.far == 0 and c.ok, c.describe()
    assert truth.mask.sum() > 1000  # there is a shadow to agree on


def test_per_triangle_volumes_under_a_directional_light_equal_ray_casting(gl_context):
    """A directional light sends every far corner to the one point ``(-d, 0)``: each side is one triangle and
    there is no dark cap, and the volumes are still closed (the shared scenes' lights are points)."""
    sc = dataclasses.replace(scene("cow_and_cubes"), light=DirectionalLight((1.0, 2.0, 0.5)))
    gl_context.set_scene(scene_clip(sc))
    res = gl_frame(sc, "pertriangle", gl=gl_context)
    truth = render_method(sc, "raycast")
    c = compare_masks(res.mask, truth.mask, truth.coverage)
    assert c.far == 0 and c.ok, c.describe()
    assert truth.mask.sum() > 1000


@pytest.mark.parametrize("method", ["zfail", "zpass"])
def test_the_staged_frame_gives_the_software_mask_and_a_row_per_stage(gl_context, method):
    sc = scene("cow_and_cubes")
    gl_context.set_scene(scene_clip(sc))
    res = gl_frame(sc, method, gl=gl_context)
    sw = render_stencil(sc, method)
    c = compare_masks(sw.mask, res.mask, sw.coverage)
    assert c.far == 0 and c.mismatched <= 20, c.describe()
    st = res.stages
    assert list(st.columns) == ["stage", "detector", "method", "seconds_wall", "seconds_gpu", "fragments"]
    assert list(st.stage) == ["detection", "volume", "depth", "stencil", "lit", "final"]
    assert (st.seconds_wall > 0).all() and set(st.method) == {method} and set(st.detector) == {"reference"}
    assert st.seconds_wall.sum() <= res.seconds_frame  # disjoint intervals inside the frame's
    assert st.fragments.isna().tolist() == [True, True, False, False, False, True]
    # the lit pass draws once on each pixel the depth pass covered (GL's own depth buffer) and not in shadow
    assert st.set_index("stage").fragments["lit"] == int((gl_context.coverage() & ~res.mask).sum())


def hand_scene():
    """One triangle over a floor at 8x8, for counting by hand (:func:`test_samples_passed_against_a_hand_count`).

    The eye at (0, 0, 4) looks straight down (up +y, 90 degrees, near 0.1), so a plane at depth ``D`` below it
    maps to the screen affinely: pixel offsets from the image centre ``u = 4 x / D``, ``v = -4 y / D``, pixel
    centres at ``u, v`` in -3.5, -2.5, ..., 3.5 (column ``u + 3.5``, row ``v + 3.5``).  The floor, z = 0
    (``D = 4``), is the square [-4, 4]^2 in two triangles: it fills the image.  The caster, one triangle at
    z = 2 (``D = 2``), facing up, covers the screen triangle ``T`` of offsets (0.9, 0.9), (3.3, 0.9),
    (0.9, 3.3). The point light is at (0, 0, 3), between the eye and the caster.
    """
    floor = from_polygons([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], [[0, 1, 2], [0, 2, 3]], name="floor")
    caster = from_polygons([[0.45, -0.45, 2], [0.45, -1.65, 2], [1.65, -0.45, 2]], [[0, 1, 2]], name="caster")
    return Scene(
        Path("hand.json"),
        8,
        8,
        np.array([0.0, 0.0, 4.0]),
        np.zeros(3),
        np.array([0.0, 1.0, 0.0]),
        90.0,
        0.1,
        PointLight((0.0, 0.0, 3.0)),
        [SceneObject("floor", floor, False), SceneObject("caster", caster, True)],
    )


def test_samples_passed_against_a_hand_count():
    """GL's samples-passed counts of the depth, stencil and lit passes of :func:`hand_scene`, counted by hand.

    Caster pixels: centres in ``T`` (``u, v >= 0.9``, ``u + v <= 4.2``; no centre lies on an edge):
    (1.5, 1.5), (1.5, 2.5), (2.5, 1.5), 3 pixels.  Depth pass: the floor first, every pixel (the top-left
    rule gives each centre on its diagonal to one triangle), then the caster, nearer, at its 3: 67.

    The caster's volume: a point ``L + s (p - L)``, ``p`` on the caster, ``s >= 1``, lies at depth
    ``D = 1 + s`` and on screen at ``f T`` with ``f = 2 s / (1 + s)``, from 1 (the caster, the light cap) to 2
    (infinity, the dark cap); the floor is ``s = 3``, ``f = 1.5``.  So pixel ``(u, v)`` sees the volume for
    ``f`` in ``[(u + v) / 4.2, min(u, v) / 0.9]`` cut to ``[1, 2]``: it enters at the lower end (the light cap
    when that is 1, a side otherwise) and leaves at the upper end (a side, or the dark cap at 2).  Z-fail
    updates the stencil where a face is at or behind the stored depth (``f >= 1`` on the caster, ``f >= 1.5``
    on the floor).  Pixels with ``u`` or ``v`` <= 0.5 see no volume (``min / 0.9 < 1``); of the other nine:
    the 3 caster pixels 2 updates each (the light cap at equal depth, -1, and the side behind, +1: 0);
    (1.5, 3.5), (3.5, 1.5) ``[1.19, 1.67]``, (2.5, 2.5) ``[1.19, 2]``, (2.5, 3.5), (3.5, 2.5) ``[1.43, 2]``:
    entered in front of the floor, left behind it, 1 update each and in shadow; (3.5, 3.5) ``[1.67, 2]``: 2
    updates behind the floor, +1 - 1.  Stencil pass: 3 x 2 + 5 + 2 = 13.  Lit pass: the 64 visible pixels
    less the 5 in shadow, 59.
    """
    gl = open_gl(8, 8)
    sc = hand_scene()
    gl.set_scene(scene_clip(sc))
    res = gl_frame(sc, "pertriangle", gl=gl)
    fragments = res.stages.set_index("stage").fragments
    assert (fragments["depth"], fragments["stencil"], fragments["lit"]) == (67, 13, 59)
    shadow = {(3.5 + v, 3.5 + u) for u, v in [(1.5, 3.5), (3.5, 1.5), (2.5, 2.5), (2.5, 3.5), (3.5, 2.5)]}
    assert set(zip(*np.nonzero(res.mask))) == shadow  # (row, column)
    assert (render_method(sc, "raycast").mask == res.mask).all()  # the ray caster agrees, pixel for pixel


def test_without_the_gl_extra_one_line_names_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "moderngl", None)  # ``import moderngl`` raises ImportError
    with pytest.raises(NoOpenGL, match="the gl extra is not installed") as err:
        GLFrame(8, 8)
    assert "\n" not in str(err.value)
