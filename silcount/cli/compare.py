"""`silcount compare A.png B.png [--coverage cov.png] [--tol F]`: do two shadow masks agree?

Prints the mismatched pixels as a fraction of covered pixels (all pixels
without ``--coverage``) and how many mismatches lie more than one pixel from
any edge of either mask (scene README, "Comparing two masks").  Exit 0 when
there are no such far mismatches and the fraction is within ``--tol``
(default 0.005), else 1.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from silcount.errors import BadArgument


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("a", type=Path, metavar="A.png")
    parser.add_argument("b", type=Path, metavar="B.png")
    parser.add_argument("--coverage", type=Path, metavar="cov.png", help="only pixels set here count")
    parser.add_argument(
        "--tol", type=float, default=0.005, metavar="F", help="largest accepted mismatch fraction (default 0.005)"
    )


def run(args: argparse.Namespace) -> int:
    from silcount.render.masks import compare_masks, read_mask

    if not (math.isfinite(args.tol) and 0.0 <= args.tol <= 1.0):
        raise BadArgument(f"--tol must be a fraction in [0, 1], got {args.tol}")
    a, b = read_mask(args.a), read_mask(args.b)
    cov = read_mask(args.coverage) if args.coverage is not None else None
    try:
        c = compare_masks(a, b, cov, args.tol)
    except BadArgument as exc:
        raise BadArgument(f"{args.a} vs {args.b}: {exc}") from None
    print(f"{args.a} vs {args.b}: {c.describe()}: {'match' if c.ok else 'MISMATCH'}")
    return 0 if c.ok else 1
