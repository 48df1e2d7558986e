"""`silcount figures`: operations by kind, cycle totals and growth plots (PNG and SVG)."""

from __future__ import annotations

import argparse
from pathlib import Path

from silcount.options import PAPER_HELP


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("reports/figures"),
        help="output directory (default reports/figures; missing folders are created)",
    )
    parser.add_argument("--paper", action="append", type=Path, default=None, metavar="DIR", help=PAPER_HELP)


# The figures `silcount report` writes, one part each (silcount.papers.figures.PARTS, dearest first).
PARTS = ("growth_by_kind", "operations", "cycles", "growth", "growth_table")


def report(out_dir: Path, name: str) -> list[Path]:
    """Write figure ``name`` under ``<out_dir>/figures/`` (a part of `silcount report`)."""
    from silcount.papers.figures import report as write

    return write(out_dir, name)


def run(args: argparse.Namespace) -> int:
    import sys

    from silcount.atomic import check_writable
    from silcount.papers import plugins
    from silcount.papers.figures import write_all, write_papers

    out = check_writable(args.out, folder=True)
    if args.paper:  # the papers' own figures (their algorithms' operations and cycles), not silcount's growth plots
        papers = plugins.from_folders(args.paper)
        paths = write_papers(out, papers)
        if not paths:
            print(f"silcount: {', '.join(p.label for p in papers)}: no algorithm to draw", file=sys.stderr)
    else:
        installed = plugins.plugins()
        paths = write_all(out) + (write_papers(out / "papers", installed) if installed else [])
    for path in paths:
        print(path)
    return 0
