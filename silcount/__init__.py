"""silcount: what silhouette detection really costs.

Instrumented detectors from Kolivand & Sunar (2011-2012), their cost models
as data, re-derived with sympy, and a software stencil shadow-volume
rasteriser that checks the shadows they produce.

>>> import silcount
>>> mesh = silcount.builtin_mesh("tetrahedron")
>>> res = silcount.detect(mesh, silcount.PointLight((0.0, 0.0, 5.0)), "ta")
>>> res.edges.shape[1]
2

The names below are loaded on first use (PEP 562), so ``import silcount``
costs nothing heavy; each lives in the subpackage named beside it.
Detectors are added with ``silcount.register_detector(silcount.DetectorSpec(...))`` or by an installed
package's entry point in the group ``silcount.detectors`` (``docs/extending.md``), found on first use.
``silcount.claims()`` and ``silcount.tables()`` return the reports' pandas
frames; ``silcount.corpus(paths, ...)`` sweeps a collection of meshes
(:mod:`silcount.study`); ``silcount.frame_stages(scene, method, ...)`` counts and times a shadow-volume
frame stage by stage (:mod:`silcount.render.stages`); ``silcount.worst_case(detector, ...)`` searches for a
worst case (:mod:`silcount.worstcase`).
"""

from __future__ import annotations

import importlib
import os
import sys
from typing import TYPE_CHECKING, Any

from silcount.errors import BadArgument, InvalidMesh, SilcountError, UnreadableInput
from silcount.version import __version__


def _numba_cache_default() -> None:
    """Point numba's cache of compiled kernels outside the source tree unless ``NUMBA_CACHE_DIR`` is set.

    In a virtual environment it is ``<venv>/cache/numba``, where ``make``'s install step compiles every
    kernel once (the ``silcount`` command's own default); otherwise ``$XDG_CACHE_HOME/silcount/numba``
    (``~/.cache/silcount/numba``).  Without it numba writes ``*.nbi``/``*.nbc`` files into
    ``silcount/*/__pycache__`` and a library user compiles everything again.  numba reads its settings
    when it is imported and again before each compilation, so an earlier ``import numba`` is told too.
    """
    if "NUMBA_CACHE_DIR" in os.environ:  # the user's (or the Makefile's) choice
        return
    if sys.prefix != sys.base_prefix:
        folder = os.path.join(sys.prefix, "cache", "numba")
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        folder = os.path.join(base, "silcount", "numba")
    os.environ["NUMBA_CACHE_DIR"] = folder
    config = sys.modules.get("numba.core.config")
    if config is not None:
        config.reload_config()


_numba_cache_default()


def _passive_wait_default() -> None:
    """Ask the OpenMP runtime under numba's ``omp`` layer to let idle pool threads sleep unless the user chose.

    Set before numba loads the layer (on the first parallel kernel), which reads it once.  With the default
    (spinning) wait, a pool thread that finished its share spins on its core until the others reach the
    barrier; on a busy machine that took the core from the very thread it waited for.  The numbers are in
    docs/performance.md, "Busy machines"; :mod:`silcount.threads` does the rest.
    """
    os.environ.setdefault("OMP_WAIT_POLICY", "passive")


_passive_wait_default()

# public name -> the module that defines it
_LAZY: dict[str, str] = {
    "DETECTORS": "silcount.detectors",
    "Silhouette": "silcount.detectors",
    "detect": "silcount.detectors",
    "load_mesh": "silcount.mesh.io",
    "PointLight": "silcount.mesh.lights",
    "DirectionalLight": "silcount.mesh.lights",
    "Mesh": "silcount.mesh.model",
    "from_polygons": "silcount.mesh.model",
    "builtin_mesh": "silcount.mesh.shapes",
    "shapes": "silcount.mesh",
    "detect_many": "silcount.detectors",
    "corpus": "silcount.study",
    "DetectorSpec": "silcount.detectors.spec",
    "register_detector": "silcount.detectors.registry",
    "frame_stages": "silcount.render.stages",
    "worst_case": "silcount.worstcase",
}
_LIVE = {"DETECTORS"}  # read on every access: registering a detector changes it

# public functions defined by another name in their module
_RENAMED: dict[str, tuple[str, str]] = {
    "claims": ("silcount.papers.claims", "claims_frame"),
    "tables": ("silcount.papers.tables", "tables_frame"),
}

if TYPE_CHECKING:
    from silcount.detectors import DETECTORS, Silhouette, detect, detect_many
    from silcount.detectors.registry import register_detector
    from silcount.detectors.spec import DetectorSpec
    from silcount.mesh import shapes
    from silcount.mesh.io import load_mesh
    from silcount.mesh.lights import DirectionalLight, PointLight
    from silcount.mesh.model import Mesh, from_polygons
    from silcount.mesh.shapes import builtin_mesh
    from silcount.papers.claims import claims_frame as claims
    from silcount.papers.tables import tables_frame as tables
    from silcount.render.stages import frame_stages
    from silcount.study import corpus
    from silcount.worstcase import worst_case


def __getattr__(name: str) -> Any:
    if name in _RENAMED:
        module, attr = _RENAMED[name]
    elif name in _LAZY:
        module, attr = _LAZY[name], name
    else:
        raise AttributeError(f"module 'silcount' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), attr)
    if name not in _LIVE:
        globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY) | set(_RENAMED))


__all__ = [
    "DETECTORS",
    "Silhouette",
    "detect",
    "detect_many",
    "DetectorSpec",
    "register_detector",
    "claims",
    "tables",
    "corpus",
    "frame_stages",
    "worst_case",
    "load_mesh",
    "PointLight",
    "DirectionalLight",
    "Mesh",
    "from_polygons",
    "builtin_mesh",
    "shapes",
    "SilcountError",
    "UnreadableInput",
    "InvalidMesh",
    "BadArgument",
    "__version__",
]
