"""The same stencil shadow-volume frame on Mesa's llvmpipe, through OpenGL (issue 15, "Rendering").

A benchmark baseline, not part of silcount (which renders without OpenGL):
``python -m benchmarks.render --llvmpipe`` times it against the software
rasteriser in the same run and compares the masks pixel by pixel.

The GL frame draws exactly the triangles silcount's rasteriser draws, in
the same clip coordinates (a pass-through vertex shader; float32 on the
GPU side where silcount keeps float64): the scene into the depth buffer
(``LESS``, cleared to 1), then every caster's volume with depth writes and
colour off and the two-sided stencil of the stencil paper Sec. 5 steps
(4)-(5) (``INCR_WRAP``/``DECR_WRAP``, back/front for z-fail, front/back for
z-pass), as :mod:`silcount.render.raster` does.  GL's window origin is the
bottom-left corner, so read-backs are flipped to silcount's row 0 at the top.
The 8-bit stencil wraps; read as int8 it equals silcount's int32 count
while counts stay within -128..127.

Needs ``moderngl`` (only to open a headless EGL context) and ``PyOpenGL``
(every GL call), both from PyPI: ``pip install moderngl PyOpenGL``.
"""

from __future__ import annotations

import ctypes
import os

import numpy as np

os.environ.setdefault("PYOPENGL_PLATFORM", "egl")

VERTEX = """#version 330 core
layout(location = 0) in vec4 clip;
void main() { gl_Position = clip; }
"""
FRAGMENT = """#version 330 core
out vec4 colour;
void main() { colour = vec4(1.0); }
"""


