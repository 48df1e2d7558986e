"""`silcount report [--out DIR]`: regenerate everything under reports/ from built-in data.

The parts, each a module exposing ``report(out_dir: Path) -> list[Path]``:
claims, tables, figures (``silcount.cli.claims``/``tables``/``figures``),
the renders of the shared scenes (``silcount.cli.render``), and the
audit of every built-in mesh (:func:`report` here, into ``<out>/audit/``).

Deterministic: the audits written here carry no wall times (``time_s`` is
``null``), use the default 16 lights of seed 0, both variants and the
``fast`` engine, so the same files come out on every run.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from silcount.audit.formats import render, write_atomic
from silcount.audit.run import AuditSettings, random_lights, run_audit
from silcount.cli import calibrate, claims, corpus, figures, tables
from silcount.cli import render as renders
from silcount.cli.audit import EXTENSIONS
from silcount.detectors import DETECTORS
from silcount.errors import BadArgument
from silcount.mesh import shapes

HELP = "regenerate everything under reports/ (claims, tables, figures, renders, audits) from built-in data"
PARTS = (
    ("claims", claims.report),
    ("tables", tables.report),
    ("figures", figures.report),
    ("render", renders.report),
    ("corpus", corpus.report),
    ("calibrate", calibrate.report),
)
# icosphere5 (20,480 faces) is left out: EESD's literal variant costs O(E x F) even in the fast engine
# (about six minutes for 16 lights on this machine); the size sweeps cover it.
REPORT_MESHES = tuple(name for name in shapes.BUILTIN if name != "icosphere5")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--out", type=Path, default=Path("reports"), metavar="DIR", help="output directory (default: reports)"
    )


def report(out_dir: Path) -> list[Path]:
    """Audit every built-in mesh into ``out_dir/audit/<mesh>.md`` and ``.json``; returns the paths."""
    settings = AuditSettings(detectors=DETECTORS, variants=("intended", "literal"), with_time=False)
    written = []
    for name in REPORT_MESHES:
        mesh = shapes.builtin_mesh(name)
        audit = run_audit(mesh, random_lights(mesh), settings, source=f"built-in {name}", quiet=True)
        for form in ("md", "json"):
            path = out_dir / "audit" / f"{name}.{EXTENSIONS[form]}"
            write_atomic(path, render(audit, form))
            written.append(path)
    return written


def run(args: argparse.Namespace) -> int:
    out: Path = args.out
    if out.exists() and not out.is_dir():
        raise BadArgument(f"--out {out}: not a directory")
    for name, fn in (*PARTS, ("audit", report)):
        paths = fn(out)
        print(f"{name}: wrote {len(paths)} files under {out}")
        for p in paths:
            print(f"  {p}")
    return 0
