"""`silcount calibrate`: do the counts predict time? (issue 14; :mod:`silcount.calibrate`).

* ``silcount calibrate [--corpus PATH] [--out DIR]`` times each algorithm's
  compiled uncounted loops per light on the icosphere series (and every mesh
  file under ``--corpus`` of at most ``--max-faces`` faces), predicts each time as tally x profile with one
  scale per (cost model, profile), and writes the tables (md, csv, json), the
  figures and the raw ``timings.csv`` under ``DIR``; ``gaussmap`` and ``cones`` are timed too (their
  compiled query on the cached tree) and predicted with the papers' four's scales, reported apart;
* ``--timings FILE`` reuses a ``timings.csv`` instead of timing afresh (on the
  meshes it times, with its number of lights);
* ``--measure`` runs the micro-benchmarks instead and writes
  ``measured-<cpu model>.toml`` (to ``--out``, default ``silcount/models/cycles/``).

``silcount report`` writes the deterministic part (:func:`report`): the
committed timings (``silcount/models/cycles/timings-*.csv``) on the icosphere series,
and on the corpus when ``$SILCOUNT_CORPUS_DIR`` is set.  To refresh them, run
``silcount calibrate [--corpus DIR] --out DIR`` and copy ``DIR/timings.csv``
over the committed file.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--out", type=Path, metavar="DIR", help="output directory (default: calibrate/; missing folders are created)"
    )
    parser.add_argument("--corpus", type=Path, metavar="PATH", help="also time every mesh file under PATH")
    parser.add_argument(
        "--max-faces",
        type=int,
        default=5000,
        metavar="N",
        help="skip corpus meshes of more than N faces (VnV and EESD cost O(E F); default 5000)",
    )
    parser.add_argument("--timings", type=Path, metavar="FILE", help="use this timings.csv instead of timing")
    parser.add_argument(
        "--profile", action="append", default=[], metavar="TOML", help="also predict with this cycle profile file"
    )
    parser.add_argument("--lights", type=int, default=4, metavar="N", help="point lights per mesh (default 4)")
    parser.add_argument("--repeats", type=int, default=3, metavar="N", help="timed runs per sample, best kept")
    parser.add_argument("--measure", action="store_true", help="measure this machine's profile instead")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def report(out_dir: Path) -> list[Path]:
    """The committed timings on the icosphere series under ``out_dir/calibrate/``; on the corpus too
    (``out_dir/calibrate/corpus/``) when ``$SILCOUNT_CORPUS_DIR`` names a folder and the timings time corpus
    files (without it, that section is left as it is, saying so)."""
    from silcount.calibrate import output, timing
    from silcount.calibrate.calibration import committed_timings, from_committed, read_timings
    from silcount.cli.corpus import CORPUS_ENV, corpus_dir

    paths = output.write(from_committed(), out_dir / "calibrate")
    corpus = corpus_dir()
    timed = committed_timings()
    if timed is not None and set(read_timings(timed)["mesh"]) - set(timing.SERIES):
        if corpus is None:  # the corpus section as committed stays; nothing to recompute it from
            print(f"calibrate: corpus skipped: ${CORPUS_ENV} does not name a folder", file=sys.stderr)
        else:
            paths += output.write(from_committed(corpus), out_dir / "calibrate" / "corpus")
    return paths


def run(args: argparse.Namespace) -> int:
    from silcount.atomic import check_writable
    from silcount.calibrate import output, timing
    from silcount.calibrate.calibration import calibrate, read_timings
    from silcount.calibrate.measure import cpu_model_name, measure
    from silcount.counting.cycles import builtin_profiles, cycles_dir, load_profile
    from silcount.errors import BadArgument, UnreadableInput

    if args.lights < 1 or args.repeats < 1:
        raise BadArgument("--lights and --repeats must be at least 1")
    if args.measure:
        print(measure(check_writable(args.out or cycles_dir(), folder=True)))
        return 0
    profiles = builtin_profiles()
    for spec in args.profile:
        prof = load_profile(spec)
        profiles[prof.name] = prof
    meshes = timing.series_meshes()
    if args.corpus is not None:
        if not args.corpus.is_dir():
            raise BadArgument(f"--corpus {args.corpus}: not a directory")
        for group, mesh in timing.corpus_meshes(args.corpus):
            if mesh.n_faces <= args.max_faces:
                meshes.append((group, mesh))
            else:
                print(f"skipped {mesh.name}: {mesh.n_faces} faces > --max-faces {args.max_faces}", file=sys.stderr)
    out = check_writable(args.out or Path("calibrate"), folder=True)  # after the arguments, before the timing
    show = False if args.quiet else None
    n_lights = args.lights
    if args.timings is not None:
        times = read_timings(args.timings)
        meshes = [(group, mesh) for group, mesh in meshes if mesh.name in set(times["mesh"])]
        if not meshes:
            raise UnreadableInput(f"timings {args.timings} time none of the meshes")
        n_lights = int(times["light"].max()) + 1
        cpu, source, live = str(times["cpu_model"].iloc[0]), str(args.timings), False
    else:
        times = timing.timings(meshes, n_lights, args.repeats, show)
        cpu, source, live = cpu_model_name(), "measured in this run", True
    cal = calibrate(meshes, times, cpu, source, profiles, n_lights, show)
    for path in output.write(cal, out, with_timings=live):
        print(path)
    return 0
