"""`silcount figures`: operations by kind, cycle totals and growth plots (PNG and SVG)."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("reports/figures"),
        help="output directory (default reports/figures; missing folders are created)",
    )


# The figures `silcount report` writes, one part each (silcount.papers.figures.PARTS, dearest first).
PARTS = ("growth_by_kind", "operations", "cycles", "growth", "growth_table")


def report(out_dir: Path, name: str) -> list[Path]:
    """Write figure ``name`` under ``<out_dir>/figures/`` (a part of `silcount report`)."""
    from silcount.papers.figures import report as write

    return write(out_dir, name)


def run(args: argparse.Namespace) -> int:
    from silcount.atomic import check_writable
    from silcount.papers.figures import write_all

    for path in write_all(check_writable(args.out, folder=True)):
        print(path)
    return 0
