"""The worst-case search's targets (issue 40): rediscovery with no hint, and a worst-case row per detector.

    SILCOUNT_MESH_DIR=... python -m benchmarks.worst_case [--rows-only | --targets-only] [--method evolve]

Rediscovery: each hand-built result of ``silcount/papers/witness.py`` found by ``silcount.worst_case`` from
seed 0 with the default budget, closed meshes only, every variant of the detector tried, and no hint (no
shape, order or light given): the HSD paper's TA line 1 exceeded in writes, HSD's line 1 exceeded, EESD's
line 1 exceeded, and a TA family of fitted exponent >= 1.9.  The baseline, measured in the same run, is the
hand-built witness: its excess (cost / bound) and its family's exponent (``witness.family_exponent``).
Each target prints its seconds, evaluations and ``os.getloadavg()``; the target is 120 s each.

Rows: per registered detector, the typical exponent (total true operations on the icosphere series under one
directional light, as built) beside the worst family found (goal ``family``), and for the output-sensitive
detectors (a ``node_test`` step) the worst fraction of E tested (goal ``per-output``), with its mesh and light.
``--out DIR`` writes the rows as ``rows.json`` and ``rows.md``.
No assertion is made on any time.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from benchmarks.common import load_line

TARGET_S = 120.0
TARGETS = (  # name, detector, kind, bound
    ("HSD paper's TA sum exceeded in writes", "ta", "write", "hsd2011-ta"),
    ("HSD's sum exceeded", "hsd", "any", "hsd2011-hsd"),
    ("EESD's first printed line exceeded", "eesd", "any", "eesd2012-eesd"),
)
ROW_BUDGET = 40


def rediscovery(method: str) -> list[dict]:
    from silcount.papers import witness
    from silcount.worstcase import worst_case

    out = []
    for name, detector, kind, bound in TARGETS:
        t = time.perf_counter()
        r = worst_case(detector, model="paper", kind=kind, bound=bound, method=method)
        dt = time.perf_counter() - t
        hand = witness.bound_witness(bound)
        hand_ratio = max(hand.cost[k] / hand.bound[k] for k in (hand.over if kind == "any" else [kind]))
        n = r.outcome.numbers
        out.append(
            {
                "target": name,
                "found": r.found,
                "seconds": round(dt, 1),
                "evaluations": r.outcome.evaluations,
                "ratio": n.get("ratio"),
                "hand_ratio": hand_ratio,
                "faces": n.get("faces"),
                "hand_faces": hand.faces,
                "over": n.get("over"),
                "witness": r.outcome.genome.rule() + f", level={r.outcome.genome.level}" if r.found else "",
                "load": load_line(),
            }
        )
        print(_line(out[-1]), flush=True)
    t = time.perf_counter()
    fam = worst_case("ta", goal="family", method=method)
    dt = time.perf_counter() - t
    hand_fam = witness.family_exponent("ta", "closed")
    n = fam.outcome.numbers
    row = {
        "target": "TA family, exponent >= 1.9",
        "found": fam.found and n["alpha"] >= 1.9,
        "seconds": round(dt, 1),
        "evaluations": fam.outcome.evaluations,
        "alpha": n.get("alpha"),
        "ci": n.get("ci"),
        "decades": n.get("decades"),
        "hand_alpha": hand_fam.exponent,
        "witness": n.get("rule", ""),
        "load": load_line(),
    }
    out.append(row)
    print(_line(row), flush=True)
    return out


def _line(r: dict) -> str:
    ok = "MET" if r["found"] and r["seconds"] <= TARGET_S else "NOT MET"
    if "alpha" in r:
        what = (
            f"exponent {r['alpha']:.3f} [{r['ci'][0]:.3f}, {r['ci'][1]:.3f}] over {r['decades']:.2f} decades "
            f"(hand-built closed family {r['hand_alpha']:.3f}; ratio {r['alpha'] / r['hand_alpha']:.3f})"
            if r["alpha"] is not None
            else "no family fitted"
        )
    else:
        what = (
            f"cost/bound {r['ratio']:.4f} in {r['over']} on {r['faces']} faces (hand-built {r['hand_ratio']:.4f} on "
            f"{r['hand_faces']} faces)"
            if r["found"]
            else "not found"
        )
    return (
        f"{r['target']}: {ok}: {r['seconds']} s, {r['evaluations']} evaluations; {what}; {r['witness']} [{r['load']}]"
    )


def rows(only: list[str] | None = None) -> list[dict]:
    """The rows of :mod:`silcount.worstcase.rows` with :data:`ROW_BUDGET`, printed as they come, with seconds."""
    from silcount.detectors.registry import specs
    from silcount.worstcase.rows import row

    out = []
    for spec in specs():
        if only and spec.name not in only:
            continue
        t = time.perf_counter()
        r = row(spec.name, ROW_BUDGET)
        r["seconds"] = round(time.perf_counter() - t, 1)
        r["load"] = load_line()
        out.append(r)
        print(json.dumps(r), flush=True)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--method", default="evolve", choices=("evolve", "hypothesis"), help="of the rediscovery targets")
    ap.add_argument("--rows-only", action="store_true")
    ap.add_argument("--targets-only", action="store_true")
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--detectors", default="", help="rows of these detectors only (comma-separated)")
    args = ap.parse_args()
    print(f"start: {load_line()}", flush=True)
    if not args.rows_only:
        rediscovery(args.method)
    if not args.targets_only:
        from silcount.worstcase.rows import markdown

        table = rows([d for d in args.detectors.split(",") if d])
        print(markdown(table))
        if args.out is not None:
            args.out.mkdir(parents=True, exist_ok=True)
            (args.out / "rows.json").write_text(json.dumps(table, indent=2) + "\n")
            (args.out / "rows.md").write_text(markdown(table))


if __name__ == "__main__":
    main()
