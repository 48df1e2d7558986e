"""Silhouette detectors: one module per algorithm, each exposing ``detect(mesh, light, variant, engine)``.

| name        | paper, section                          | module        |
|-------------|-----------------------------------------|---------------|
| reference   | edge adjacency (silcount)               | reference.py  |
| ta          | HSD 2011 Sec. 4.1; EESD 2012 Sec. 3.1   | ta.py         |
| vnv         | HSD 2011 Sec. 4.2; EESD 2012 Sec. 3.2   | vnv.py        |
| hsd         | HSD 2011 Sec. V, 6.3                    | hsd.py        |
| eesd        | EESD 2012 Sec. 3.3, 5.3                 | eesd.py       |
| gaussmap    | Gooch et al., I3D 1999, Sec. 4.1        | gaussmap.py   |
| cones       | Johnson & Cohen, I3D 2001, Sec. 3;      | cones.py      |
|             | Sander et al., SIGGRAPH 2000, Sec. 3    |               |

The first five are the papers' (and silcount's O(E) yardstick); the last two
are the literature's output-sensitive detectors of the time, set beside them
(``docs/literature.md``).

Beside them: ``result.py`` (the result type, :class:`Silhouette`), ``base.py``
(counted visibility and assembling the result),
``adjacency.py`` (light-facing flags and the reference rule, shared by all),
``edge_array.py`` (TA's and HSD's array S), ``onplane.py`` (EESD literal's
point-on-plane search), ``hierarchy.py``, ``hierarchy_build.py``,
``hierarchy_walk.py``, ``hierarchy_naive.py`` and ``hierarchy_query.py`` (the
bounded plane tree gaussmap and cones share: the tree, its compiled build, its
compiled walk, both on counting arithmetic, and the detector glue),
``morton.py`` (their Z-order keys), ``eesd_rays.py`` (EESD's outward points and
rays) and ``eesd_counted.py`` (EESD's counted routines).  :data:`REGISTRY` maps each name to its ``detect``,
:data:`LABELS` to the name tables and figures give it; :data:`ONE_VARIANT` are
the detectors with one variant (:func:`variants_of`), and :func:`runs` names
each run of a sweep over detectors and variants.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Sequence
from types import ModuleType

import numpy as np

from silcount import options
from silcount.detectors.base import ENGINES, VARIANTS
from silcount.detectors.result import Silhouette, compare_with_reference, differences
from silcount.errors import check_choice
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh

Detector = Callable[..., Silhouette]
MODULES: tuple[ModuleType, ...] = tuple(importlib.import_module(f"{__name__}.{name}") for name in options.DETECTORS)
"""Each detector's module, named by :data:`silcount.options.DETECTORS` (where the command line reads the names
without importing the detectors): ``detect`` and what it declares of itself, from which the tables below are read
(so that a new detector touches its own module, that tuple and its ``silcount/models/`` file):

* ``NAME``; ``LABEL``, how tables and figures name it; ``PAPER_MODEL``, the ``silcount/models/`` file of its
  ``paper`` cost model; ``ONE_VARIANT``, ``variant`` accepted and ignored (one run, ``intended``);
* ``LITERATURE``, one of the literature's output-sensitive detectors beside the papers'; ``VISITED_STEP``,
  the step counting the edges (sides) its per-light loop examines;
* ``plain_edge_ids(mesh, light)``, its own loops (``intended``) compiled and uncounted, what a frame really
  pays (timed by ``silcount calibrate`` and the corpus study), returning the ascending ids ``detect``
  returns; ``PLAIN_QUADRATIC``, those loops visit every (edge, face) pair; where they use per-mesh
  preprocessing (cached with the mesh), ``plain_setup(mesh)`` to run it outside the timings;
* ``GROWTH_VARIANT``, the variant whose measured growth is set beside the paper's closed form (the one
  whose loops are the printed pseudo-code's); ``STYLE``, its colour and marker in every figure (the
  papers' circles, the yardsticks' other shapes).
"""
REGISTRY: dict[str, Detector] = {m.NAME: m.detect for m in MODULES}
DETECTORS: tuple[str, ...] = tuple(REGISTRY)
LITERATURE: tuple[str, ...] = tuple(m.NAME for m in MODULES if m.LITERATURE)  # beside the papers'
ONE_VARIANT: tuple[str, ...] = tuple(m.NAME for m in MODULES if m.ONE_VARIANT)  # one run, ``intended``
LABELS: dict[str, str] = {m.NAME: m.LABEL for m in MODULES}  # how tables and figures name each detector
PAPER_MODEL: dict[str, str] = {m.NAME: m.PAPER_MODEL for m in MODULES}  # the ``paper`` cost model's file
VISITED_STEP: dict[str, str] = {m.NAME: m.VISITED_STEP for m in MODULES}
"""The step counting the edges (sides, for TA and HSD) a detector's per-light loop examines."""
PAPERS: tuple[str, ...] = tuple(m.NAME for m in MODULES if not m.LITERATURE and m.NAME != "reference")
"""The papers' detectors (TA, VnV, HSD, EESD): neither the yardstick nor the literature's."""
PLAIN_QUADRATIC: tuple[str, ...] = tuple(m.NAME for m in MODULES if m.PLAIN_QUADRATIC)
GROWTH_VARIANT: dict[str, str] = {m.NAME: m.GROWTH_VARIANT for m in MODULES}
STYLES: dict[str, tuple[str, str]] = {m.NAME: m.STYLE for m in MODULES}  # colour, marker in every figure
_BY_NAME = {m.NAME: m for m in MODULES}


