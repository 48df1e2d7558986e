"""The whole shadow-volume frame on OpenGL (Mesa llvmpipe), timed and counted stage by stage (issue 41).

Stages, named as the software renderer names them:

``detection``
    the detector on the CPU (wall time only); nothing for ``pertriangle``, which finds no silhouette.
``volume``
    the volume triangles built on the CPU (:mod:`.volumes` from the silhouette for ``zpass``/``zfail``,
    :func:`.volumes.pertriangle_volume` for ``pertriangle``: the software frame's geometry), taken to clip
    space and uploaded.
``depth``
    clear, then the scene into the depth buffer (``LESS``, cleared to 1) with the ambient colour
    (alpha 1 marks a covered pixel): the stencil paper Sec. 5 step (1).
``stencil``
    the volume faces into the stencil, depth and colour writes off, two-sided operations on one draw
    (steps (2)-(5); ``INCR_WRAP``/``DECR_WRAP``).  Z-pass: front faces increment, back faces decrement
    where ``LESS`` passes.  Z-fail (Everitt & Kilgard 2002, capped volumes, the camera's infinite far plane,
    as :mod:`.stencil` does): back faces increment, front faces decrement where ``LESS`` fails.  It is drawn
    as the same operations on depth *pass* under the complementary test ``GEQUAL`` (``not (z < d)`` is
    ``z >= d``, and depth writes are off), which changes no stencil value and makes the pass's
    samples-passed count the number of stencil updates, for both methods.
``lit``
    the scene again where the stencil is 0 (``EQUAL 0``), ``LEQUAL`` against the stored depth, depth writes
    off, the lit colour (steps (6)-(8) with the ``nonzero`` test).
``final``
    the colour read back and the mask formed: in shadow where the ambient pass drew and the lit pass did not.

Each stage is bounded by ``ctx.finish()`` (``glFinish``) on both sides and timed twice: wall time on the CPU
(``time.perf_counter``) and GPU time by a ``GL_TIME_ELAPSED`` query (moderngl's ``ctx.query(time=True)``),
which encloses a ``glFinish`` too, since llvmpipe rasterises when the commands are flushed.  On llvmpipe
the query still reports far less than the stage's wall time for the large draws (``python -m
benchmarks.frame_gl``, docs/performance.md: 20 ms against 228 ms for per-triangle volumes into the stencil on
torus_self_shadow at 512x512), so there the wall time is the measure and the query's time is only printed
beside it.
A ``GL_SAMPLES_PASSED`` query (``ctx.query(samples=True)``) on the same stage gives ``fragments``: the
fragments that passed the depth and stencil tests, i.e. depth writes in ``depth``, stencil updates in
``stencil`` and lit fragments in ``lit`` (none in the other stages).  The frame's wall time runs from the
first stage's start to the last one's end.

Vertices go to GL in clip coordinates (a pass-through vertex shader, float32), the scene's clip coordinates
computed once; z-fail's light caps are rows of that very array, so GL computes the caps' depth from the
same bits as the stored depth.  GL's window origin is the bottom-left corner: read-backs are flipped to
silcount's row 0 at the top.  The 8-bit stencil wraps; read as int8 it is silcount's count while counts stay
within -128..127.  moderngl opens the headless EGL context and runs the queries; PyOpenGL makes the other GL
calls (moderngl 5 has no stencil operations).  Both come with the ``gl`` extra, imported on first use;
without them, or without an EGL driver, :class:`silcount.errors.NoOpenGL` says which.  Importing this module
loads numpy alone (the detectors and the rasteriser's helpers on a frame's first use), so that
``tests/oracles/gl_stencil.py``'s whole llvmpipe process, which draws with :class:`GLFrame`, starts as a
plain GL application would.
"""

from __future__ import annotations

import ctypes
import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from silcount.errors import BadArgument, NoOpenGL, check_choice

if TYPE_CHECKING:
    from silcount.render.scene import Scene

STAGES = ("detection", "volume", "depth", "stencil", "lit", "final")
METHODS = ("zpass", "zfail", "pertriangle")
COLUMNS = ["stage", "detector", "method", "seconds_wall", "seconds_gpu", "fragments"]

VERTEX = """#version 330 core
layout(location = 0) in vec4 clip;
void main() { gl_Position = clip; }
"""
FRAGMENT = """#version 330 core
uniform vec4 colour;
out vec4 frag;
void main() { frag = colour; }
"""


