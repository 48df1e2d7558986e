"""Stencil shadow volumes, z-pass and z-fail (stencil paper Sec. 5; Everitt & Kilgard 2002).

Steps, as the stencil paper lists them (Sec. 5, steps (1)-(8)):

1. render the scene into the depth buffer (:data:`raster.DEPTH`);
2-3. depth writes off, stencil on;
4-5. z-pass: front-facing volume polygons increment, back-facing decrement,
   where the depth test passes.  z-fail (the paper's second (4)-(5)):
   back-facing increment, front-facing decrement, where it fails;
6-8. the final test.  The text says "if the number of stencil buffer is not
   zero it is therefore in the shadow": ``nonzero`` (the default, and what
   ray casting agrees with).  The printed step (8) is ``If (~Stencil % 2)``
   followed by "Keep Stencil"; ``parity`` is that printed form, literally
   (:func:`shadow_from_stencil` gives the readings).  They differ wherever two
   volumes overlap (stencil 2): parity lights the overlap of two shadows.

The paper's z-fail omits what makes it correct; we add Everitt & Kilgard's
robust form: the volume is capped (light cap = the lit faces, dark cap = the
unlit faces at infinity, :mod:`.volumes`) and the far plane is at infinity
(:mod:`.camera`), so no volume polygon is ever clipped by the far plane.  The
light cap is rasterised from the very clip coordinates of the scene
triangles, so its depth equals the stored depth bit for bit and ``LESS``
fails there, which counts it, as z-fail needs.  Z-pass needs no caps, but
it is wrong when the eye is inside a volume: the near plane cuts the
volume, the entering faces are lost (:func:`eye_in_shadow` reports that).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from silcount.detectors import detect
from silcount.errors import check_choice
from silcount.mesh.lights import DirectionalLight
from silcount.options import SHADOW_TESTS, VOLUMES
from silcount.render.camera import Camera
from silcount.render.raster import DEPTH, ZFAIL, ZPASS, homogeneous, new_buffers, rasterize, to_clip
from silcount.render.receiver import floor_plane
from silcount.render.scene import Scene
from silcount.render.volumes import Volume, build_volume

METHODS = ("zpass", "zfail")


def shadow_from_stencil(stencil: np.ndarray, test: str = "nonzero") -> np.ndarray:
    """In shadow, per pixel, from the stencil count (stencil paper Sec. 5, step (8)).

    ``nonzero``: ``stencil != 0``, the paper's own words ("not zero ... in the shadow").

    ``parity``: the printed ``If (~Stencil % 2)``.  In C, unary ``~`` binds tighter than ``%``, so it is
    ``(~Stencil) % 2``.  In two's complement ``~s = -s - 1``; C99 ``%`` truncates towards zero, so
    ``(-s - 1) % 2`` is ``0`` for odd ``s`` and ``-1`` (true) for even ``s``.  With an unsigned stencil
    (``~s = UINT_MAX - s``, ``UINT_MAX`` odd) it is ``1`` for even ``s``, ``0`` for odd: the same, and an
    8-bit stencil that wraps (256 is even) keeps the parity.  So the condition holds exactly where the
    stencil is **even**, zero included.  Step (8) follows steps (6)-(7), "render the all scene again with
    lighting" and "enable to write in color buffer": the condition says where the lit pass draws, so the
    pixel is lit where the stencil is even and in shadow where it is odd, ``stencil & 1``.

    Other readings, not implemented: ``~`` as the logical NOT of the paper's own ``Iff(~P_i, ...)`` and
    ``~Z_test`` gives ``(!Stencil) % 2 = !Stencil``, true iff the stencil is zero: lit where zero, which is
    ``nonzero``.  ``~(Stencil % 2)`` (against C precedence) is false only for negative odd stencils, which
    a closed volume never leaves; ``!(Stencil % 2)`` is ``parity`` again.  Taking the condition as "in
    shadow" rather than "lit" would shade every lit pixel (stencil 0 is even), so it is not a reading.
    """
    check_choice("shadow test", test, SHADOW_TESTS)
    if test == "nonzero":
        return stencil != 0
    return (stencil & 1) != 0  # parity


@dataclass
class SceneDepth:
    """The scene's depth pass: depth, triangle id per pixel and the clip coordinates it used."""

    depth: np.ndarray
    tri_id: np.ndarray
    clip: np.ndarray

    @property
    def coverage(self) -> np.ndarray:
        return self.tri_id >= 0


@dataclass
class StencilResult:
    mask: np.ndarray  # (H, W) bool, in shadow
    coverage: np.ndarray  # (H, W) bool
    stencil: np.ndarray  # (H, W) int32
    scene: SceneDepth
    volumes: list[Volume]
    timings: dict[str, float]  # seconds: silhouette, volume, raster
    eye_in_shadow: bool
    volume_clip: np.ndarray  # (T, 3, 4) the stencil pass's triangles in clip space, in drawing order
    warnings: list[str] = field(default_factory=list)


def depth_pass(scene: Scene, camera: Camera) -> SceneDepth:
    """Step (1): every scene triangle into the depth buffer, ids in scene order."""
    clip = to_clip(homogeneous(scene.triangles), camera.view_projection)
    depth, stencil, tri_id = new_buffers(camera.width, camera.height)
    rasterize(clip, np.arange(len(clip), dtype=np.int64), DEPTH, depth, stencil, tri_id)
    return SceneDepth(depth, tri_id, clip)