def plain_edge_ids(mesh: Mesh, light: Light, name: str) -> np.ndarray:
    """Detector ``name``'s own loops (``intended``), compiled and uncounted: the ascending ids ``detect`` returns.

    The papers' four and the reference run their printed loops (HSD over the merged polygons, cached with
    the mesh); ``gaussmap`` and ``cones`` their per-light query on the tree cached with the mesh, on one
    numba thread like every loop here.  Tested against :func:`detect` in ``tests/test_plain.py``.
    """
    check_choice("plain kernel", name, DETECTORS, error=ValueError)
    return _BY_NAME[name].plain_edge_ids(mesh, light)


def plain_setup(mesh: Mesh, name: str) -> None:
    """Run detector ``name``'s per-mesh preprocessing of its plain loops (none for most), cached with the mesh."""
    check_choice("plain kernel", name, DETECTORS, error=ValueError)
    setup = getattr(_BY_NAME[name], "plain_setup", None)
    if setup is not None:
        setup(mesh)


def variants_of(name: str, variants: Sequence[str]) -> tuple[str, ...]:
    """The variants of ``variants`` that are distinct runs of detector ``name``: ``intended`` alone for
    :data:`ONE_VARIANT`, whose ``literal`` would repeat it."""
    return ("intended",) if name in ONE_VARIANT else tuple(variants)


def runs(detectors: Sequence[str], variants: Sequence[str]) -> list[tuple[str, str, str]]:
    """``(key, detector, variant)`` for every distinct run of ``detectors`` under ``variants``
    (:func:`variants_of`): the key is the detector's name for ``intended``, ``name:variant`` otherwise, as
    the reports of ``silcount audit`` and ``silcount corpus`` name their runs."""
    out = []
    for name in detectors:
        for variant in variants_of(name, variants):
            out.append((name if variant == "intended" else f"{name}:{variant}", name, variant))
    return out


def is_reference_run(name: str, engine: str) -> bool:
    """Whether a run of ``name`` on ``engine`` is the reference's ``fast`` run, which a caller that always
    runs it (for agreement) reuses rather than repeats."""
    return name == "reference" and engine == "fast"


def detect(
    mesh: Mesh, light: Light, name: str = "reference", variant: str = "intended", engine: str = "fast"
) -> Silhouette:
    """Run detector ``name`` on ``mesh`` for ``light``; see :class:`Silhouette` for the result."""
    _check(name, variant, engine)
    return REGISTRY[name](mesh, light, variant=variant, engine=engine)


def _check(name: str, variant: str, engine: str) -> None:
    check_choice("detector", name, DETECTORS)
    check_choice("variant", variant, VARIANTS)
    check_choice("engine", engine, ENGINES)


def detect_many(
    mesh: Mesh, lights: Sequence[Light], name: str = "reference", variant: str = "intended", engine: str = "fast"
) -> list[Silhouette]:
    """:func:`detect` for each of ``lights``, identical results, in one pass where the algorithm allows.

    A detector whose module has ``detect_many(mesh, lights, variant)`` batches its ``fast`` engine: the
    ``reference`` packs 64 lights' facing flags into one word per face and finds every light's silhouette
    in one XOR pass over the edges (:func:`silcount.detectors.adjacency.many_edge_ids`); EESD tests every
    light's rays against their edges' own faces in one pass over the edges
    (:func:`silcount.detectors.eesd_rays.own_blocked`).  The others, and every ``naive`` engine, run per
    light.  ``tests/test_detect_many.py`` checks every field against :func:`detect`.
    """
    _check(name, variant, engine)
    lights = list(lights)
    many = getattr(_BY_NAME[name], "detect_many", None)
    if engine == "fast" and many is not None:
        return many(mesh, lights, variant)
    return [REGISTRY[name](mesh, light, variant=variant, engine=engine) for light in lights]


__all__ = [
    "DETECTORS",
    "GROWTH_VARIANT",
    "LABELS",
    "LITERATURE",
    "MODULES",
    "ONE_VARIANT",
    "PAPER_MODEL",
    "PAPERS",
    "PLAIN_QUADRATIC",
    "REGISTRY",
    "STYLES",
    "VISITED_STEP",
    "detect",
    "detect_many",
    "is_reference_run",
    "plain_edge_ids",
    "plain_setup",
    "runs",
    "variants_of",
    "Silhouette",
    "compare_with_reference",
    "differences",
]
