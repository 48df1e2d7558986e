"""`silcount claims`: every quantitative claim of the papers, with a computed verdict."""

from __future__ import annotations

import argparse
from pathlib import Path


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


def report(out_dir: Path) -> list[Path]:
    """Write the claims reports under ``<out_dir>/claims/`` (used by `silcount report`)."""
    from silcount.papers.claims import report as write

    return write(out_dir)


def run(args: argparse.Namespace) -> int:
    from silcount.counting.cycles import load_profile
    from silcount.papers.claims import default_evidence, format_claims

    profile = load_profile(args.cycles) if args.cycles else None
    print(format_claims(args.format, profile, default_evidence(render=not args.no_render)), end="")
    return 0
