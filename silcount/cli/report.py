"""`silcount report [--out DIR]`: regenerate everything under reports/ from built-in data.

The parts, each a module exposing ``report(out_dir: Path) -> list[Path]``:
claims, tables, figures (``silcount.cli.claims``/``tables``/``figures``),
the renders of the shared scenes (``silcount.cli.render``), a worst-case row per detector
(``silcount.cli.worst_case``, into ``<out>/worst-case/``), the frame budget
(:func:`frame_budget`, from the committed stage times), and the
audit of every built-in mesh (:func:`report` here, into ``<out>/audit/``).

Deterministic: the audits written here carry no wall times (``time_s`` is
``null``), use the default 16 lights of seed 0, both variants and the
``fast`` engine, so the same files come out on every run.

Parallel: the parts (and the audit of each mesh) are independent, so they
run in a pool of worker processes, one per available core (``spawn``ed:
no numba thread pool is forked; numba single-threaded in each); each writes only its own files, and the
listing is printed in the fixed order below whatever the finishing order.
A failing part fails the command with one line naming it.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from silcount.cli import calibrate, claims, corpus, figures, tables, worst_case
from silcount.cli import render as renders
from silcount.cli.audit import EXTENSIONS
from silcount.errors import SilcountError
from silcount.options import DEFAULT_LIGHT_COUNT, DEFAULT_SEED


def frame_budget(out_dir: Path) -> list[Path]:
    """The frame budget (:mod:`silcount.papers.budget`) under ``out_dir/frame/``, from the committed times."""
    from silcount.papers.budget import report as budget_report

    return budget_report(out_dir)


PARTS = (
    ("claims", claims.report),
    ("tables", tables.report),
    ("render", renders.report),
    ("corpus", corpus.report),
    ("calibrate", calibrate.report),
    ("worst-case", worst_case.report),
    ("frame", frame_budget),
)
# icosphere5 (20,480 faces) is left out: EESD's literal variant costs O(E x F) even in the fast engine
# (about six minutes for 16 lights on this machine); the size sweeps cover it.
LEFT_OUT = ("icosphere5",)


def report_meshes() -> tuple[str, ...]:
    """The built-in meshes whose audits `silcount report` writes: all but :data:`LEFT_OUT`."""
    from silcount.mesh import shapes

    return tuple(name for name in shapes.BUILTIN if name not in LEFT_OUT)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("reports"),
        metavar="DIR",
        help="output directory (default: reports; missing folders are created)",
    )


def audit_one(out_dir: Path, name: str) -> list[Path]:
    """Audit built-in mesh ``name`` into ``out_dir/audit/<name>.md`` and ``.json``; returns the paths."""
    from silcount.atomic import write_text
    from silcount.audit.compute import AuditSettings, run_audit
    from silcount.audit.layout import format_audit
    from silcount.detectors import names
    from silcount.mesh import shapes
    from silcount.mesh.lights import random_lights

    settings = AuditSettings(detectors=names(), variants=("intended", "literal"), with_time=False)
    mesh = shapes.builtin_mesh(name)
    audit = run_audit(
        mesh, random_lights(mesh, DEFAULT_LIGHT_COUNT, DEFAULT_SEED), settings, source=f"built-in {name}", quiet=True
    )
    written = []
    for form in ("md", "json"):
        path = out_dir / "audit" / f"{name}.{EXTENSIONS[form]}"
        write_text(path, format_audit(audit, form))
        written.append(path)
    return written


def report(out_dir: Path) -> list[Path]:
    """Audit every built-in mesh into ``out_dir/audit/<mesh>.md`` and ``.json``; returns the paths."""
    return [p for name in report_meshes() for p in audit_one(out_dir, name)]


class PartFailed(SilcountError):
    """A part of `silcount report` raised: the message names it; the exit code is the error's own (1 for an
    exception that is not a :class:`SilcountError`)."""

    def __init__(self, message: str, exit_code: int = 1) -> None:
        super().__init__(message, exit_code)
        self.exit_code = exit_code

    def __str__(self) -> str:
        return str(self.args[0])


def _run_part(name: str, fn: Callable[..., list[Path]], *args) -> list[Path]:
    try:
        return fn(*args)
    except Exception as exc:  # re-raised with the part's name (in the worker, where the traceback is)
        code = exc.exit_code if isinstance(exc, SilcountError) else 1
        raise PartFailed(f"part {name} failed: {type(exc).__name__}: {exc}", code) from exc


def _one_thread() -> None:
    """Worker initialiser: numba kernels single-threaded (the pool is the parallelism; no oversubscription)."""
    import numba

    numba.set_num_threads(1)


def _workers() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1))


def run(args: argparse.Namespace) -> int:
    from silcount.atomic import check_writable

    out: Path = check_writable(args.out, folder=True)
    # the dearest first, so that no long part starts last (figures, then corpus: ~10 s each on one core)
    tasks: list[tuple[str, Callable[..., list[Path]], tuple]] = [
        (f"figure {name}", figures.report, (out, name)) for name in figures.PARTS
    ]
    tasks += [(name, fn, (out,)) for name, fn in PARTS]
    meshes = report_meshes()
    tasks += [(f"audit {mesh}", audit_one, (out, mesh)) for mesh in meshes]
    with ProcessPoolExecutor(_workers(), mp_context=mp.get_context("spawn"), initializer=_one_thread) as pool:
        futures = [pool.submit(_run_part, name, fn, *a) for name, fn, a in tasks]
        done = [f.result() for f in futures]  # in task order; the first failure is raised here
    listing = {name: paths for (name, _, _), paths in zip(tasks, done, strict=True)}
    figure_paths = [p for name in figures.PARTS for p in listing.pop(f"figure {name}")]
    audits = [p for mesh in meshes for p in listing.pop(f"audit {mesh}")]
    for name, paths in (("figures", figure_paths), *listing.items(), ("audit", audits)):
        print(f"{name}: wrote {len(paths)} files under {out}")
        for p in paths:
            print(f"  {p}")
    return 0