class GLStencil:
    """A headless llvmpipe context with a ``width`` x ``height`` colour + depth24/stencil8 framebuffer."""

    def __init__(self, width: int, height: int) -> None:
        import moderngl
        from OpenGL import GL

        self.gl = GL
        # kept alive: it owns the context; moderngl types its **kwargs oddly (dict[str, Any] each)
        self.ctx = moderngl.create_standalone_context(backend="egl")  # type: ignore[arg-type]
        self.renderer = self.ctx.info["GL_RENDERER"]
        self.width, self.height = width, height
        self.fbo = GL.glGenFramebuffers(1)
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self.fbo)
        colour, depth_stencil = GL.glGenRenderbuffers(2)
        for rb, fmt, attach in (
            (colour, GL.GL_RGBA8, GL.GL_COLOR_ATTACHMENT0),
            (depth_stencil, GL.GL_DEPTH24_STENCIL8, GL.GL_DEPTH_STENCIL_ATTACHMENT),
        ):
            GL.glBindRenderbuffer(GL.GL_RENDERBUFFER, rb)
            GL.glRenderbufferStorage(GL.GL_RENDERBUFFER, fmt, width, height)
            GL.glFramebufferRenderbuffer(GL.GL_FRAMEBUFFER, attach, GL.GL_RENDERBUFFER, rb)
        status = GL.glCheckFramebufferStatus(GL.GL_FRAMEBUFFER)
        if status != GL.GL_FRAMEBUFFER_COMPLETE:
            raise RuntimeError(f"gl_stencil: framebuffer incomplete (status {status:#x})")
        self._use_program()
        self.vao = GL.glGenVertexArrays(1)
        GL.glBindVertexArray(self.vao)
        self.scene_vbo, self.volume_vbo = GL.glGenBuffers(2)
        self.n_scene = 0
        GL.glViewport(0, 0, width, height)
        GL.glDisable(GL.GL_CULL_FACE)
        GL.glClearDepth(1.0)
        GL.glClearStencil(0)

    def _use_program(self) -> None:
        """Compile, link and bind the pass-through program (the only one: it stays bound)."""
        GL = self.gl
        prog = GL.glCreateProgram()
        for kind, src in ((GL.GL_VERTEX_SHADER, VERTEX), (GL.GL_FRAGMENT_SHADER, FRAGMENT)):
            sh = GL.glCreateShader(kind)
            GL.glShaderSource(sh, src)
            GL.glCompileShader(sh)
            if not GL.glGetShaderiv(sh, GL.GL_COMPILE_STATUS):
                raise RuntimeError(f"gl_stencil: shader: {GL.glGetShaderInfoLog(sh).decode()}")
            GL.glAttachShader(prog, sh)
        GL.glLinkProgram(prog)
        GL.glUseProgram(prog)

    def _upload(self, vbo: int, clip: np.ndarray) -> int:
        GL = self.gl
        data = np.ascontiguousarray(clip, dtype=np.float32).reshape(-1, 4)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, vbo)
        GL.glBufferData(GL.GL_ARRAY_BUFFER, data.nbytes, data, GL.GL_STREAM_DRAW)
        GL.glEnableVertexAttribArray(0)
        GL.glVertexAttribPointer(0, 4, GL.GL_FLOAT, GL.GL_FALSE, 16, ctypes.c_void_p(0))
        return len(data)

    def set_scene(self, clip: np.ndarray) -> None:
        """The (T, 3, 4) scene triangles in clip space, uploaded once (the scene does not move)."""
        self.n_scene = self._upload(self.scene_vbo, clip)

    def frame(self, volume_clip: np.ndarray, method: str) -> None:
        """One frame: clear, depth pass of the scene, volume upload, stencil pass; waits for the GPU."""
        GL = self.gl
        GL.glDepthMask(GL.GL_TRUE)  # the write masks gate glClear too: restore them first
        GL.glColorMask(GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE)
        GL.glClear(GL.GL_COLOR_BUFFER_BIT | GL.GL_DEPTH_BUFFER_BIT | GL.GL_STENCIL_BUFFER_BIT)
        GL.glEnable(GL.GL_DEPTH_TEST)
        GL.glDepthFunc(GL.GL_LESS)
        GL.glDisable(GL.GL_STENCIL_TEST)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, self.scene_vbo)
        GL.glVertexAttribPointer(0, 4, GL.GL_FLOAT, GL.GL_FALSE, 16, ctypes.c_void_p(0))
        GL.glDrawArrays(GL.GL_TRIANGLES, 0, self.n_scene)
        n = self._upload(self.volume_vbo, volume_clip)
        GL.glDepthMask(GL.GL_FALSE)
        GL.glColorMask(GL.GL_FALSE, GL.GL_FALSE, GL.GL_FALSE, GL.GL_FALSE)
        GL.glEnable(GL.GL_STENCIL_TEST)
        GL.glStencilFunc(GL.GL_ALWAYS, 0, 0xFF)
        keep, inc, dec = GL.GL_KEEP, GL.GL_INCR_WRAP, GL.GL_DECR_WRAP
        if method == "zfail":  # (face, stencil fail, depth fail, depth pass)
            GL.glStencilOpSeparate(GL.GL_BACK, keep, inc, keep)
            GL.glStencilOpSeparate(GL.GL_FRONT, keep, dec, keep)
        else:
            GL.glStencilOpSeparate(GL.GL_FRONT, keep, keep, inc)
            GL.glStencilOpSeparate(GL.GL_BACK, keep, keep, dec)
        GL.glDrawArrays(GL.GL_TRIANGLES, 0, n)
        GL.glFinish()

    def stencil(self) -> np.ndarray:
        """The stencil as int8 counts, (H, W), row 0 at the top."""
        GL = self.gl
        raw = GL.glReadPixels(0, 0, self.width, self.height, GL.GL_STENCIL_INDEX, GL.GL_UNSIGNED_BYTE)
        return np.frombuffer(raw, dtype=np.int8).reshape(self.height, self.width)[::-1]

    def coverage(self) -> np.ndarray:
        """Where the depth pass drew (depth below the cleared 1), (H, W), row 0 at the top."""
        GL = self.gl
        raw = GL.glReadPixels(0, 0, self.width, self.height, GL.GL_DEPTH_COMPONENT, GL.GL_FLOAT)
        return (np.frombuffer(raw, dtype=np.float32).reshape(self.height, self.width) < 1.0)[::-1]


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
    gl = GLStencil(width, height)
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
