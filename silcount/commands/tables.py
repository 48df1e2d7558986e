"""`silcount tables`: the papers' operation-count tables, printed beside re-derived beside measured."""
from __future__ import annotations

import argparse
from pathlib import Path

from ..tables import FORMATS, render, report, write_all  # noqa: F401  (report: used by `silcount report`)

HELP = "the EESD paper's Tables 1-2 and the HSD equivalents: printed, re-derived, measured"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--format", choices=FORMATS, default="md", help="output format (default md)")
    parser.add_argument("--out", type=Path, default=None, help="write tables.md, tables.csv and tables.tex into this directory")


def run(args: argparse.Namespace) -> int:
    if args.out is not None:
        for path in write_all(args.out):
            print(path)
    else:
        print(render(args.format), end="")
    return 0
