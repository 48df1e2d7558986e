"""``--paper DIR``, shared by `silcount claims`, `tables`, `figures` and `audit`: a paper given as a folder of TOML.

Without it a command judges the built-in papers and those of the ``silcount.papers`` entry points
(:mod:`silcount.papers.plugins`); with it, the named folders only.  A folder that cannot be read fails the command
with one line naming it (exit 3, :class:`silcount.papers.registry.BrokenPaper`).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from silcount.papers.registry import Paper


def add_paper_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--paper",
        action="append",
        type=Path,
        default=None,
        metavar="DIR",
        help="a paper given as a folder of TOML files (docs/papers-as-data.md; repeatable); default: the built-in "
        "papers and those installed under the entry-point group silcount.papers",
    )


def papers_from(args: argparse.Namespace) -> "tuple[Paper, ...] | None":
    """The ``--paper`` folders' papers, or None (the default papers) when none is given; entry points are read only
    when no folder is given (a broken one is left out with one line on stderr)."""
    from silcount.papers import plugins, registry

    if args.paper:
        return plugins.from_folders(args.paper)
    installed = plugins.plugins()
    return registry.builtin() + installed if installed else None
