"""What an audit puts beside a measured tally: cycle-weighted totals and the paper's printed formula.

Cycle profiles come from :mod:`silcount.counting.cycles` (built-in names or a
user's TOML file with a ``[weights]`` table).

The printed closed forms are the last printed line of each model's
``[closed_form]`` in ``silcount/models/``, through :mod:`silcount.papers.formulas`,
evaluated at the mesh's ``n`` (faces; HSD: merged polygons) and ``m`` (mean sides).
"""

from __future__ import annotations

from collections.abc import Mapping

from silcount.counting import models
from silcount.counting.cycles import load_profile
from silcount.mesh.model import Mesh


def cycle_profile(spec: str) -> tuple[str, dict[str, float]]:
    """``(name, kind -> cycles)`` for a profile name or a TOML file path."""
    prof = load_profile(spec)
    return prof.name, dict(prof.weights)


def weighted(tally: Mapping[str, float], weights: Mapping[str, float]) -> float:
    """``sum(count * weight)`` over the kinds the profile weighs; an int when every term is."""
    total = sum(tally.get(k, 0) * w for k, w in weights.items())
    return int(total) if float(total).is_integer() else float(total)


def formula_point(detector: str, mesh: Mesh, notes: dict) -> tuple[float, float]:
    """The papers' ``n`` and ``m`` for this mesh: faces and mean sides; for HSD its polygons (HSD Sec. 6.3)."""
    merged = notes.get("merge")
    if detector == "hsd" and isinstance(merged, dict):
        return merged["polygons"], merged["mean_sides"]
    return mesh.n_faces, mesh.mean_sides


def printed_formula(detector: str, mesh: Mesh, notes: dict | None = None) -> dict | None:
    """The paper's printed closed form for ``detector`` at this mesh's ``n`` and ``m``, or ``None``.

    ``n`` is the papers' face count (they substitute ``f_n = n``, ``e_n = 6n``),
    ``m`` the mean sides per face; ``None`` for ``reference``, ``gaussmap`` and ``cones`` (their models
    are silcount's own annotation, with no printed closed form).
    """
    from silcount.detectors import PAPER_MODEL

    model = PAPER_MODEL[detector]
    spec = models.load(model)
    if "closed_form" not in spec:
        return None
    from silcount.papers import formulas  # sympy (~0.3 s): only when there is a printed formula to evaluate

    n, m = formula_point(detector, mesh, notes or {})
    values = formulas.evaluate(formulas.printed_final(model), n=n, m=m)
    return {
        "model": model,
        "source": f"{spec.get('source_file', model)} Sec. {spec['closed_form'].get('section', '?')}",
        "printed": formulas.printed_lines(model)[-1].printed,
        "n": n,
        "m": m,
        "tally": {k: (int(v) if v.is_integer else float(v)) for k, v in values.items()},
    }
