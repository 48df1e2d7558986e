"""The searches: a seeded evolutionary search over genomes (:mod:`.space`), hypothesis's targeted search, shrinking.

Both methods spend a budget counted in evaluations (detector runs on a distinct genome), never seconds, so a
seed and a budget give the same witness on any machine.  The evolutionary search (SlowFuzz-style resource-guided
mutation, CCS 2017) keeps a population of the best genomes found, mutates one or two genes of a parent chosen by
tournament, and stops when the goal is met.  The targeted search hands the genome's genes to
``hypothesis.given`` and reports the score with ``hypothesis.target``, a failing example being one that meets the
goal; hypothesis then shrinks it.  :func:`shrink` shrinks any witness greedily in the generator's own terms
(fewer faces: a lower level, no subdivision; then simpler genes) while it still meets the goal.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from silcount.errors import InvalidMesh
from silcount.worstcase.space import CLOSED_SHAPES, LIGHTS, ORDERS, SHAPES, Genome

Score = Callable[[Genome], "Scored"]


@dataclass(frozen=True)
class Scored:
    """A genome's evaluation: its ``score`` (what the search maximises), whether it meets the goal, its faces."""

    genome: Genome
    score: float
    met: bool
    faces: int
    detail: dict = field(default_factory=dict, compare=False)


@dataclass
class Evaluator:
    """Scores genomes through ``score``, once each (a cache by genome), counting the distinct evaluations."""

    score: Callable[[Genome], Scored | None]  # None: the genome's mesh is outside the allowed space
    budget: int
    closed_only: bool = True
    evaluations: int = 0
    infeasible: int = 0
    cache: dict = field(default_factory=dict)
    tick: Callable[[], object] | None = None  # called once per evaluation (a progress bar's update)

    @property
    def spent(self) -> bool:
        return self.evaluations >= self.budget

    def __call__(self, g: Genome) -> Scored:
        g = g.canonical()
        key = g.key()
        if key not in self.cache:
            self.evaluations += 1
            self.cache[key] = self._score(g)
            if self.tick is not None:
                self.tick()
        return self.cache[key]

    def _score(self, g: Genome) -> Scored:
        try:
            s = self.score(g)
        except InvalidMesh:  # a genome whose mesh silcount refuses (a perturbation collapsing faces): not a run
            s = None
        if s is None:
            self.infeasible += 1
            return Scored(g, float("-inf"), False, 0)
        return s


def is_closed(g: Genome) -> bool:
    """Does ``g`` build a closed, consistently wound mesh (TA's and HSD's precondition)?"""
    return g.shape in CLOSED_SHAPES and g.defect == "none"


def random_genome(rng: np.random.Generator, closed_only: bool, max_level: int) -> Genome:
    shapes = CLOSED_SHAPES if closed_only else SHAPES
    return Genome(
        shape=str(rng.choice(shapes)),
        level=int(rng.integers(1, max_level + 1)),
        subdiv=int(rng.choice([0, 0, 1])),
        perturb=float(rng.choice([0.0, round(float(rng.uniform(0, 0.3)), 3)])),
        height=round(float(rng.uniform(0.05, 1.5)), 3),
        order=str(rng.choice(ORDERS)),
        stride=int(rng.integers(2, 9)),
        rotate_corners=bool(rng.integers(0, 2)),
        light=str(rng.choice(LIGHTS)),
        theta=round(float(rng.uniform(0, np.pi)), 3),
        phi=round(float(rng.uniform(0, 2 * np.pi)), 3),
        axis=int(rng.integers(0, 6)),
        face=int(rng.integers(0, 1000)),
        defect="none" if closed_only else str(rng.choice(["none", "none", "remove", "reverse"])),
        defect_count=int(rng.integers(1, 6)),
        seed=int(rng.integers(0, 2**31)),
    )


def mutate(g: Genome, rng: np.random.Generator, closed_only: bool, max_level: int) -> Genome:
    """``g`` with one or two genes redrawn (the level by one step up or down, most of the time)."""
    fresh = random_genome(rng, closed_only, max_level)
    out = g
    for _ in range(int(rng.integers(1, 3))):
        gene = str(rng.choice(list(Genome.__dataclass_fields__)))
        if gene == "level" and rng.uniform() < 0.7:
            out = replace(out, level=int(np.clip(out.level + rng.choice([-1, 1]), 1, max_level)))
        else:
            out = replace(out, **{gene: getattr(fresh, gene)})
    return out


