"""`silcount corpus PATH...`: every detector under many lights on every mesh of a collection, on Dask.

The sweep is :func:`silcount.study.corpus`; the files of ``--out`` and the
stdout formats are :mod:`silcount.study.output`.  Runs in-process by default
(``--scheduler processes`` or ``threads``, ``--workers N``), or on a running
``dask.distributed`` cluster (``--scheduler tcp://HOST:PORT``, after
``dask scheduler`` and ``dask worker tcp://HOST:PORT`` on the machines).

Exit status: 0 when every mesh was audited; **1 when at least one mesh could
not be** (its row carries the one-line ``error``; every output is still
written); 2 bad arguments; 3 no mesh file found or a path that does not exist.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

CORPUS_ENV = "SILCOUNT_CORPUS_DIR"
REPORT_LEVELS = (0,)  # each subdivision level quadruples the faces, and about the time, of the sweep


def _levels(text: str) -> list[int]:
    try:
        levels = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a comma-separated list of levels such as 0,1,2") from None
    if not levels or min(levels) < 0:
        raise argparse.ArgumentTypeError(f"{text!r}: levels are integers >= 0")
    return levels


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.epilog = (
        "exit status: 0 every mesh audited; 1 at least one mesh could not be (its row carries the one-line error, "
        "every output is still written); 2 bad arguments; 3 no mesh file found"
    )
    parser.add_argument("paths", nargs="+", metavar="PATH", help="mesh files or folders (searched recursively)")
    parser.add_argument("--lights", type=int, default=64, metavar="N", help="lights per mesh (default 64)")
    parser.add_argument(
        "--light-kind",
        choices=("directional", "point", "both"),
        default="directional",
        help="directions uniform on the sphere; point lights at 3x the bounding radius; both (default directional)",
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of every mesh's lights, with its sha256 (default 0)")
    parser.add_argument(
        "--detectors",
        default=None,
        metavar="LIST",
        help="comma-separated detector names (default: every registered one)",
    )
    parser.add_argument("--variant", choices=("intended", "literal", "both"), default="intended")
    parser.add_argument(
        "--subdivide",
        type=_levels,
        default=[0],
        metavar="LEVELS",
        help="midpoint subdivision levels to sweep, e.g. 0,1,2 (default 0: the files as they are)",
    )
    parser.add_argument(
        "--scheduler",
        default="processes",
        metavar="threads|processes|tcp://HOST:PORT",
        help="Dask's in-process threads or processes, or a dask.distributed scheduler's address (default processes)",
    )
    parser.add_argument("--workers", type=int, default=None, metavar="N", help="local workers (default: CPU count)")
    parser.add_argument(
        "--memory-budget",
        default=None,
        metavar="SIZE",
        help="a worker's peak memory, e.g. 4GB: a larger mesh runs in parts or is refused (default: 3/4 of the "
        "machine's memory over the local workers; none on a cluster)",
    )
    cache = parser.add_mutually_exclusive_group()
    cache.add_argument("--cache", type=Path, default=None, metavar="DIR", help="cache folder (default ~/.cache/...)")
    cache.add_argument("--no-cache", action="store_true", help="neither read nor write the cache")
    parser.add_argument("--no-time", action="store_true", help="do not time the plain compiled loops")
    parser.add_argument(
        "--time-lights", type=int, default=1, metavar="K", help="lights timed per mesh and detector (default 1)"
    )
    parser.add_argument("--format", choices=("text", "md", "json"), default="text", help="stdout (default text)")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        metavar="DIR",
        help="write corpus.parquet, meshes.csv, fits.json, figures (missing folders are created)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    from silcount.atomic import check_writable
    from silcount.errors import BadArgument
    from silcount.study import corpus
    from silcount.study.output import format_corpus, write_out

    if args.out is not None:
        check_writable(args.out, folder=True)  # before the sweep
    if args.workers is not None and args.workers < 1:
        raise BadArgument(f"--workers {args.workers}: need at least one")
    detectors = None if args.detectors is None else [d.strip() for d in args.detectors.split(",") if d.strip()]
    result = corpus(
        args.paths,
        lights=args.lights,
        light_kind=args.light_kind,
        seed=args.seed,
        detectors=detectors,
        variant=args.variant,
        subdivide=args.subdivide,
        scheduler=args.scheduler,
        workers=args.workers,
        cache=False if args.no_cache else (args.cache or True),
        timing=not args.no_time,
        time_lights=args.time_lights,
        quiet=args.quiet,
        memory_budget=args.memory_budget,
    )
    sys.stdout.write(format_corpus(result, args.format))
    if args.out is not None:
        for path in write_out(result, args.out):
            print(f"wrote {path}", file=sys.stderr)
    return 1 if result.failed else 0


def corpus_dir() -> Path | None:
    """``$SILCOUNT_CORPUS_DIR`` (the Makefile sets ``../shared/corpus``) if it names a folder, else None."""
    env = os.environ.get(CORPUS_ENV)
    return Path(env) if env and Path(env).is_dir() else None


def report(out_dir: Path) -> list[Path]:
    """The corpus section of `silcount report` under ``out_dir/corpus/``, or nothing (saying so) without a corpus.

    Settings: 64 directional lights of seed 0, every detector (``intended``: the
    papers' four, ``reference``, ``gaussmap`` and ``cones``), subdivision levels
    :data:`REPORT_LEVELS`, no wall times (byte-identical reruns), the default
    cache (a timed ``silcount corpus`` run with the same settings fills it), no
    ``corpus.parquet``.  ``literature.md`` (linked from ``summary.md``) sets the
    papers' detectors beside the literature's; without wall times its time
    rows are ``-``, and with directional lights only it has no point-light rows
    (``silcount corpus --light-kind both --out DIR`` gives both, timed).  ``scale.md``, the sweep-time
    model's check and its 10,000-mesh estimate, comes from the committed measurements
    (:mod:`silcount.study.scale`) and is written with or without a corpus.
    """
    from silcount.atomic import make_folder, write_text
    from silcount.study import corpus, scale
    from silcount.study.output import write_out

    make_folder(out_dir / "corpus")
    paths = [write_text(out_dir / "corpus" / "scale.md", scale.page(scale.load_profile()))]
    source = corpus_dir()
    if source is None:
        print(f"corpus: skipped: ${CORPUS_ENV} does not name a folder")
        return paths
    result = corpus([source], subdivide=REPORT_LEVELS, timing=False, quiet=True)
    return paths + write_out(result, out_dir / "corpus", with_rows=False)
