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

``pertriangle`` (issue 41) finds no silhouette: each light-facing triangle's own capped volume
(:func:`.volumes.pertriangle_volume`), counted by z-fail.  Every frame logs its stages (:data:`STAGES`,
:class:`FrameLog`): seconds and the events :mod:`.stages` turns into operation counts.
"""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from silcount.detectors import detect
from silcount.errors import BadArgument, check_choice
from silcount.mesh.lights import DirectionalLight
from silcount.options import SHADOW_TESTS, VOLUMES
from silcount.render.camera import Camera
from silcount.render.raster import COUNTS, DEPTH, ZFAIL, ZPASS, homogeneous, new_buffers, rasterize, to_clip
from silcount.render.receiver import floor_plane
from silcount.render.scene import Scene
from silcount.render.volumes import Volume, build_volume, pertriangle_volume

METHODS = ("zpass", "zfail", "pertriangle")


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


STAGES = ("detection", "volume", "depth", "stencil", "lit", "final")
"""The frame's stages, in order (:mod:`.stages` counts and times them; the OpenGL frame uses the same names)."""


@dataclass
class FrameLog:
    """What one frame did, stage by stage: seconds (``time.perf_counter``) and events (:mod:`.stages` turns
    events into operation counts).  ``frame_seconds`` runs from the depth pass's start to the final test's
    end; the diagnostics after it (eye in a volume, open casters) are no stage."""

    seconds: dict[str, float] = field(default_factory=lambda: dict.fromkeys(STAGES, 0.0))
    events: dict[str, Counter] = field(default_factory=lambda: {s: Counter() for s in STAGES})
    detection: Counter = field(default_factory=Counter)  # the detectors' own true tallies, summed over casters
    frame_seconds: float = 0.0


@dataclass
class SceneDepth:
    """The scene's depth pass: depth, triangle id per pixel, the clip coordinates it used, its raster counts."""

    depth: np.ndarray
    tri_id: np.ndarray
    clip: np.ndarray
    counts: np.ndarray  # raster.COUNTS of the pass

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
    log: FrameLog  # seconds and events per stage
    eye_in_shadow: bool
    volume_clip: np.ndarray  # (T, 3, 4) the stencil pass's triangles in clip space, in drawing order
    warnings: list[str] = field(default_factory=list)

    @property
    def timings(self) -> dict[str, float]:
        """Seconds of the silhouette, the volume build and the rasterisation (the depth and stencil passes): the
        split ``benchmarks.render`` prints; :attr:`log` has every stage's."""
        sec = self.log.seconds
        return {"silhouette": sec["detection"], "volume": sec["volume"], "raster": sec["depth"] + sec["stencil"]}


@dataclass
class Framebuffer:
    """A frame's depth, stencil and triangle-id buffers (:func:`.raster.new_buffers`), kept from frame to frame
    as a GL application keeps its framebuffer: a frame drawn into one clears it (the clears are counted,
    ``pixels_cleared``) instead of allocating new memory, whose first touch is page faults that no GPU frame
    pays (torus_self_shadow at 1024^2: 2.7 ms of a 5.2 ms depth pass).  A result drawn into it holds views of
    it, valid until the next frame drawn into the same framebuffer."""

    depth: np.ndarray
    stencil: np.ndarray
    tri_id: np.ndarray

    @classmethod
    def of(cls, width: int, height: int) -> Framebuffer:
        return cls(*new_buffers(width, height))

    def check(self, camera: Camera) -> None:
        if self.depth.shape != (camera.height, camera.width):
            h, w = self.depth.shape
            raise BadArgument(f"a {w}x{h} framebuffer cannot hold a {camera.width}x{camera.height} frame")


_NO_STENCIL = np.zeros((1, 1), dtype=np.int32)  # the DEPTH mode never touches the stencil


