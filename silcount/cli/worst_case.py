"""`silcount worst-case`: search meshes, face orders and lights for a detector's worst case (docs/worst-case.md)."""

from __future__ import annotations

import argparse
from pathlib import Path

from silcount.options import WORST_CASE_GOALS, WORST_CASE_KINDS, WORST_CASE_METHODS

REPORT_BUDGET = 8  # evaluations per search of each detector's row in `silcount report` (seconds, not minutes)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--detector", required=True, help="a registered detector (silcount audit --help lists them)")
    parser.add_argument(
        "--goal", choices=WORST_CASE_GOALS, default="exceed", help="what to search for (default exceed)"
    )
    parser.add_argument("--model", choices=("true", "paper"), default="true", help="cost model (default true)")
    parser.add_argument("--kind", choices=WORST_CASE_KINDS, default="total", help="operation kind (default total)")
    parser.add_argument(
        "--profile", default=None, metavar="PROFILE|FILE", help="measure cycles under this cycle profile instead"
    )
    parser.add_argument(
        "--bound",
        default=None,
        metavar="MODEL[:LINE]|FORM",
        help="goal exceed: a paper's printed line (e.g. hsd2011-ta) or a closed form in n, f_n, e_n, m",
    )
    parser.add_argument("--variant", default=None, help="the detector's variant (default: every variant it has)")
    parser.add_argument("--method", choices=WORST_CASE_METHODS, default="evolve", help="search method (default evolve)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the search (default 0)")
    parser.add_argument("--budget", type=int, default=None, help="evaluations (default 400 exceed, 120 otherwise)")
    parser.add_argument(
        "--open", action="store_true", help="search open and defective meshes too (default: closed, consistently wound)"
    )
    parser.add_argument("--out", type=Path, default=None, metavar="DIR", help="write the witness and summary.json here")


def report(out_dir: Path) -> list[Path]:
    """Write ``<out_dir>/worst-case/rows.md`` and ``rows.json``: a worst-case row per detector
    (:mod:`silcount.worstcase.rows`, seed 0, :data:`REPORT_BUDGET` evaluations per search, the best rule grown)."""
    import json

    from silcount.atomic import make_folder, write_text
    from silcount.worstcase.rows import markdown, rows

    table = rows(REPORT_BUDGET, grow=1)
    folder = make_folder(out_dir / "worst-case")
    head = (
        "# A worst-case row per detector\n\n"
        f"Written by `silcount report` (silcount/worstcase/rows.py): seed 0, {REPORT_BUDGET} evaluations per search, "
        "the best rule grown from 64 to 40,000 faces; `python -m benchmarks.worst_case --rows-only` runs a larger "
        "budget. Typical: total true operations on the icosphere series, as built, one directional light. "
        "docs/worst-case.md says what is searched.\n\n"
    )
    return [
        write_text(folder / "rows.md", head + markdown(table)),
        write_text(folder / "rows.json", json.dumps(table, indent=2, sort_keys=True) + "\n"),
    ]


def run(args: argparse.Namespace) -> int:
    from silcount.worstcase import worst_case

    result = worst_case(
        args.detector,
        goal=args.goal,
        model=args.model,
        kind=args.kind,
        profile=args.profile,
        bound=args.bound,
        variant=args.variant,
        seed=args.seed,
        budget=args.budget,
        method=args.method,
        closed_only=not args.open,
        out=args.out,
        progress=None,
    )
    o = result.outcome
    print(f"{o.goal}: {o.measure}")
    print(f"method {o.method}, seed {o.seed}, {o.evaluations} of {o.budget} evaluations")
    if not o.found:
        print("not found")
    else:
        assert o.genome is not None
        print(f"witness: {o.genome.rule()}, level {o.genome.level}")
        for key, value in o.numbers.items():
            print(f"  {key}: {value}")
    for role, path in result.files.items():
        print(f"{role}: {path}")
    return 0
