"""Witness families: meshes and lights on which a detector's true cost reaches its worst-case growth.

A complexity claim "X is O(f(n))" is an upper bound (``docs/claims.md``, rule 7):
growth below f on typical meshes (the icosphere sweep, the corpus) does not
contradict it, and it is tight only if some family of inputs reaches f.  For
TA, what makes the cost quadratic is the linear search of the array S
(:mod:`silcount.detectors.edge_array`): every side of a light-facing face scans
S from the front, so the total is about (sides searched) x |S|, and |S| is
small on the icosphere sweep (about sqrt(F): the silhouette and the front of
the faces processed so far).  Two families keep S at a constant fraction of
the edges:

``closed``
    icosphere k, closed and consistently wound (TA's precondition, "each edge
    should be shared by just two triangles"), under a fixed directional light,
    its faces renumbered so that a maximal independent set of the lit faces
    (no two sharing an edge, chosen greedily in index order) comes first: each
    of those faces adds all three sides to S, so S holds a constant fraction of
    the edges when the other lit faces start searching it (0.42 E on
    icosphere5: 4330 faces of its 10240 lit ones), and their deletes find
    their edge anywhere in it.
``strip``
    an open strip of 2k triangles in z = 0, every face lit from above: the
    boundary edges are never deleted, so S grows by one per triangle.

:func:`worst_cases` fits the exponent of TA's total true operations
against faces on each family (fast engine), as :class:`~silcount.papers.growth.Exponent`
values the complexity rules take beside the typical growth.

Found, not built (issue 40): a paper detector with no hand-built family, and a printed line with no hand-built
execution in :data:`BOUND_WITNESSES` (a paper added as data), are judged with the witness
:mod:`silcount.worstcase` finds from seed :data:`SEARCH_SEED` within a small fixed budget of evaluations
(:data:`FAMILY_BUDGET`, :data:`BOUND_BUDGET`: seconds of ``make report``, not minutes); every witness says
whether it was built by hand or found, and the search's budget.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from silcount.detectors import detect
from silcount.detectors.adjacency import facing_flags
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh, from_polygons
from silcount.mesh.shapes import icosahedron, icosphere, plane
from silcount.papers.growth import Exponent, measure_exponent

CLOSED_SIZES = (2, 3, 4, 5)  # icosphere subdivisions: 320 .. 20480 faces
STRIP_SIZES = (1000, 2000, 4000, 8000, 16000)  # cells of the strip: 2000 .. 32000 faces
CLOSED_LIGHT = DirectionalLight((0.36, 0.48, 0.8))
STRIP_LIGHT = DirectionalLight((0.0, 0.0, 1.0))


def _neighbours(mesh: Mesh) -> np.ndarray:
    """(F, 3) the faces across each side of a closed triangle mesh."""
    pair = mesh.manifold_sides[mesh.side_edge]  # the two sides of each side's edge
    own = np.arange(mesh.n_sides)
    other = np.where(pair[:, 0] == own, pair[:, 1], pair[:, 0])
    return mesh.side_face[other].reshape(-1, 3)


def lit_first(mesh: Mesh, light: Light) -> Mesh:
    """``mesh`` with its faces renumbered: a greedy maximal independent set of the lit faces, the other lit
    faces, then the unlit ones (each group in its old order).  Geometry, winding and edges are unchanged."""
    if not (mesh.is_triangle_mesh and mesh.is_watertight):
        raise ValueError("lit_first needs a closed, consistently wound triangle mesh")
    lit, _ = facing_flags(mesh, light)
    near = _neighbours(mesh)
    picked = np.zeros(mesh.n_faces, dtype=bool)
    for f in np.flatnonzero(lit).tolist():
        if not picked[near[f]].any():
            picked[f] = True
    order = np.concatenate([np.flatnonzero(picked), np.flatnonzero(lit & ~picked), np.flatnonzero(~lit)])
    return from_polygons(mesh.vertices, mesh.faces[order], name=f"{mesh.name}_lit_first")


def closed_family(sizes=CLOSED_SIZES) -> list[tuple[Mesh, Light]]:
    return [(lit_first(icosphere(k), CLOSED_LIGHT), CLOSED_LIGHT) for k in sizes]


def strip_family(sizes=STRIP_SIZES) -> list[tuple[Mesh, Light]]:
    out: list[tuple[Mesh, Light]] = []
    for cells in sizes:
        m = plane(1, cells)
        m.name = f"strip{2 * cells}"
        out.append((m, STRIP_LIGHT))
    return out


FAMILIES = {
    "closed": (closed_family, "icosphere, lit faces renumbered (an independent set first), one directional light"),
    "strip": (strip_family, "open triangle strip, every face lit"),
}


def total_true(detector: str, mesh: Mesh, light: Light) -> int:
    """Total true operations of ``detector`` (fast engine, default variant) on ``mesh`` for ``light``."""
    return int(sum(detect(mesh, light, detector, engine="fast").tally["true"].values()))


def family_exponent(detector: str, family: str) -> Exponent:
    """The fitted exponent (95% interval) and class of ``detector``'s total true operations vs faces on a family."""
    build, what = FAMILIES[family]
    runs = build()
    faces = [m.n_faces for m, _ in runs]
    source = f"witness family '{family}': {what}; F = {faces[0]} .. {faces[-1]}, fast engine"
    return measure_exponent(detector, "true", faces, [total_true(detector, m, light) for m, light in runs], source)


