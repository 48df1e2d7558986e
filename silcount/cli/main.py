"""The ``silcount`` command line.

Each subcommand lives in ``silcount/cli/<name>.py`` and exposes ``HELP``
(one line), ``add_arguments(parser)`` and ``run(args) -> int``; :data:`COMMANDS`
maps each name to its module.  Command modules import only argparse-level
things at the top and their heavy dependencies (sympy, trimesh, matplotlib,
numba kernels) inside ``run``, so ``silcount render`` never loads sympy.
Library errors (:mod:`silcount.errors`) become one line on stderr and their
documented exit code here, and nowhere else:

| exit | meaning |
|------|---------|
| 0 | success |
| 1 | a check failed (e.g. ``compare`` found mismatches) |
| 2 | bad arguments |
| 3 | unreadable input, or an output that cannot be written (:mod:`silcount.atomic`) |
| 4 | invalid mesh |
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
from types import ModuleType

# numba's compiled kernels and Python's bytecode are read from inside the virtual environment unless
# NUMBA_CACHE_DIR and PYTHONPYCACHEPREFIX say otherwise (the Makefile's own settings), so that what
# ``make install`` compiles serves every later command, and the processes it starts (Dask's workers),
# even where PYTHONDONTWRITEBYTECODE keeps imports from writing bytecode themselves
if sys.prefix != sys.base_prefix:
    os.environ.setdefault("NUMBA_CACHE_DIR", os.path.join(sys.prefix, "cache", "numba"))
    if sys.pycache_prefix is None:
        sys.pycache_prefix = os.environ.setdefault("PYTHONPYCACHEPREFIX", os.path.join(sys.prefix, "cache", "pycache"))

from silcount.cli import audit, calibrate, claims, compare, corpus, figures, render, report, tables
from silcount.errors import SilcountError

COMMANDS: dict[str, ModuleType] = {
    "audit": audit,
    "report": report,
    "claims": claims,
    "tables": tables,
    "figures": figures,
    "render": render,
    "compare": compare,
    "corpus": corpus,
    "calibrate": calibrate,
}


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # exit 2 with one line, as argparse does, but name the program
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    from silcount.version import __version__

    parser = _Parser(prog="silcount", description="Audit silhouette-detection algorithms and the papers' cost claims.")
    parser.add_argument("--version", action="version", version=f"silcount {__version__}")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser)
    for name, module in COMMANDS.items():
        p = sub.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "command", None):
        parser.print_help()
        return 0
    try:
        return int(args._run(args) or 0)
    except SilcountError as exc:
        print(f"silcount {args.command}: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print("silcount: interrupted", file=sys.stderr)
        return 130


def run() -> None:
    """The ``silcount`` console script: :func:`main`, then exit without the teardown collections.

    Once numba's typing registries are loaded, the interpreter's garbage collections at exit take
    0.2-0.3 s (a third of a whole ``silcount render``).  ``gc.freeze()`` moves every live object to the
    permanent generation, so those collections find nothing to do; exit handlers, stream flushing
    and module teardown still run.  Only the process entry points call this, never :func:`main`.
    """
    code = main()
    gc.freeze()
    sys.exit(code)


if __name__ == "__main__":
    run()
