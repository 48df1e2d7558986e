"""Silhouette detectors: one module per algorithm, each exposing ``detect(mesh, light, variant, engine)``.

| name        | paper, section                          | module        |
|-------------|-----------------------------------------|---------------|
| reference   | edge adjacency (silcount)               | reference.py  |
| ta          | HSD 2011 Sec. 4.1; EESD 2012 Sec. 3.1   | ta.py         |
| vnv         | HSD 2011 Sec. 4.2; EESD 2012 Sec. 3.2   | vnv.py        |
| hsd         | HSD 2011 Sec. V, 6.3                    | hsd.py        |
| eesd        | EESD 2012 Sec. 3.3, 5.3                 | eesd.py       |
"""
from __future__ import annotations

import importlib

from ..errors import BadArgument
from ..lights import Light
from ..mesh import Mesh
from .base import ENGINES, VARIANTS, Silhouette

DETECTORS: tuple[str, ...] = ("reference", "ta", "vnv", "hsd", "eesd")


def detect(mesh: Mesh, light: Light, name: str = "reference", variant: str = "intended", engine: str = "fast") -> Silhouette:
    """Run detector ``name`` on ``mesh`` for ``light``; see :class:`Silhouette` for the result."""
    if name not in DETECTORS:
        raise BadArgument(f"unknown detector {name!r}; choose from {', '.join(DETECTORS)}")
    if variant not in VARIANTS:
        raise BadArgument(f"unknown variant {variant!r}; choose from {', '.join(VARIANTS)}")
    if engine not in ENGINES:
        raise BadArgument(f"unknown engine {engine!r}; choose from {', '.join(ENGINES)}")
    module = importlib.import_module(f".{name}", __name__)
    return module.detect(mesh, light, variant=variant, engine=engine)


__all__ = ["DETECTORS", "detect", "Silhouette"]