SEARCH_SEED = 0
FAMILY_BUDGET = 16  # evaluations of the family search, per detector without a hand-built family
BOUND_BUDGET = 200  # evaluations of the search for an execution exceeding a printed line
HAND_BUILT = {"ta": ("closed",)}  # detector -> its hand-built families (FAMILIES)


def found_family_exponent(detector: str) -> Exponent | None:
    """The fastest-growing family the worst-case search finds for ``detector``
    (:func:`silcount.worstcase.goals.family`, seed :data:`SEARCH_SEED`, :data:`FAMILY_BUDGET` evaluations, its
    best rule grown), its series fitted and classed as the hand-built ones are (:func:`measure_exponent`);
    ``None`` if no family spans two decades."""
    from silcount.worstcase.goals import family
    from silcount.worstcase.objective import Measure

    found = family(Measure(detector), seed=SEARCH_SEED, budget=FAMILY_BUDGET, grow=1)
    n = found.numbers
    if not found.found:
        return None
    source = (
        f"worst-case search family: {n['rule']}; found by silcount's search (seed {SEARCH_SEED}, "
        f"{found.evaluations} of {FAMILY_BUDGET} evaluations, the best rule grown), not built by hand; "
        f"F = {n['faces'][0]} .. {n['faces'][-1]}, fast engine"
    )
    return measure_exponent(detector, "true", n["faces"], n["costs"], source)


@cache
def worst_cases(detector: str) -> tuple[Exponent, ...]:
    """Worst-case growth witnesses of ``detector``: one :class:`Exponent` per hand-built family
    (:data:`HAND_BUILT`), or, for a detector without one (VnV, EESD, HSD, the hierarchies, a plug-in), the
    family the search finds (:func:`found_family_exponent`), if it spans two decades.  Measured on first use,
    once per detector: only the detectors that an O() claim names are searched."""
    if detector in HAND_BUILT:
        return tuple(family_exponent(detector, f) for f in HAND_BUILT[detector])
    found = found_family_exponent(detector)
    return () if found is None else (found,)


# --- executed witnesses against the printed upper bounds (issue 24) ---------------------------------------------
#
# "Every face lit" (v = 1) is no execution: on a closed, consistently wound mesh sum_f (L - p_f).n_f A_f is
# -3 x volume for a point light and sum_f d.n_f A_f = 0 for a directional one, so some face always faces away.
# A printed first line that fails as an upper bound is refuted by a run of silcount's own naive engine instead:
# its step counts priced by the model's annotations (``paper_tally``) against the printed line at the mesh's own
# f_n, e_n and m.

PILLOW_LIGHT = DirectionalLight((0.0, 0.0, 1.0))


def pillow(k: int = 10, height: float = 0.5, depth: float = 0.5) -> Mesh:
    """A closed, consistently wound "pillow": the dome z = height (1-x^2)(1-y^2) over a k x k grid of [-1, 1]^2
    (2k^2 triangles, each lit from straight above) closed by a fan of 4k triangles to an apex at z = -depth
    (each facing away).  k = 10: 240 triangles, 200 lit, 40 silhouette edges (the rim)."""
    xs = np.linspace(-1.0, 1.0, k + 1)
    X, Y = np.meshgrid(xs, xs, indexing="ij")
    verts = np.stack([X.ravel(), Y.ravel(), (height * (1 - X**2) * (1 - Y**2)).ravel()], axis=1)

    def at(i: int, j: int) -> int:
        return i * (k + 1) + j

    faces = []
    for i in range(k):
        for j in range(k):
            a, b, c, d = at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)
            faces += [(a, b, c), (a, c, d)]
    apex = len(verts)
    rim = [at(i, 0) for i in range(k)] + [at(k, j) for j in range(k)]
    rim += [at(i, k) for i in range(k, 0, -1)] + [at(0, j) for j in range(k, 0, -1)]
    faces += [(b, a, apex) for a, b in zip(rim, rim[1:] + rim[:1])]
    mesh = from_polygons(np.vstack([verts, [(0.0, 0.0, -depth)]]), np.array(faces), name=f"pillow{k}")
    if not mesh.is_watertight:
        raise AssertionError("pillow must be closed and consistently wound")
    return mesh


