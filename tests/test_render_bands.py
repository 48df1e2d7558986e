"""The two-core rasteriser equals the single-threaded one of commit 318ab63 bit for bit (issue 15).

Depth, stencil and triangle ids are compared buffer for buffer on every built-in and shared scene,
every stencil method and volume, for 1, 2 and 3 parts, and on random triangles (inside, crossing the
near plane and the screen edges, behind the eye, at infinity).  The masks of the shared scenes are also
compared with the PNGs committed at 318ab63 (``git show``), when the checkout has that commit.
"""

from __future__ import annotations

import io
import subprocess
from pathlib import Path

import numpy as np
import pytest
from common import shared_scenes
from oracles.render_baseline import rasterize_serial  # the single-threaded rasteriser of 318ab63
from PIL import Image

from silcount.cli.render import shared_scene_dir
from silcount.detectors import DETECTORS
from silcount.render import planar, stencil
from silcount.render.builtin import BUILTIN, builtin_scene
from silcount.render.methods import render_method
from silcount.render.raster import COUNTS, DEPTH, ZFAIL, ZPASS, new_buffers, rasterize
from silcount.render.scene import load_scene

REPO = Path(__file__).resolve().parents[1]


SHARED = ("cube_on_floor", "icosahedron_on_floor", "torus_self_shadow", "cow_and_cubes", "eye_in_shadow")


def _serial(clip, ids, mode, depth, st, tri_id, clear=False):
    """The baseline, in :func:`rasterize`'s signature; it counts nothing (these tests compare buffers).  The
    baseline drew into buffers cleared beforehand, whole: ``clear`` does that first."""
    if clear and mode == DEPTH:
        depth[:] = 1.0
        tri_id[:] = -1
    elif clear:
        st[:] = 0
    rasterize_serial(clip, ids, mode, depth, st, tri_id)
    return np.zeros(len(COUNTS), dtype=np.int64)


def _scenes():
    out = [builtin_scene(n, 200) for n in BUILTIN]
    d = shared_scene_dir()
    if d is not None:
        out += [load_scene(d / f"{n}.json") for n in SHARED]
    return out


@pytest.fixture(scope="module")
def scenes():
    return _scenes()


def _buffers(sc, method, volume, monkeypatch, serial):
    with monkeypatch.context() as m:
        if serial:
            m.setattr(stencil, "rasterize", _serial)
        r = stencil.render_stencil(sc, method, volume=volume)
    return r.scene.depth, r.scene.tri_id, r.stencil


@pytest.mark.parametrize("method", ["zpass", "zfail"])
@pytest.mark.parametrize("volume", ["infinite", "truncated"])
def test_stencil_buffers_identical_to_the_serial_baseline(scenes, method, volume, monkeypatch):
    for sc in scenes:
        new = _buffers(sc, method, volume, monkeypatch, serial=False)
        old = _buffers(sc, method, volume, monkeypatch, serial=True)
        for a, b in zip(new, old):
            assert np.array_equal(a, b), sc.name
        assert (new[2] != 0).any(), sc.name


def test_planar_masks_identical_to_the_serial_baseline(scenes, monkeypatch):
    for sc in scenes:
        for variant in ("intended", "literal"):
            new = planar.planar_mask(sc, variant)[0]
            with monkeypatch.context() as m:
                m.setattr(planar, "rasterize", _serial)
                m.setattr(stencil, "rasterize", _serial)
                old = planar.planar_mask(sc, variant)[0]
            assert np.array_equal(new, old), (sc.name, variant)


