"""`silcount tables`: the papers' operation-count tables, printed beside re-derived beside measured."""

from __future__ import annotations

import argparse
from pathlib import Path

FORMATS = ("md", "csv", "tex")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--format", choices=FORMATS, default="md", help="output format (default md)")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="write tables.md, tables.csv and tables.tex into this directory (missing folders are created)",
    )


def report(out_dir: Path) -> list[Path]:
    """Write the tables under ``<out_dir>/tables/`` (used by `silcount report`)."""
    from silcount.papers.tables import report as write

    return write(out_dir)


def run(args: argparse.Namespace) -> int:
    from silcount.atomic import check_writable
    from silcount.papers.tables import format_tables, write_all

    if args.out is not None:
        check_writable(args.out, folder=True)
        for path in write_all(args.out):
            print(path)
    else:
        print(format_tables(args.format), end="")
    return 0
