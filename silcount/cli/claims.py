"""`silcount claims`: every quantitative claim of the papers, with a computed verdict."""

from __future__ import annotations

import argparse
from pathlib import Path

from silcount.options import PAPER_HELP


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--format", choices=("text", "md", "json"), default="text", help="output format (default text)")
    parser.add_argument(
        "--cycles",
        metavar="PROFILE|FILE",
        default=None,
        help="an extra cycle profile (built-in name or TOML file with [weights]) for the ordering claims",
    )
    parser.add_argument(
        "--no-render",
        action="store_true",
        help="skip the render experiments (the stencil claims then say 'not measured'; verdicts unchanged)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        metavar="DIR",
        help="write claims.txt, claims.md, claims.json and rules.md into this directory instead of stdout",
    )
    parser.add_argument("--paper", action="append", type=Path, default=None, metavar="DIR", help=PAPER_HELP)


def report(out_dir: Path) -> list[Path]:
    """Write the claims reports under ``<out_dir>/claims/`` (used by `silcount report`)."""
    from silcount.papers.claims import report as write

    return write(out_dir)


def run(args: argparse.Namespace) -> int:
    from silcount.counting.cycles import load_profile
    from silcount.papers.claims import default_evidence, format_claims, write_claims
    from silcount.papers.plugins import chosen

    papers = chosen(args.paper)
    profile = load_profile(args.cycles) if args.cycles else None
    evidence = default_evidence(render=not args.no_render)
    if args.out is not None:
        from silcount.atomic import check_writable

        for path in write_claims(check_writable(args.out, folder=True), evidence, papers):
            print(path)
    else:
        print(format_claims(args.format, profile, evidence, papers), end="")
    return 0