# model -> (detector, variant, mesh builder, light, what the run shows)
BOUND_WITNESSES = {
    "hsd2011-ta": (
        "ta",
        "intended",
        pillow,
        PILLOW_LIGHT,
        "S starts empty: adds >= deletes, and an add (3W) is dearer",
    ),
    "hsd2011-hsd": (
        "hsd",
        "intended",
        pillow,
        PILLOW_LIGHT,
        "f_n, e_n, m: the merged polygons; as TA, S starts empty and an add (3W) is dearer",
    ),
    "eesd2012-eesd": (
        "eesd",
        "literal",
        icosahedron,
        PILLOW_LIGHT,
        "every missed face adds, an Add left out of the sum",
    ),
}


@dataclass(frozen=True)
class BoundWitness:
    """One run of silcount's naive engine priced by a model's annotations, against its first printed line."""

    model: str
    detector: str
    variant: str
    mesh: str
    faces: int
    lit: int
    light: str
    params: dict
    steps: dict
    cost: dict  # kind -> the run's cost under the model's annotations
    bound: dict  # kind -> the first printed line at the mesh's own f_n, e_n, m
    note: str
    origin: str = "hand-built"  # or how the search found it (seed, evaluations of its budget)

    @property
    def over(self) -> list[str]:
        """The kinds in which the run exceeds the printed line."""
        return [k for k in self.cost if self.cost[k] > self.bound[k]]

    def excess(self) -> str:
        """``kind cost > bound`` for each kind the run exceeds."""
        return "; ".join(f"{k} {self.cost[k]} > {_show(self.bound[k])}" for k in self.over)

    def describe(self) -> str:
        p = ", ".join(f"{k} = {_show(v)}" for k, v in sorted(self.params.items()))
        over = self.excess()
        return (
            f"silcount's naive {self.detector} ({self.variant}) on {self.mesh} ({self.faces} faces, {self.lit} lit, "
            f"closed and consistently wound, light {self.light}), priced by {self.model}'s annotations, exceeds "
            f"the first printed line at the mesh's own {p}: {over} ({self.note}; {self.origin} witness)"
        )


def _show(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else f"{float(x):.4g}"


@cache
def bound_witness(model: str) -> BoundWitness:
    """Run :data:`BOUND_WITNESSES`' ``model`` entry and price it (see the section comment above)."""
    detector, variant, build, light, note = BOUND_WITNESSES[model]
    return _priced(model, detector, variant, build(), light, note, "hand-built")


@cache
def found_bound_witness(model: str) -> BoundWitness | None:
    """An execution exceeding ``model``'s first printed line that :func:`silcount.worstcase.worst_case` finds
    (the model's own detector, every variant, any kind, closed meshes; seed :data:`SEARCH_SEED`,
    :data:`BOUND_BUDGET` evaluations), re-run by the naive engine and priced as the hand-built ones; ``None``
    if the search finds none."""
    from silcount.counting import models
    from silcount.worstcase import worst_case
    from silcount.worstcase.space import build

    detector = models.load(model)["algorithm"]
    found = worst_case(detector, model="paper", kind="any", bound=model, seed=SEARCH_SEED, budget=BOUND_BUDGET)
    if not found.found or found.outcome.genome is None:
        return None
    mesh, light = build(found.outcome.genome)
    origin = (
        f"found by silcount's worst-case search (seed {SEARCH_SEED}, {found.outcome.evaluations} of {BOUND_BUDGET} "
        f"evaluations: {found.outcome.genome.rule()}, level {found.outcome.genome.level}), not built by hand,"
    )
    note = "the search's witness"
    return _priced(model, detector, found.outcome.numbers["variant"], mesh, light, note, origin)


def witness_for(model: str) -> BoundWitness | None:
    """The hand-built execution of :data:`BOUND_WITNESSES` for ``model``, else the one the search finds."""
    return bound_witness(model) if model in BOUND_WITNESSES else found_bound_witness(model)


def _priced(model: str, detector: str, variant: str, mesh: Mesh, light: Light, note: str, origin: str) -> BoundWitness:
    """One naive run of ``detector`` on ``mesh`` priced by ``model``'s annotations, against its first line."""
    import sympy as sp

    from silcount.counting import models
    from silcount.papers import formulas as F

    run = detect(mesh, light, detector, variant=variant, engine="naive")
    cost = models.paper_tally(model, run.steps, run.paper_params)
    subs = {F.LOCALS[k]: sp.nsimplify(x) for k, x in run.paper_params.items()}
    bound = {k: float(sp.nsimplify(x.subs(subs))) for k, x in F.printed_lines(model)[0].form.items()}
    lit = int(facing_flags(mesh, light)[0].sum())
    direction = (
        "directional " + str(tuple(float(c) for c in light.vector)) if light.is_directional else light.describe()
    )
    return BoundWitness(
        model,
        detector,
        variant,
        mesh.name,
        mesh.n_faces,
        lit,
        direction,
        dict(run.paper_params),
        dict(run.steps),
        cost,
        bound,
        note,
        origin,
    )
