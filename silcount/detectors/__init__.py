"""Silhouette detectors: each a :class:`.spec.DetectorSpec` in the registry (:mod:`.registry`).

The built-ins (:mod:`.builtin`) are the papers' four (TA, VnV, HSD, EESD), silcount's O(E) yardstick
(``reference``) and the literature's output-sensitive detectors of the time (``gaussmap``, ``cones``;
``docs/literature.md``); installed plug-ins add theirs through the entry-point group ``silcount.detectors``
(``docs/extending.md``).  Nothing here is read before first use: :func:`names` and every look-up fill the
registry then.

The detectors: ``reference.py``, ``ta.py``, ``vnv.py``, ``hsd.py``; in ``eesd/``, EESD with its rays, counted
routines and point-on-plane search; in ``hierarchy/``, ``gaussmap`` and ``cones`` with the bounded plane tree
they share.  Beside them: ``spec.py`` (the record),
``registry.py`` (the registry), ``builtin.py`` (the built-ins' specs), ``result.py`` (the result type,
:class:`Silhouette`), ``batch.py`` (many lights' results, columnar: :class:`SilhouetteBatch`), ``base.py``
(counted visibility and assembling the result), ``adjacency.py``
(light-facing flags and the reference rule, shared by all) and ``edge_array.py`` (TA's and HSD's array
S).  :func:`runs` names each run of a sweep over
detectors and variants.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from silcount.detectors.batch import SilhouetteBatch
from silcount.detectors.registry import get, names, register_detector, specs, with_role
from silcount.detectors.result import Silhouette, compare_with_reference, differences
from silcount.detectors.spec import ENGINES, VARIANTS, DetectorSpec
from silcount.errors import check_choice
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh
from silcount.threads import fitted_call


def __getattr__(name: str) -> tuple[str, ...]:
    """``DETECTORS``: the registered names, read from the registry on each access (PEP 562)."""
    if name == "DETECTORS":
        return names()
    raise AttributeError(f"module 'silcount.detectors' has no attribute {name!r}")


def plain_edge_ids(mesh: Mesh, light: Light, name: str) -> np.ndarray:
    """Detector ``name``'s own loops (``intended``), compiled and uncounted: the ascending ids ``detect`` returns.

    The papers' four and the reference run their printed loops (HSD over the merged polygons, cached with
    the mesh); ``gaussmap`` and ``cones`` their per-light query on the tree cached with the mesh, on one
    numba thread like every loop here.  Tested against :func:`detect` in ``tests/test_plain.py``.  A
    detector without plain loops (``spec.plain_edge_ids is None``) raises ``ValueError``.
    """
    spec = get(name, error=ValueError, prefix="plain kernel: ")
    if spec.plain_edge_ids is None:
        raise ValueError(f"detector {name!r} has no plain loops")
    return spec.plain_edge_ids(mesh, light)


def plain_setup(mesh: Mesh, name: str) -> None:
    """Run detector ``name``'s per-mesh preprocessing of its plain loops (none for most), cached with the mesh."""
    setup = get(name, error=ValueError, prefix="plain kernel: ").plain_setup
    if setup is not None:
        setup(mesh)


def variants_of(name: str, variants: Sequence[str]) -> tuple[str, ...]:
    """The variants of ``variants`` that are distinct runs of detector ``name``: ``intended`` alone for a
    detector of one variant, whose ``literal`` would repeat it."""
    own = get(name).variants
    return ("intended",) if len(own) == 1 else tuple(v for v in variants if v in own)


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


@fitted_call
def detect(
    mesh: Mesh, light: Light, name: str = "reference", variant: str = "intended", engine: str = "fast"
) -> Silhouette:
    """Run detector ``name`` on ``mesh`` for ``light``; see :class:`Silhouette` for the result."""
    return _check(name, variant, engine).detect(mesh, light, variant=variant, engine=engine)


def _check(name: str, variant: str, engine: str) -> DetectorSpec:
    spec = get(name)
    check_choice("variant", variant, VARIANTS)
    check_choice("engine", engine, ENGINES)
    check_choice(f"engine of {name}", engine, spec.engines)
    return spec


@fitted_call
def detect_many(
    mesh: Mesh, lights: Sequence[Light], name: str = "reference", variant: str = "intended", engine: str = "fast"
) -> SilhouetteBatch:
    """:func:`detect` for each of ``lights``, identical results, in one pass where the algorithm allows.

    The result is a :class:`.batch.SilhouetteBatch`: a sequence of :class:`Silhouette` (``batch[i]``,
    iteration; each made when asked for, equal to :func:`detect`'s for that light) whose arrays hold every
    light's edges as CSR and its steps, tallies and ties, for consumers of many lights.  Every built-in's
    ``fast`` engine batches: the ``reference`` packs 64 lights' facing flags into one word per face and finds
    every light's silhouette in one XOR pass over the edges (:func:`silcount.detectors.adjacency.many_edge_ids`);
    VnV counts each light's light-facing sides from those words in one compiled loop over the lights; TA and HSD
    replay S for each light on threads side by side; EESD tests every light's rays against their edges' own
    faces in one pass over the edges (:func:`silcount.detectors.eesd.rays.own_blocked`); ``gaussmap`` and
    ``cones`` run their compiled query per light.  None makes a Python object per light.  A plug-in's
    ``detect_many`` may return a batch or a list of :class:`Silhouette` (wrapped here), and every ``naive``
    engine runs per light.  ``tests/test_detect_many.py`` checks every field against :func:`detect`.
    """
    spec = _check(name, variant, engine)
    lights = list(lights)
    if engine == "fast" and spec.detect_many is not None:
        got = spec.detect_many(mesh, lights, variant)
    else:
        got = [spec.detect(mesh, light, variant=variant, engine=engine) for light in lights]
    return got if isinstance(got, SilhouetteBatch) else SilhouetteBatch.of_silhouettes(got, mesh)


__all__ = [
    "DetectorSpec",
    "ENGINES",
    "VARIANTS",
    "detect",
    "detect_many",
    "get",
    "is_reference_run",
    "names",
    "plain_edge_ids",
    "plain_setup",
    "register_detector",
    "runs",
    "specs",
    "variants_of",
    "with_role",
    "Silhouette",
    "SilhouetteBatch",
    "compare_with_reference",
    "differences",
]