def evolve(ev: Evaluator, seed: int, closed_only: bool, max_level: int, population: int = 12) -> list[Scored]:
    """(mu + 1) evolution until the goal is met or the budget is spent; the population, best first."""
    rng = np.random.default_rng([seed, 0x57])
    pop: list[Scored] = []
    while len(pop) < population and not ev.spent:
        s = ev(random_genome(rng, closed_only, max_level))
        pop.append(s)
        if s.met:
            return _ranked(pop)
    while not ev.spent:
        a, b = rng.integers(0, len(pop), size=2)
        parent = pop[a] if _better(pop[a], pop[b]) else pop[b]
        child = ev(mutate(parent.genome, rng, closed_only, max_level))
        worst = min(range(len(pop)), key=lambda i: (pop[i].score, -pop[i].faces))
        if _better(child, pop[worst]) and all(child.genome != p.genome for p in pop):
            pop[worst] = child
        if child.met:
            break
    return _ranked(pop)


def _better(a: Scored, b: Scored) -> bool:
    return (a.met, a.score, -a.faces) > (b.met, b.score, -b.faces)


def _ranked(pop: list[Scored]) -> list[Scored]:
    return sorted(pop, key=lambda s: (s.met, s.score, -s.faces, s.genome.key()), reverse=True)


def targeted(ev: Evaluator, seed: int, closed_only: bool, max_level: int) -> list[Scored]:
    """hypothesis's targeted search (``hypothesis.target``), a met goal being a failure it then shrinks."""
    from hypothesis import HealthCheck, Phase, given, settings, target
    from hypothesis import seed as hseed
    from hypothesis import strategies as st

    shapes = CLOSED_SHAPES if closed_only else SHAPES
    genomes = st.builds(
        Genome,
        shape=st.sampled_from(shapes),
        level=st.integers(1, max_level),
        subdiv=st.integers(0, 1),
        perturb=st.sampled_from([0.0, 0.05, 0.1, 0.2, 0.3]),
        height=st.sampled_from([0.5, 0.05, 0.2, 1.0, 1.5]),
        order=st.sampled_from(ORDERS),
        stride=st.integers(2, 8),
        rotate_corners=st.booleans(),
        light=st.sampled_from(LIGHTS),
        theta=st.floats(0.0, 3.14, allow_nan=False).map(lambda x: round(x, 3)),
        phi=st.floats(0.0, 6.28, allow_nan=False).map(lambda x: round(x, 3)),
        axis=st.integers(0, 5),
        face=st.integers(0, 999),
        defect=st.just("none") if closed_only else st.sampled_from(["none", "remove", "reverse"]),
        defect_count=st.integers(1, 5),
        seed=st.integers(0, 1000),
    )
    seen: list[Scored] = []

    class Met(Exception):
        pass

    @hseed(seed)
    @settings(
        max_examples=max(1, ev.budget),
        database=None,
        deadline=None,
        phases=[Phase.generate, Phase.target, Phase.shrink],
        suppress_health_check=list(HealthCheck),
    )
    @given(genomes)
    def probe(g: Genome) -> None:
        if ev.spent and g.canonical().key() not in ev.cache:
            return
        s = ev(g)
        seen.append(s)
        if np.isfinite(s.score):
            target(float(s.score))
        if s.met:
            raise Met

    try:
        probe()
    except Met:
        pass
    return _ranked(list({s.genome.key(): s for s in seen}.values()))


SIMPLER: tuple[tuple[str, Any], ...] = (
    ("subdiv", 0),
    ("perturb", 0.0),
    ("rotate_corners", False),
    ("defect", "none"),
    ("order", "as_built"),
    ("light", "axis"),
    ("height", 0.5),
)


def shrink(ev: Evaluator, best: Scored, max_steps: int = 200) -> Scored:
    """The smallest witness reachable from ``best`` by lowering the level and subdivisions and simplifying genes,
    each step kept only if the goal is still met (fewer faces first, then simpler genes)."""
    cur = best
    for _ in range(max_steps):
        steps = [replace(cur.genome, level=lv) for lv in range(1, cur.genome.level)]
        steps += [replace(cur.genome, **{k: v}) for k, v in SIMPLER if getattr(cur.genome, k) != v]
        moved = False
        for g in steps:
            if ev.spent:
                return cur
            s = ev(g)
            if s.met and (s.faces < cur.faces or (s.faces == cur.faces and g != cur.genome)):
                cur, moved = s, True
                break
        if not moved:
            return cur
    return cur


METHODS = {"evolve": evolve, "hypothesis": targeted}


def run_search(ev: Evaluator, method: str, seed: int, closed_only: bool, max_level: int = 6) -> list[Scored]:
    return METHODS[method](ev, seed, closed_only, max_level)


__all__ = [
    "Evaluator",
    "METHODS",
    "Scored",
    "evolve",
    "is_closed",
    "mutate",
    "random_genome",
    "run_search",
    "shrink",
    "targeted",
]
