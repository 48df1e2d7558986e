"""Worst cases found, not built: a search of meshes, face orders and lights for executions that break a bound.

:func:`worst_case` is ``silcount.worst_case`` and ``silcount worst-case``: for any registered detector, a cost
model (``true``, or ``paper`` where the detector has one) and an operation kind or cycles under a profile, it
searches :mod:`.space` (the structured generators, face orders, subdivisions, perturbations, lights) by
:mod:`.search` for one of the goals of :mod:`.goals`, and writes each witness with :mod:`.files`.  The
search space, the methods tried and their results: ``docs/worst-case.md``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from silcount.errors import BadArgument, check_choice
from silcount.options import WORST_CASE_GOALS as GOALS
from silcount.options import WORST_CASE_METHODS as METHODS

if TYPE_CHECKING:
    import pandas as pd

    from silcount.worstcase.goals import Outcome

DEFAULT_BUDGET = {"exceed": 400, "family": 120, "per-output": 120}


@dataclass
class WorstCase:
    """A search's outcome (:class:`.goals.Outcome`) and the witness files written, if any."""

    outcome: Outcome
    files: dict

    @property
    def found(self) -> bool:
        return self.outcome.found

    def frame(self) -> pd.DataFrame:
        """One row per witness (family: per grown rule), its numbers as columns."""
        import pandas as pd

        o = self.outcome
        base = {"goal": o.goal, "measure": o.measure, "method": o.method, "seed": o.seed, "budget": o.budget}
        base |= {"evaluations": o.evaluations, "found": o.found}
        if o.goal == "family":
            rows = [base | {k: v for k, v in r.items() if k != "genome"} for r in o.rows]
            return pd.DataFrame(rows or [base])
        flat = {k: v for k, v in o.numbers.items() if not isinstance(v, dict)}
        return pd.DataFrame([base | flat | {"genome": None if o.genome is None else o.genome.rule()}])

    def summary(self) -> dict:
        return {**self.outcome.summary(), "files": self.files}


def worst_case(
    detector: str,
    *,
    goal: str = "exceed",
    model: str = "true",
    kind: str = "total",
    profile: str | None = None,
    bound: str | None = None,
    variant: str | None = None,
    seed: int = 0,
    budget: int | None = None,
    method: str = "evolve",
    closed_only: bool = True,
    out: str | Path | None = None,
    progress: bool | None = False,
) -> WorstCase:
    """Search for a worst case of ``detector`` (see the module docstring); write it into ``out`` if given.

    ``bound`` (goal ``exceed``): ``MODEL`` or ``MODEL:LINE`` (a paper's printed line; with ``model="paper"`` its
    own model prices the run) or a closed form in ``n, f_n, e_n, m`` (with ``A M C R W`` per kind).  ``variant``
    ``None``: every variant of the detector, the dearest counting.  ``budget``: evaluations (distinct genomes
    scored), :data:`DEFAULT_BUDGET` by goal.  ``closed_only``: closed, consistently wound meshes only (TA's
    precondition); ``False`` adds open and defective meshes.  Bad arguments raise :class:`BadArgument`.
    """
    from silcount.detectors.registry import get
    from silcount.progress import progress as bar
    from silcount.worstcase import goals
    from silcount.worstcase.objective import Measure, parse_bound

    get(detector)
    check_choice("goal", goal, GOALS)
    check_choice("method", method, METHODS)
    if budget is None:
        budget = DEFAULT_BUDGET[goal]
    if int(budget) < 1:
        raise BadArgument(f"budget must be at least 1 evaluation, got {budget}")
    parsed = None
    if goal == "exceed":
        if not bound:
            raise BadArgument("goal 'exceed' needs a bound (--bound MODEL[:LINE] or a closed form)")
        parsed = parse_bound(bound)
    elif bound:
        raise BadArgument(f"--bound applies to goal 'exceed' only, not {goal!r}")
    pricing = parsed.model if parsed is not None and model == "paper" else None
    measure = Measure(detector, model, kind, variant, profile, pricing)
    with bar(budget, f"worst-case {goal}", enabled=progress) as pb:

        def tick() -> None:
            pb.update(1)

        if goal == "exceed":
            assert parsed is not None
            outcome = goals.exceed(
                measure, parsed, seed=int(seed), budget=int(budget), method=method, closed_only=closed_only, tick=tick
            )
        else:
            run = goals.family if goal == "family" else goals.per_output
            outcome = run(
                measure, seed=int(seed), budget=int(budget), method=method, closed_only=closed_only, tick=tick
            )
    result = WorstCase(outcome, {})
    if out is not None:
        result.files = write(result, Path(out))
    return result


def write(result: WorstCase, out: Path) -> dict:
    """The witness's mesh and light (if one was found) and ``summary.json`` into ``out``; the paths, by role."""
    from silcount.atomic import make_folder, write_text
    from silcount.worstcase.files import save_witness
    from silcount.worstcase.space import build

    make_folder(out)
    files: dict = {}
    o = result.outcome
    if o.genome is not None:
        mesh, light = build(o.genome)
        extra = {"goal": o.goal, "measure": o.measure, "seed": o.seed, "budget": o.budget}
        files = save_witness(out, "witness", mesh, light, o.genome, extra)
    summary = {**o.summary(), "files": {k: Path(v).name for k, v in files.items()}}
    files["summary"] = str(write_text(out / "summary.json", json.dumps(summary, indent=2, sort_keys=True) + "\n"))
    return files


__all__ = ["DEFAULT_BUDGET", "GOALS", "METHODS", "WorstCase", "worst_case", "write"]
