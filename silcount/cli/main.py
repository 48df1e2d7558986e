"""The ``silcount`` command line.

Each subcommand lives in ``silcount/cli/<name>.py`` and exposes
``add_arguments(parser)`` and ``run(args) -> int``; :data:`COMMANDS` maps each
name to its one-line help.  A subcommand's module is imported only when that
subcommand is chosen (:class:`_Commands`), so ``silcount --help`` imports none
of them.  Command modules import only argparse-level things at the top (their
choices come from :mod:`silcount.options`) and their heavy dependencies
(numba kernels, scipy, sympy, pandas, matplotlib) inside ``run``, so
``silcount CMD --help`` loads none of them and ``silcount render`` never loads sympy.
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
import importlib
import os
import sys

# Python's bytecode is read from inside the virtual environment unless PYTHONPYCACHEPREFIX says otherwise
# (the Makefile's own setting), so that what ``make install`` compiles serves every later command, and the
# processes it starts (Dask's workers), even where PYTHONDONTWRITEBYTECODE keeps imports from writing
# bytecode themselves; numba's cache has the same default, set by ``import silcount`` for every caller
if sys.prefix != sys.base_prefix and sys.pycache_prefix is None:
    sys.pycache_prefix = os.environ.setdefault("PYTHONPYCACHEPREFIX", os.path.join(sys.prefix, "cache", "pycache"))

from silcount.errors import SilcountError

COMMANDS: dict[str, str] = {
    "audit": "audit a mesh: silhouette edges and operation tallies of every detector, per light and aggregated",
    "report": "regenerate everything under reports/ (claims, tables, figures, renders, audits) from built-in data",
    "claims": "every quantitative claim of the papers: printed, re-derived, measured, verdict",
    "tables": "the EESD paper's Tables 1-2 and the HSD equivalents: printed, re-derived, measured",
    "figures": "the papers' figures redrawn, as printed and corrected, and measured growth plots (PNG, SVG)",
    "render": "render a silcount-scene/1 file's shadow mask by z-pass, z-fail, planar projection or ray casting",
    "compare": "compare two shadow-mask PNGs; exit 1 on real disagreements",
    "corpus": "sweep a collection of meshes (files or folders): silhouette size and every detector's cost against "
    "faces",
    "calibrate": "do the counts predict time? time the algorithms' compiled loops and predict them from tally x cycle "
    "profile",
    "worst-case": "search meshes, face orders and lights for a detector's worst case: a bound exceeded, the "
    "fastest-growing family, the most work per silhouette edge",
}
"""Each subcommand's one-line help; its module is ``silcount.cli.<name>`` (a ``-`` in the name is ``_``)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # exit 2 with one line, as argparse does, but name the program
        self.exit(2, f"{self.prog}: error: {message}\n")


class _Commands(argparse._SubParsersAction):
    """The subcommands' action: the chosen subcommand's module is imported and adds its arguments, then it parses.

    Only the chosen subcommand's parser gets its arguments; the others stay empty (their names and help
    lines come from :data:`COMMANDS`).
    """

    def __call__(self, parser, namespace, values, option_string=None):
        name = values[0]
        if name in COMMANDS and not self._name_parser_map[name].get_default("_run"):
            module = importlib.import_module(f"silcount.cli.{name.replace('-', '_')}")
            module.add_arguments(self._name_parser_map[name])
            self._name_parser_map[name].set_defaults(_run=module.run)
        super().__call__(parser, namespace, values, option_string)


def build_parser() -> argparse.ArgumentParser:
    from silcount.version import __version__

    parser = _Parser(prog="silcount", description="Audit silhouette-detection algorithms and the papers' cost claims.")
    parser.add_argument("--version", action="version", version=f"silcount {__version__}")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser, action=_Commands)
    for name, help_line in COMMANDS.items():
        sub.add_parser(name, help=help_line, description=help_line)
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
    """The ``silcount`` console script: :func:`main` with fewer collections, then exit without the teardown ones.

    Start-up allocates some 120,000 long-lived objects (numba and its typing registries, for ``silcount
    render``).  With the collector's default first threshold, 700, that costs 255 young, 23 middle and 2
    full collections, each traversing what was loaded so far: 0.06 s of the 0.79 s of CPU time of a whole
    ``silcount render`` of the shared cow_and_cubes scene.  A first threshold of 10,000 leaves 32, 2 and 0
    (``gc.get_stats()``); cycles are still collected, 14 times less often.  Once numba's typing registries
    are loaded, the interpreter's garbage collections at exit take 0.2-0.3 s (a third of a whole ``silcount
    render``).  ``gc.freeze()`` moves every live object to the permanent generation, so those collections
    find nothing to do; exit handlers, stream flushing and module teardown still run.  Only the process
    entry points call this, never :func:`main`.
    """
    gc.set_threshold(10_000, *gc.get_threshold()[1:])
    code = main()
    gc.freeze()
    sys.exit(code)


if __name__ == "__main__":
    run()