def depth_pass(
    scene: Scene, camera: Camera, framebuffer: Framebuffer | None = None, scene_clip: np.ndarray | None = None
) -> SceneDepth:
    """Step (1): every scene triangle into the depth buffer, ids in scene order; into ``framebuffer``'s depth
    and ids (cleared first) if given, else into new buffers.  ``scene_clip``: the scene's triangles already in
    ``camera``'s clip space (:func:`.opengl.scene_clip`), else they are transformed here."""
    if scene_clip is None:
        clip = to_clip(homogeneous(scene.triangles), camera.view_projection)
    elif scene_clip.shape != (len(scene.triangles), 3, 4):
        raise BadArgument(f"scene_clip: {scene_clip.shape} is not the scene's ({len(scene.triangles)}, 3, 4) triangles")
    else:
        clip = scene_clip
    if framebuffer is None:  # new buffers, left as allocated: the pass clears them
        depth, tri_id = np.empty((camera.height, camera.width)), np.empty((camera.height, camera.width), np.int32)
    else:
        framebuffer.check(camera)
        depth, tri_id = framebuffer.depth, framebuffer.tri_id
    ids = np.arange(len(clip), dtype=np.int64)
    counts = rasterize(clip, ids, DEPTH, depth, _NO_STENCIL, tri_id, clear=True)  # the far plane, ids -1
    return SceneDepth(depth, tri_id, clip, counts)


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


def _caster_volume(
    scene: Scene,
    k: int,
    method: str,
    caps: bool,
    how: tuple[str, str],
    receiver,
    sd: SceneDepth,
    log: FrameLog,
    camera: Camera,
) -> tuple[Volume, np.ndarray]:
    """Caster ``k``'s volume and the clip-space triangles it draws (``caps``: with the light and dark caps), by
    ``camera``'s view-projection (computed on first use: in the volume stage, as the GL frame's is, when the
    depth pass was given the scene's clip coordinates); its detection (``how``: detector, variant) and volume
    construction logged."""
    mesh, ev = scene.objects[k].mesh, log.events["volume"]
    point = not isinstance(scene.light, DirectionalLight)
    t0 = time.perf_counter()
    if method == "pertriangle":
        iv = pertriangle_volume(mesh, scene.light)
        table = to_clip(iv.points, camera.view_projection)  # each point once: shared quads get the same bits
        sides, dark, vol = table[iv.sides], table[iv.dark_cap], iv.volume()
        ev["vertices_extruded"] += len(mesh.vertices) if point else 0
        ev["vertices_transformed"] += len(iv.points)
    else:
        sil = detect(mesh, scene.light, how[0], variant=how[1], engine="fast")
        t1 = time.perf_counter()
        log.seconds["detection"] += t1 - t0
        log.detection.update(sil.true_tally)
        t0 = t1
        vol = build_volume(mesh, scene.light, silhouette=sil, receiver=receiver)
        vp = camera.view_projection
        sides = to_clip(vol.sides, vp)
        dark = to_clip(vol.dark_cap, vp) if caps else np.zeros((0, 3, 4))
        if point and receiver is None:  # to_infinity: a - L for both ends of each edge, each unlit face's corners
            ev["vertices_extruded"] += 2 * len(sil.oriented) + 3 * len(vol.dark_cap)
        ev["vertices_transformed"] += 3 * (len(vol.sides) + len(dark))
    ev["faces_tested"] += mesh.n_faces  # the facing test behind the caps (and the per-triangle volumes)
    parts = [sides]
    if caps:  # the light cap: the scene's own clip coordinates, so its depth equals the stored one bit for bit
        first = sum(o.mesh.n_faces for o in scene.objects[:k])
        parts += [sd.clip[first : first + mesh.n_faces][vol.lit_faces], dark]
    clip = np.concatenate(parts, axis=0)
    ev["triangles_emitted"] += len(clip)
    log.seconds["volume"] += time.perf_counter() - t0
    return vol, clip


