"""A second, numpy-only silhouette and volume builder for the OpenGL frame, and a whole llvmpipe process (issue 15).

The GL passes themselves are :class:`silcount.render.opengl.GLFrame` (once this module's ``GLStencil``; issue
41 moved them into the package to time the frame stage by stage): GL rasterises, tests and clips the very
clip-space triangles silcount draws, with its own depth test and two-sided stencil, so the masks it gives
are an independent implementation of the stencil steps.  What stays here is what a GL application would do
on the CPU with no silcount code at all: :func:`bake` ships the scene, :func:`volume_clip` finds the
silhouette and builds the volume with numpy, and :func:`process` is the whole llvmpipe process that
``python -m benchmarks.render --llvmpipe --whole-process`` times against ``silcount render``.

Needs the ``gl`` extra (moderngl, PyOpenGL): ``pip install moderngl PyOpenGL``.
"""

from __future__ import annotations

import numpy as np

from silcount.render.opengl import GLFrame


def bake(scene, path: str) -> None:
    """Write what a GL application would ship for ``scene``: world triangles, the camera, each caster's edge table.

    The edge table is each two-face edge's faces ``f0, f1`` and its vertices ``u, v`` as ``f0`` traverses
    them (an offline precompute, as silcount's per-mesh adjacency); :func:`process` needs nothing else.
    """
    from silcount.render.camera import Camera

    arrays = {"vp": Camera.of(scene).view_projection, "scene": scene.triangles}
    arrays["size"] = np.array([scene.width, scene.height])
    arrays["light"] = np.asarray(scene.light.position, dtype=float)  # the shared scenes' point light
    for k, obj in enumerate(scene.casters):
        f = obj.mesh.faces
        u, v = f.ravel(), np.roll(f, -1, axis=1).ravel()
        key = np.minimum(u, v) * len(obj.mesh.vertices) + np.maximum(u, v)
        order = np.argsort(key, kind="stable")
        pair = np.flatnonzero(key[order][1:] == key[order][:-1])
        first, second = order[pair], order[pair + 1]
        arrays[f"v{k}"], arrays[f"f{k}"] = obj.mesh.vertices, f
        arrays[f"e{k}"] = np.stack([first // 3, second // 3, u[first], v[first]], axis=1)
    np.savez(path, **arrays)


def volume_clip(baked, method: str) -> np.ndarray:
    """Every caster's shadow volume in clip space, computed with numpy from the baked arrays."""
    L, vp, parts, k = baked["light"], baked["vp"], [], 0
    while f"v{k}" in baked:
        V, F, E = baked[f"v{k}"], baked[f"f{k}"], baked[f"e{k}"]
        p0, p1, p2 = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
        lit = np.einsum("ij,ij->i", L - p0, np.cross(p1 - p0, p2 - p0)) > 0  # (L - p0) . n > 0
        sil = E[lit[E[:, 0]] != lit[E[:, 1]]]
        a = np.where(lit[sil[:, 0]], sil[:, 2], sil[:, 3])  # traversed as the lit face traverses it
        b = np.where(lit[sil[:, 0]], sil[:, 3], sil[:, 2])
        one, zero = np.ones((len(a), 1)), np.zeros((len(a), 1))
        ah, bh = np.hstack([V[a], one]), np.hstack([V[b], one])
        ai, bi = np.hstack([V[a] - L, zero]), np.hstack([V[b] - L, zero])
        parts += [np.stack([bh, ah, ai], axis=1), np.stack([bh, ai, bi], axis=1)]
        if method == "zfail":
            caps = V[F]
            parts.append(np.concatenate([caps[lit], np.ones(caps[lit].shape[:2] + (1,))], axis=2))
            parts.append(np.concatenate([caps[~lit] - L, np.zeros(caps[~lit].shape[:2] + (1,))], axis=2))
        k += 1
    return np.concatenate(parts) @ vp.T


def process(baked_path: str, out: str, method: str) -> None:
    """A whole llvmpipe process: load the baked scene, one frame, the mask as a PNG; prints stage times."""
    import time

    t0 = time.perf_counter()
    from PIL import Image

    baked = dict(np.load(baked_path))
    t1 = time.perf_counter()
    width, height = (int(x) for x in baked["size"])
    gl = GLFrame(width, height)
    scene = np.concatenate([baked["scene"], np.ones(baked["scene"].shape[:2] + (1,))], axis=2) @ baked["vp"].T
    gl.set_scene(scene)
    t2 = time.perf_counter()
    gl.frame(volume_clip(baked, method), method)
    mask = gl.coverage() & (gl.stencil() != 0)
    t3 = time.perf_counter()
    Image.fromarray(np.where(mask, 255, 0).astype(np.uint8), mode="L").save(out)
    print(t1 - t0, t2 - t1, t3 - t2, time.perf_counter() - t3)


if __name__ == "__main__":
    import sys

    process(*sys.argv[1:4])