def _open_gl() -> tuple[Any, Any]:
    """moderngl's headless EGL context and PyOpenGL's ``GL``; :class:`NoOpenGL` names what is missing."""
    os.environ.setdefault("PYOPENGL_PLATFORM", "egl")  # PyOpenGL picks its platform at import
    try:
        import moderngl
        from OpenGL import GL
    except ImportError as err:
        raise NoOpenGL(f"OpenGL frame: the gl extra is not installed ({err}); pip install 'silcount[gl]'") from err
    try:  # moderngl raises a bare Exception when EGL or its driver is missing
        ctx = moderngl.create_standalone_context(backend="egl")  # type: ignore[arg-type]
    except Exception as err:
        raise NoOpenGL(f"OpenGL frame: no headless EGL context ({type(err).__name__}: {err})") from err
    return ctx, GL


class GLFrame:
    """A headless GL context with a ``width`` x ``height`` RGBA8 + depth24/stencil8 framebuffer and the passes.

    :meth:`set_scene` uploads the scene once; :meth:`depth`, :meth:`stencil_pass`, :meth:`lit` and
    :meth:`read_mask` are the frame's GL stages (module docstring); :meth:`frame` runs the depth and stencil
    passes at once for the tests that compare stencil counts (``tests/oracles/gl_stencil.py``).
    """

    def __init__(self, width: int, height: int) -> None:
        self.ctx, self.gl = _open_gl()  # the context is kept alive here: it owns every GL object below
        GL = self.gl
        self.renderer = self.ctx.info["GL_RENDERER"]
        self.width, self.height = int(width), int(height)
        self.fbo = GL.glGenFramebuffers(1)
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self.fbo)
        colour, depth_stencil = GL.glGenRenderbuffers(2)
        for rb, fmt, attach in (
            (colour, GL.GL_RGBA8, GL.GL_COLOR_ATTACHMENT0),
            (depth_stencil, GL.GL_DEPTH24_STENCIL8, GL.GL_DEPTH_STENCIL_ATTACHMENT),
        ):
            GL.glBindRenderbuffer(GL.GL_RENDERBUFFER, rb)
            GL.glRenderbufferStorage(GL.GL_RENDERBUFFER, fmt, self.width, self.height)
            GL.glFramebufferRenderbuffer(GL.GL_FRAMEBUFFER, attach, GL.GL_RENDERBUFFER, rb)
        status = GL.glCheckFramebufferStatus(GL.GL_FRAMEBUFFER)
        if status != GL.GL_FRAMEBUFFER_COMPLETE:
            raise NoOpenGL(f"OpenGL frame: framebuffer incomplete (status {status:#x})")
        self.colour_uniform = self._use_program()
        GL.glBindVertexArray(GL.glGenVertexArrays(1))
        self.scene_vbo, self.volume_vbo = GL.glGenBuffers(2)
        self.n_scene = self.n_volume = 0
        self.scene_clip = np.zeros((0, 3, 4))  # the uploaded scene's clip coordinates (its light caps' rows)
        GL.glViewport(0, 0, self.width, self.height)
        GL.glDisable(GL.GL_CULL_FACE)
        GL.glClearDepth(1.0)
        GL.glClearStencil(0)
        GL.glClearColor(0.0, 0.0, 0.0, 0.0)
        # one time + samples-passed query per GL stage, reused frame after frame (moderngl frees none by itself)
        self.queries = {s: self.ctx.query(samples=True, time=True) for s in STAGES[1:]}

    def _use_program(self) -> int:
        """Compile, link and bind the pass-through program (the only one: it stays bound); its colour uniform."""
        GL = self.gl
        prog = GL.glCreateProgram()
        for kind, src in ((GL.GL_VERTEX_SHADER, VERTEX), (GL.GL_FRAGMENT_SHADER, FRAGMENT)):
            sh = GL.glCreateShader(kind)
            GL.glShaderSource(sh, src)
            GL.glCompileShader(sh)
            if not GL.glGetShaderiv(sh, GL.GL_COMPILE_STATUS):
                raise NoOpenGL(f"OpenGL frame: shader: {GL.glGetShaderInfoLog(sh).decode()}")
            GL.glAttachShader(prog, sh)
        GL.glLinkProgram(prog)
        GL.glUseProgram(prog)
        return int(GL.glGetUniformLocation(prog, "colour"))

    def _upload(self, vbo: int, clip: np.ndarray) -> int:
        GL = self.gl
        data = np.ascontiguousarray(clip, dtype=np.float32).reshape(-1, 4)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, vbo)
        GL.glBufferData(GL.GL_ARRAY_BUFFER, data.nbytes, data, GL.GL_STREAM_DRAW)
        return len(data)

    def _draw(self, vbo: int, n: int) -> None:
        GL = self.gl
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, vbo)
        GL.glEnableVertexAttribArray(0)
        GL.glVertexAttribPointer(0, 4, GL.GL_FLOAT, GL.GL_FALSE, 16, ctypes.c_void_p(0))
        GL.glDrawArrays(GL.GL_TRIANGLES, 0, n)

    def set_scene(self, clip: np.ndarray) -> None:
        """The (T, 3, 4) scene triangles in clip space, uploaded once (the scene does not move)."""
        self.scene_clip = clip
        self.n_scene = self._upload(self.scene_vbo, clip)

    def upload_volume(self, clip: np.ndarray) -> None:
        """The (V, 3, 4) volume triangles in clip space, for the next :meth:`stencil_pass`."""
        self.n_volume = self._upload(self.volume_vbo, clip)

    def depth(self) -> None:
        """Clear everything, then the scene with ``LESS``, depth writes on, the ambient colour (0, 0, 0, 1)."""
        GL = self.gl
        GL.glDepthMask(GL.GL_TRUE)  # the write masks gate glClear too: restore them first
        GL.glColorMask(GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE)
        GL.glStencilMask(0xFF)
        GL.glClear(GL.GL_COLOR_BUFFER_BIT | GL.GL_DEPTH_BUFFER_BIT | GL.GL_STENCIL_BUFFER_BIT)
        GL.glEnable(GL.GL_DEPTH_TEST)
        GL.glDepthFunc(GL.GL_LESS)
        GL.glDisable(GL.GL_STENCIL_TEST)
        GL.glUniform4f(self.colour_uniform, 0.0, 0.0, 0.0, 1.0)
        self._draw(self.scene_vbo, self.n_scene)

    def stencil_pass(self, method: str) -> None:
        """The uploaded volume into the stencil: z-pass, or z-fail as depth-pass operations under ``GEQUAL``
        (module docstring); ``pertriangle`` is z-fail."""
        GL = self.gl
        GL.glDepthMask(GL.GL_FALSE)
        GL.glColorMask(GL.GL_FALSE, GL.GL_FALSE, GL.GL_FALSE, GL.GL_FALSE)
        GL.glEnable(GL.GL_STENCIL_TEST)
        GL.glStencilFunc(GL.GL_ALWAYS, 0, 0xFF)
        keep, inc, dec = GL.GL_KEEP, GL.GL_INCR_WRAP, GL.GL_DECR_WRAP
        if method == "zpass":  # (face, stencil fail, depth fail, depth pass)
            GL.glDepthFunc(GL.GL_LESS)
            GL.glStencilOpSeparate(GL.GL_FRONT, keep, keep, inc)
            GL.glStencilOpSeparate(GL.GL_BACK, keep, keep, dec)
        else:  # where LESS fails = where GEQUAL passes
            GL.glDepthFunc(GL.GL_GEQUAL)
            GL.glStencilOpSeparate(GL.GL_BACK, keep, keep, inc)
            GL.glStencilOpSeparate(GL.GL_FRONT, keep, keep, dec)
        self._draw(self.volume_vbo, self.n_volume)

    def lit(self) -> None:
        """The scene again where the stencil is 0 and the depth is the stored one, in the lit colour."""
        GL = self.gl
        GL.glColorMask(GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE)
        GL.glDepthMask(GL.GL_FALSE)
        GL.glDepthFunc(GL.GL_LEQUAL)
        GL.glEnable(GL.GL_STENCIL_TEST)
        GL.glStencilFunc(GL.GL_EQUAL, 0, 0xFF)
        GL.glStencilOp(GL.GL_KEEP, GL.GL_KEEP, GL.GL_KEEP)
        GL.glUniform4f(self.colour_uniform, 1.0, 1.0, 1.0, 1.0)
        self._draw(self.scene_vbo, self.n_scene)

    def read_mask(self) -> np.ndarray:
        """The final test: (H, W) bool, in shadow where the ambient pass drew (alpha) and the lit pass did not."""
        GL = self.gl
        raw = GL.glReadPixels(0, 0, self.width, self.height, GL.GL_RGBA, GL.GL_UNSIGNED_BYTE)
        rgba = np.frombuffer(raw, dtype=np.uint8).reshape(self.height, self.width, 4)[::-1]
        return (rgba[..., 3] > 0) & (rgba[..., 0] == 0)

    def frame(self, volume_clip: np.ndarray, method: str) -> None:
        """Depth pass, volume upload, stencil pass; waits for the GPU (the tests read :meth:`stencil` after)."""
        self.depth()
        self.upload_volume(volume_clip)
        self.stencil_pass(method)
        self.ctx.finish()

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