def segment_blocked(origin: np.ndarray, target: np.ndarray, triangles: np.ndarray) -> bool:
    """Does the open segment origin -> target cross any of the (T, 3, 3) triangles (Moller-Trumbore)?"""
    d = target - origin
    e1 = triangles[:, 1] - triangles[:, 0]
    e2 = triangles[:, 2] - triangles[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = det != 0
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - triangles[:, 0]
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ d) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (t < 1)
    return bool(hit.any())


def eye_in_shadow(scene: Scene) -> bool:
    """Is the eye inside a shadow volume, i.e. is its segment to the light blocked by a caster?"""
    tris = [o.triangles for o in scene.casters]
    if not tris:
        return False
    light = scene.light
    if isinstance(light, DirectionalLight):
        far = scene.eye + 1e6 * np.asarray(light.direction) / np.linalg.norm(light.direction)
    else:
        far = np.asarray(light.position)
    tri = np.concatenate(tris)
    lo, hi = np.minimum(scene.eye, far), np.maximum(scene.eye, far)
    box_lo = np.minimum(np.minimum(tri[:, 0], tri[:, 1]), tri[:, 2])  # elementwise: 4x faster than min(axis=1)
    box_hi = np.maximum(np.maximum(tri[:, 0], tri[:, 1]), tri[:, 2])
    near = ((box_lo <= hi) & (box_hi >= lo)).all(axis=1)  # boxes that can meet the segment
    return segment_blocked(scene.eye, far, tri[near])


def open_caster_warnings(scene: Scene) -> list[str]:
    """One warning per caster that is not closed and consistently wound, naming its open edges."""
    out = []
    for o in scene.casters:
        m = o.mesh
        if m.is_watertight:
            continue
        bad = np.concatenate([m.boundary_edges, m.nonmanifold_edges, m.inconsistent_edges])
        shown = ", ".join(f"{a}-{b}" for a, b in m.edges[bad[:8]].tolist())
        more = f" (and {bad.size - 8} more)" if bad.size > 8 else ""
        out.append(
            f"caster {o.name!r} is not closed and consistently wound: stencil counts are not exact; "
            f"{m.boundary_edges.size} boundary, {m.nonmanifold_edges.size} non-manifold, "
            f"{m.inconsistent_edges.size} inconsistently wound edges (vertex pairs {shown}{more})"
        )
    return out


def render_stencil(
    scene: Scene,
    method: str = "zfail",
    detector: str = "reference",
    variant: str = "intended",
    depth: SceneDepth | None = None,
    shadow_test: str = "nonzero",
    volume: str = "infinite",
) -> StencilResult:
    """Shadow mask by stencil shadow volumes; ``depth`` reuses a depth pass of the same camera.

    ``shadow_test``: :func:`shadow_from_stencil`.  ``volume``: ``infinite`` (extruded to infinity),
    ``truncated`` (stopped at the floor plane by the stencil paper's "new pixel", :mod:`.volumes`) or
    ``sides`` (infinite, without caps: z-fail as the EESD paper prints it, "like Z-pass algorithm except step 5
    and 6", its step 4 giving the silhouette's quads only; z-pass draws no caps either way).
    """
    check_choice("stencil method", method, METHODS)
    check_choice("shadow test", shadow_test, SHADOW_TESTS)
    check_choice("volume", volume, VOLUMES)
    receiver: tuple[np.ndarray, float] | None = None
    if volume == "truncated":
        _, normal, offset = floor_plane(scene)
        receiver = (normal, offset)
    camera = Camera.of(scene)
    timings = {"silhouette": 0.0, "volume": 0.0, "raster": 0.0}
    t0 = time.perf_counter()
    sd = depth if depth is not None else depth_pass(scene, camera)
    timings["raster"] += time.perf_counter() - t0
    stencil = np.zeros((camera.height, camera.width), dtype=np.int32)
    mode = ZPASS if method == "zpass" else ZFAIL
    offsets = np.concatenate([[0], np.cumsum([o.mesh.n_faces for o in scene.objects])])
    volumes, parts = [], []
    for k, obj in enumerate(scene.objects):
        if not obj.casts_shadow:
            continue
        t0 = time.perf_counter()
        sil = detect(obj.mesh, scene.light, detector, variant=variant, engine="fast")
        t1 = time.perf_counter()
        vol = build_volume(obj.mesh, scene.light, silhouette=sil, receiver=receiver)
        parts.append(to_clip(vol.sides, camera.view_projection))
        if method == "zfail" and volume != "sides":
            parts.append(sd.clip[offsets[k] : offsets[k + 1]][vol.lit_faces])
            parts.append(to_clip(vol.dark_cap, camera.view_projection))
        timings["silhouette"] += t1 - t0
        timings["volume"] += time.perf_counter() - t1
        volumes.append(vol)
    t0 = time.perf_counter()  # every caster's volume in one pass: the stencil is a sum of +-1, in any order
    clip = np.ascontiguousarray(np.concatenate(parts, axis=0)) if parts else np.zeros((0, 3, 4))
    if parts:
        rasterize(clip, np.zeros(len(clip), dtype=np.int64), mode, sd.depth, stencil, sd.tri_id)  # read-only here
    timings["raster"] += time.perf_counter() - t0
    mask = sd.coverage & shadow_from_stencil(stencil, shadow_test)
    return StencilResult(
        mask, sd.coverage, stencil, sd, volumes, timings, eye_in_shadow(scene), clip, open_caster_warnings(scene)
    )