def _random_clip(rng, n):
    """Triangles in clip space: mostly on screen, some across the near plane, the edges, w <= 0, w = 0."""
    tri = rng.normal(0.0, 1.0, (n, 3, 4))
    tri[..., 3] = rng.uniform(0.05, 3.0, (n, 3))
    tri[..., :2] *= tri[..., 3:4] * rng.uniform(0.2, 2.5, (n, 1, 1))
    tri[..., 2] = rng.uniform(-1.2, 1.0, (n, 3)) * tri[..., 3]
    tri[: n // 10, 0, 3] *= -1.0  # a vertex behind the eye
    tri[n // 10 : n // 5, 1, 3] = 0.0  # a vertex at infinity
    return np.ascontiguousarray(tri)


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("mode", [DEPTH, ZPASS, ZFAIL])
def test_random_triangles_identical_for_any_number_of_parts(seed, mode):
    rng = np.random.default_rng(seed)
    clip = _random_clip(rng, 400)
    ids = np.arange(len(clip), dtype=np.int64)
    base = new_buffers(97, 61)
    if mode != DEPTH:
        rasterize_serial(_random_clip(rng, 100), ids[:100], DEPTH, *base)  # a depth buffer to test against
    want = [b.copy() for b in base]
    rasterize_serial(clip, ids, mode, *want)
    assert (want[0] != base[0]).any() or (want[1] != 0).any()
    for parts in (1, 2, 3):
        got = [b.copy() for b in base]
        rasterize(clip, ids, mode, *got, parts=parts)
        for a, b in zip(got, want):
            assert np.array_equal(a, b), parts


@pytest.mark.parametrize("seed", [4, 5])
@pytest.mark.parametrize("mode", [DEPTH, ZPASS, ZFAIL])
def test_clearing_band_by_band_is_clearing_first(seed, mode):
    """``clear=True`` into buffers full of garbage draws what the baseline draws into cleared ones, for any
    number of parts (each band cleared by the part that draws it); the buffer a mode only reads is untouched."""
    rng = np.random.default_rng(seed)
    clip = _random_clip(rng, 300)
    ids = np.arange(len(clip), dtype=np.int64)
    depth, st, tri_id = new_buffers(83, 67)
    if mode != DEPTH:
        rasterize_serial(_random_clip(rng, 100), ids[:100], DEPTH, depth, st, tri_id)
    want = [depth.copy(), st.copy(), tri_id.copy()]
    rasterize_serial(clip, ids, mode, *want)
    for parts in (1, 2, 3):
        got = [depth.copy(), st.copy(), tri_id.copy()]
        written = [0, 2] if mode == DEPTH else [1]
        for k in written:
            got[k][:] = rng.integers(-9, 9, got[k].shape)
        rasterize(clip, ids, mode, *got, parts=parts, clear=True)
        for a, b in zip(got, want):
            assert np.array_equal(a, b), parts
    empty = [depth.copy(), np.full_like(st, 7), tri_id.copy()]
    rasterize(clip[:0], ids[:0], ZFAIL, *empty, clear=True)  # no triangle: still cleared
    assert not empty[1].any()


def _committed_mask(name):
    try:
        blob = subprocess.run(
            ["git", "-C", str(REPO), "show", f"318ab63:reports/renders/{name}"], capture_output=True, check=True
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("commit 318ab63 is not in this checkout (no git, or a source tarball)")
    return np.asarray(Image.open(io.BytesIO(blob)).convert("L")) >= 128


@pytest.mark.parametrize("name", SHARED)
def test_shared_scene_masks_equal_those_committed_at_318ab63(name):
    d = shared_scenes()
    sc = load_scene(d / f"{name}.json")
    truth = render_method(sc, "raycast")
    assert np.array_equal(truth.mask, _committed_mask(f"{name}.raycast.png"))
    assert np.array_equal(truth.coverage, _committed_mask(f"{name}.coverage.png"))
    for method in ("zpass", "zfail"):
        assert np.array_equal(render_method(sc, method).mask, _committed_mask(f"{name}.{method}.png")), method
    for variant in ("intended", "literal"):
        got = render_method(sc, "planar", variant=variant).mask
        assert np.array_equal(got, _committed_mask(f"{name}.planar-{variant}.png")), variant
    ref = render_method(sc, "zfail").mask
    for det in DETECTORS:
        for variant in ("intended", "literal"):
            got = render_method(sc, "zfail", det, variant).mask
            if (got != ref).any():  # 318ab63 wrote a detector's mask only where it differs from the reference
                assert np.array_equal(got, _committed_mask(f"{name}.zfail.{det}-{variant}.png")), (det, variant)