@dataclass
class GLFrameResult:
    """One GL frame: its stages (a DataFrame, columns :data:`COLUMNS`), its mask and its wall time."""

    stages: Any  # pandas.DataFrame, one row per stage of STAGES, in order
    mask: np.ndarray  # (H, W) bool, in shadow
    seconds_frame: float  # wall time from the first stage's start to the last one's end


def scene_clip(scene: Scene) -> np.ndarray:
    """(T, 3, 4) every scene triangle in clip space, objects in file order (uploaded once by :meth:`set_scene`)."""
    from silcount.render.camera import Camera
    from silcount.render.raster import homogeneous, to_clip

    return to_clip(homogeneous(scene.triangles), Camera.of(scene).view_projection)


def _silhouettes(scene: Scene, detector: str, variant: str) -> list:
    """The detection stage: the detector's silhouette of every caster (None for objects that cast nothing)."""
    from silcount.detectors import detect

    return [
        detect(o.mesh, scene.light, detector, variant=variant, engine="fast") if o.casts_shadow else None
        for o in scene.objects
    ]


def _volume_clip(scene: Scene, clip: np.ndarray, method: str, silhouettes: list) -> np.ndarray:
    """The volume stage's geometry: (V, 3, 4) clip-space triangles, light caps taken from ``clip``'s rows."""
    from silcount.render.camera import Camera
    from silcount.render.raster import to_clip
    from silcount.render.volumes import build_volume, pertriangle_volume

    vp = Camera.of(scene).view_projection
    offsets = np.concatenate([[0], np.cumsum([o.mesh.n_faces for o in scene.objects])])
    parts = []
    for k, obj in enumerate(scene.objects):
        if not obj.casts_shadow:
            continue
        rows = clip[offsets[k] : offsets[k + 1]]
        if method == "pertriangle":  # the software frame's volumes (stencil.py), drawn by GL
            iv = pertriangle_volume(obj.mesh, scene.light)
            table = to_clip(iv.points, vp)
            parts += [table[iv.sides], rows[iv.lit_faces], table[iv.dark_cap]]
            continue
        vol = build_volume(obj.mesh, scene.light, silhouette=silhouettes[k])
        parts.append(to_clip(vol.sides, vp))
        if method == "zfail":
            parts += [rows[vol.lit_faces], to_clip(vol.dark_cap, vp)]
    return np.concatenate(parts, axis=0) if parts else np.zeros((0, 3, 4))