def render_stencil(
    scene: Scene,
    method: str = "zfail",
    detector: str = "reference",
    variant: str = "intended",
    depth: SceneDepth | None = None,
    shadow_test: str = "nonzero",
    volume: str = "infinite",
    framebuffer: Framebuffer | None = None,
    scene_clip: np.ndarray | None = None,
) -> StencilResult:
    """Shadow mask by stencil shadow volumes; ``depth`` reuses a depth pass of the same camera; ``framebuffer``
    (:class:`Framebuffer`) is drawn into instead of new buffers; ``scene_clip``: the scene's triangles in clip
    space (:func:`.opengl.scene_clip`), computed before the frame for a scene that does not move, as the GL
    frame uploads them once (:meth:`.opengl.GLFrame.set_scene`): the depth stage then transforms no vertex.

    ``method``: ``zpass``, ``zfail`` or ``pertriangle`` (z-fail on every light-facing triangle's own capped
    volume, :func:`.volumes.pertriangle_volume`: no detector runs, ``detector`` and ``variant`` are unused).
    ``shadow_test``: :func:`shadow_from_stencil`.  ``volume``: ``infinite`` (extruded to infinity),
    ``truncated`` (stopped at the floor plane by the stencil paper's "new pixel", :mod:`.volumes`) or
    ``sides`` (infinite, without caps: z-fail as the EESD paper prints it, "like Z-pass algorithm except step 5
    and 6", its step 4 giving the silhouette's quads only; z-pass draws no caps either way); ``pertriangle``
    takes ``infinite`` only.  The result's ``log`` holds each stage's seconds and events (:mod:`.stages`); a
    reused ``depth`` pass is not this frame's work, so its ``depth`` stage is empty.
    """
    check_choice("stencil method", method, METHODS)
    check_choice("shadow test", shadow_test, SHADOW_TESTS)
    check_choice("volume", volume, VOLUMES)
    if method == "pertriangle" and volume != "infinite":
        raise BadArgument(f"the pertriangle method draws infinite capped volumes, not {volume!r} ones")
    receiver: tuple[np.ndarray, float] | None = None
    if volume == "truncated":
        _, normal, offset = floor_plane(scene)
        receiver = (normal, offset)
    camera = Camera.of(scene)
    log = FrameLog()
    H, W = camera.height, camera.width
    start = t0 = time.perf_counter()
    sd = depth if depth is not None else depth_pass(scene, camera, framebuffer, scene_clip)
    if depth is None:
        log.events["depth"].update(dict(zip(COUNTS, sd.counts.tolist())))
        transformed = 3 * len(sd.clip) if scene_clip is None else 0
        log.events["depth"].update(
            pixels_cleared=2 * H * W, vertices_transformed=transformed, depth_writes=int(sd.counts[1])
        )
    log.seconds["depth"] += time.perf_counter() - t0
    caps = method == "pertriangle" or (method == "zfail" and volume != "sides")
    volumes, parts = [], []
    for k, obj in enumerate(scene.objects):
        if obj.casts_shadow:
            vol, clip = _caster_volume(scene, k, method, caps, (detector, variant), receiver, sd, log, camera)
            volumes.append(vol)
            parts.append(clip)
    t0 = time.perf_counter()  # every caster's volume in one pass: the stencil is a sum of +-1, in any order
    if framebuffer is None:
        stencil = np.empty((H, W), dtype=np.int32)  # cleared by the pass (clear=True)
    else:
        framebuffer.check(camera)
        stencil = framebuffer.stencil
    clip = np.ascontiguousarray(np.concatenate(parts, axis=0)) if parts else np.zeros((0, 3, 4))
    mode = ZPASS if method == "zpass" else ZFAIL
    counts = rasterize(
        clip, np.zeros(len(clip), dtype=np.int64), mode, sd.depth, stencil, sd.tri_id, clear=True
    )  # the stencil cleared to 0 band by band; depth and ids read only
    log.events["stencil"].update(pixels_cleared=H * W, **dict(zip(COUNTS, counts.tolist())))
    log.seconds["stencil"] += time.perf_counter() - t0
    t0 = time.perf_counter()  # the lit pass: the stencil test on every visible sample (one per covered pixel)
    covered = sd.coverage
    in_shadow = shadow_from_stencil(stencil[covered], shadow_test)
    log.events["lit"].update(coverage_tests=H * W, stencil_tests=len(in_shadow))
    log.seconds["lit"] += time.perf_counter() - t0
    t0 = time.perf_counter()  # the final test's result, the mask
    mask = np.zeros((H, W), dtype=bool)
    mask[covered] = in_shadow
    log.events["final"].update(pixels_cleared=H * W, mask_writes=len(in_shadow))
    log.seconds["final"] += time.perf_counter() - t0
    log.frame_seconds = time.perf_counter() - start
    return StencilResult(
        mask, covered, stencil, sd, volumes, log, eye_in_shadow(scene), clip, open_caster_warnings(scene)
    )
