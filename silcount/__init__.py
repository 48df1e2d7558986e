"""silcount: what silhouette detection really costs.

Instrumented detectors from Kolivand & Sunar (2011-2012), their cost models
as data, re-derived with sympy, and a software stencil shadow-volume
rasteriser that checks the shadows they produce.

>>> import silcount
>>> mesh = silcount.builtin_mesh("tetrahedron")
>>> res = silcount.detect(mesh, silcount.PointLight((0.0, 0.0, 5.0)), "ta")
>>> res.edges.shape[1]
2
"""
from __future__ import annotations

from .detectors import DETECTORS, Silhouette, detect
from .errors import BadArgument, InvalidMesh, SilcountError, UnreadableInput
from .io import load_mesh
from .lights import DirectionalLight, PointLight
from .mesh import Mesh, from_polygons
from . import shapes
from .shapes import builtin_mesh

__version__ = "0.1.0"

__all__ = [
    "DETECTORS", "Silhouette", "detect", "load_mesh", "PointLight", "DirectionalLight", "Mesh",
    "from_polygons", "builtin_mesh", "shapes", "SilcountError", "UnreadableInput", "InvalidMesh", "BadArgument",
    "__version__",
]
