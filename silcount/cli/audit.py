"""`silcount audit [MESH]`: every detector on one mesh (or on every built-in mesh), per light and aggregated.

The computation is :func:`silcount.audit.compute.run_audit`; the layout is
:mod:`silcount.audit.layout`.  Output goes to stdout, or with ``--out`` to a file
written atomically (a temporary file renamed into place, so a failure never
leaves half a report).  With no MESH, every built-in mesh is audited; ``--out``
is then a directory receiving ``<mesh>.<format>``.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from silcount.errors import BadArgument, TooMuchWork
from silcount.options import AUDIT_FORMATS, DEFAULT_LIGHT_COUNT, DEFAULT_SEED, PAPER_HELP

if TYPE_CHECKING:
    from silcount.audit.compute import AuditSettings
    from silcount.mesh.lights import Light
    from silcount.mesh.model import Mesh

EXTENSIONS = {"text": "txt", "md": "md", "json": "json"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    # let "--light -1,2,3" read as a value, as argparse already does for "-1" and "-.5"
    parser._negative_number_matcher = re.compile(r"^-[\d.]")
    parser.add_argument(
        "mesh",
        nargs="?",
        metavar="MESH",
        help="OBJ, OFF, PLY, STL, GLB or GLTF file; omitted: audit every built-in mesh",
    )
    parser.add_argument("--light", action="append", default=[], metavar="X,Y,Z", help="a point light (repeatable)")
    parser.add_argument(
        "--directional",
        action="append",
        default=[],
        metavar="X,Y,Z",
        help="a directional light, the direction towards the light (repeatable)",
    )
    parser.add_argument(
        "--random-lights",
        type=int,
        default=None,
        metavar="N",
        help=f"N point lights at random on a sphere of 3x the bounding radius "
        f"(default {DEFAULT_LIGHT_COUNT} when no light is given)",
    )
    parser.add_argument(
        "--seed", type=int, default=DEFAULT_SEED, help=f"seed of the random lights (default {DEFAULT_SEED})"
    )
    parser.add_argument(
        "--detectors",
        default=None,
        metavar="LIST",
        help="comma-separated detector names (default: every registered one)",
    )
    parser.add_argument("--variant", choices=("intended", "literal", "both"), default="intended")
    parser.add_argument("--engine", choices=("fast", "naive"), default="fast")
    parser.add_argument(
        "--cycles",
        default="paper",
        metavar="PROFILE|FILE",
        help="cycle profile: paper (EESD 2012 weights), unit, or a TOML file (default paper)",
    )
    parser.add_argument(
        "--with-edges",
        action="store_true",
        help="list each light's silhouette edges as [[x,y,z],[x,y,z]] in the input's coordinates",
    )
    parser.add_argument("--format", choices=AUDIT_FORMATS, default="text")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        metavar="PATH",
        help="write here instead of stdout (a directory when MESH is omitted; missing folders are created)",
    )
    parser.add_argument(
        "--max-memory",
        default=None,
        metavar="SIZE",
        help="refuse meshes estimated to need more (e.g. 2G; default $SILCOUNT_MAX_MEMORY or free RAM)",
    )
    parser.add_argument(
        "--max-work",
        default=None,
        metavar="N",
        help="refuse a detector run whose elementary tests (ray-triangle, plane-point) pass N "
        "(e.g. 1e12; default $SILCOUNT_MAX_WORK or 1e11; per light); the others are reported",
    )
    parser.add_argument(
        "--weld-tolerance",
        type=float,
        default=0.0,
        metavar="T",
        help="merge vertices closer than T (default 0: weld by exact position only)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    parser.add_argument("--paper", action="append", type=Path, default=None, metavar="DIR", help=PAPER_HELP)


def parse_vector(text: str, option: str) -> tuple[float, float, float]:
    """``"1,2,3"`` -> (1.0, 2.0, 3.0); anything else is a :class:`BadArgument` naming the option."""
    parts = text.replace(" ", "").split(",")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        values = ()
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise BadArgument(f"{option} {text!r}: expected three finite comma-separated numbers X,Y,Z")
    return values


def explicit_lights(args: argparse.Namespace) -> list[Light]:
    from silcount.mesh.lights import DirectionalLight, PointLight

    lights: list[Light] = [PointLight(parse_vector(t, "--light")) for t in args.light]
    for t in args.directional:
        v = parse_vector(t, "--directional")
        if not any(v):
            raise BadArgument(f"--directional {t!r}: the zero vector has no direction")
        lights.append(DirectionalLight(v))
    return lights


def settings_from(args: argparse.Namespace) -> AuditSettings:
    from silcount.audit.compute import AuditSettings
    from silcount.detectors import get, names

    if args.detectors is None:
        chosen = names()
    else:
        chosen = tuple(d.strip() for d in args.detectors.split(",") if d.strip())
        for d in chosen:
            get(d, prefix="--detectors: ")
        if not chosen:
            raise BadArgument("--detectors: the list is empty")
    variants = ("intended", "literal") if args.variant == "both" else (args.variant,)
    return AuditSettings(
        detectors=chosen,
        variants=variants,
        engine=args.engine,
        cycles=args.cycles,
        with_edges=args.with_edges,
        formulas=paper_formulas(args.paper or []),
    )


def paper_formulas(folders: list[Path]) -> tuple[tuple[str, str], ...]:
    """``(detector, model)`` of each algorithm of the ``--paper`` folders that prints a closed form for a detector."""
    if not folders:
        return ()
    from silcount.counting import models
    from silcount.detectors import names
    from silcount.papers import plugins

    out: dict[str, str] = {}
    for paper in plugins.from_folders(folders):
        for model in paper.algorithms:
            spec = models.load(model)
            detector = spec.get("algorithm")
            if "closed_form" not in spec or detector not in names():
                continue
            if detector in out:
                raise BadArgument(f"--paper: {out[detector]} and {model} both print a closed form for {detector}")
            out[detector] = model
    return tuple(sorted(out.items()))


def lights_for(mesh: Mesh, fixed: list[Light], count: int | None, seed: int) -> list[Light]:
    from silcount.mesh.lights import random_lights

    if count is not None and count < 0:
        raise BadArgument(f"--random-lights {count}: must be >= 0")
    n = count if count is not None else (0 if fixed else DEFAULT_LIGHT_COUNT)
    lights = fixed + random_lights(mesh, n, seed)
    if not lights:
        raise BadArgument("no light: give --light, --directional or --random-lights N with N > 0")
    return lights


def audit_one(mesh: Mesh, args: argparse.Namespace, settings: AuditSettings, fixed: list[Light], source: str) -> dict:
    from silcount.audit.compute import run_audit

    return run_audit(
        mesh, lights_for(mesh, fixed, args.random_lights, args.seed), settings, source=source, quiet=args.quiet
    )


def refusals(audits: list[dict]) -> int:
    """One line on stderr per refused run (the reports name them too); the exit code: 0, or
    :class:`TooMuchWork`'s when some run was refused."""
    lines = [
        f"silcount audit: error: {a['source']}: {k} refused: {why}"
        for a in audits
        for k, why in a.get("refused", {}).items()
    ]
    for line in lines:
        print(line, file=sys.stderr)
    return TooMuchWork.exit_code if lines else 0