def gl_frame(
    scene: Scene,
    method: str = "zfail",
    detector: str = "reference",
    variant: str = "intended",
    gl: GLFrame | None = None,
) -> GLFrameResult:
    """One whole frame of ``scene`` on GL, stage by stage (module docstring).

    ``gl``: a :class:`GLFrame` of the scene's size whose scene is already uploaded (:func:`scene_clip`,
    :meth:`GLFrame.set_scene`), for repeated frames; without it one is opened and the scene uploaded first,
    outside the frame.  ``pertriangle`` runs no detector: its ``detection`` row is 0 s, detector ``none``.
    """
    import pandas as pd

    check_choice("OpenGL method", method, METHODS)
    if gl is None:
        gl = GLFrame(scene.width, scene.height)
        gl.set_scene(scene_clip(scene))
    clip = gl.scene_clip  # computed once with the upload, not every frame
    if (gl.width, gl.height) != (scene.width, scene.height):
        raise BadArgument(
            f"OpenGL frame: the context is {gl.width}x{gl.height}, the scene {scene.width}x{scene.height}"
        )
    ctx, queries = gl.ctx, gl.queries
    walls: dict[str, float] = {}

    @contextmanager
    def stage(name: str) -> Iterator[None]:
        """Wall time bounded by ``glFinish`` on both sides, and the stage's GL queries."""
        t = time.perf_counter()
        with queries[name]:
            yield
            ctx.finish()  # inside the query: llvmpipe rasterises at the flush, which the query must enclose
        ctx.finish()
        walls[name] = time.perf_counter() - t

    ctx.finish()
    start = time.perf_counter()
    silhouettes = _silhouettes(scene, detector, variant) if method != "pertriangle" else []
    walls["detection"] = time.perf_counter() - start
    with stage("volume"):
        gl.upload_volume(_volume_clip(scene, clip, method, silhouettes))
    with stage("depth"):
        gl.depth()
    with stage("stencil"):
        gl.stencil_pass(method)
    with stage("lit"):
        gl.lit()
    with stage("final"):
        mask = gl.read_mask()
    seconds_frame = time.perf_counter() - start
    counted = ("depth", "stencil", "lit")
    rows = [
        {
            "stage": s,
            "detector": "none" if method == "pertriangle" else detector,
            "method": method,
            "seconds_wall": walls[s],
            "seconds_gpu": queries[s].elapsed * 1e-9 if s in queries else float("nan"),
            "fragments": queries[s].samples if s in counted else pd.NA,
        }
        for s in STAGES
    ]
    frame = pd.DataFrame(rows, columns=COLUMNS).astype({"fragments": "Int64"})
    return GLFrameResult(frame, mask, seconds_frame)
