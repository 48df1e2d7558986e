"""Silhouette detectors: one module per algorithm, each exposing ``detect(mesh, light, variant, engine)``.

| name        | paper, section                          | module        |
|-------------|-----------------------------------------|---------------|
| reference   | edge adjacency (silcount)               | reference.py  |
| ta          | HSD 2011 Sec. 4.1; EESD 2012 Sec. 3.1   | ta.py         |
| vnv         | HSD 2011 Sec. 4.2; EESD 2012 Sec. 3.2   | vnv.py        |
| hsd         | HSD 2011 Sec. V, 6.3                    | hsd.py        |
| eesd        | EESD 2012 Sec. 3.3, 5.3                 | eesd.py       |

Beside them: ``base.py`` (the result type, counted visibility),
``adjacency.py`` (light-facing flags and the reference rule, shared by all),
``edge_array.py`` (TA's and HSD's array S), ``onplane.py`` (EESD literal's
point-on-plane search) and ``plain.py`` (each algorithm's loops compiled and
uncounted, for timing).  :data:`REGISTRY` maps each name to its ``detect``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from silcount.detectors import eesd, hsd, reference, ta, vnv
from silcount.detectors.base import ENGINES, VARIANTS, Silhouette
from silcount.errors import BadArgument
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

Detector = Callable[..., Silhouette]
REGISTRY: dict[str, Detector] = {
    "reference": reference.detect,
    "ta": ta.detect,
    "vnv": vnv.detect,
    "hsd": hsd.detect,
    "eesd": eesd.detect,
}
DETECTORS: tuple[str, ...] = tuple(REGISTRY)


def detect(
    mesh: Mesh, light: Light, name: str = "reference", variant: str = "intended", engine: str = "fast"
) -> Silhouette:
    """Run detector ``name`` on ``mesh`` for ``light``; see :class:`Silhouette` for the result."""
    _check(name, variant, engine)
    return REGISTRY[name](mesh, light, variant=variant, engine=engine)


def _check(name: str, variant: str, engine: str) -> None:
    if name not in DETECTORS:
        raise BadArgument(f"unknown detector {name!r}; choose from {', '.join(DETECTORS)}")
    if variant not in VARIANTS:
        raise BadArgument(f"unknown variant {variant!r}; choose from {', '.join(VARIANTS)}")
    if engine not in ENGINES:
        raise BadArgument(f"unknown engine {engine!r}; choose from {', '.join(ENGINES)}")


def detect_many(
    mesh: Mesh, lights: Sequence[Light], name: str = "reference", variant: str = "intended", engine: str = "fast"
) -> list[Silhouette]:
    """:func:`detect` for each of ``lights``, identical results, in one pass where the algorithm allows.

    The ``reference`` detector's ``fast`` engine packs 64 lights' facing flags
    into one word per face and finds every light's silhouette in one XOR pass
    over the edges (:func:`silcount.detectors.adjacency.many_edge_ids`); the
    others run per light.
    """
    _check(name, variant, engine)
    lights = list(lights)
    if name == "reference" and engine == "fast":
        return reference.detect_many(mesh, lights, variant)
    return [REGISTRY[name](mesh, light, variant=variant, engine=engine) for light in lights]


__all__ = ["DETECTORS", "REGISTRY", "detect", "detect_many", "Silhouette"]