def run(args: argparse.Namespace) -> int:
    from silcount.atomic import check_writable, write_text
    from silcount.audit.costs import cycle_profile
    from silcount.audit.layout import format_audit, render_json
    from silcount.mesh import shapes
    from silcount.mesh.chunks import limit_work, parse_work
    from silcount.mesh.io import load_mesh, parse_size

    settings = settings_from(args)
    fixed = explicit_lights(args)
    max_memory = parse_size(args.max_memory, "--max-memory") if args.max_memory else None
    max_work = parse_work(args.max_work, "--max-work") if args.max_work else None
    cycle_profile(settings.cycles)  # a bad profile fails before a large mesh is loaded
    if args.out is not None:  # and so does an --out that cannot be written
        check_writable(args.out, folder=args.mesh is None)
    with limit_work(max_work):  # the runs' work limit (silcount.mesh.chunks)
        if args.mesh is not None:
            if not args.weld_tolerance >= 0.0:
                raise BadArgument(f"--weld-tolerance must be >= 0, got {args.weld_tolerance}")
            mesh = load_mesh(args.mesh, max_memory=max_memory, weld_tolerance=args.weld_tolerance)
            audit = audit_one(mesh, args, settings, fixed, str(args.mesh))
            text = format_audit(audit, args.format)
            if args.out is None:
                sys.stdout.write(text)
            else:
                write_text(args.out, text)
                print(f"wrote {args.out}", file=sys.stderr)
            return refusals([audit])
        audits = []
        for name in shapes.BUILTIN:
            audits.append((name, audit_one(shapes.builtin_mesh(name), args, settings, fixed, f"built-in {name}")))
        if args.out is not None:
            for name, a in audits:
                path = args.out / f"{name}.{EXTENSIONS[args.format]}"
                write_text(path, format_audit(a, args.format))
                print(f"wrote {path}", file=sys.stderr)
        elif args.format == "json":
            sys.stdout.write(render_json([a for _, a in audits]))  # type: ignore[arg-type]
        else:
            sys.stdout.write("\n".join(format_audit(a, args.format) for _, a in audits))
        return refusals([a for _, a in audits])
