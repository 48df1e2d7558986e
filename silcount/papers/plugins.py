"""The papers a command judges: ``--paper DIR`` folders, or the built-ins and the ``silcount.papers`` entry points.

An entry point of the group ``silcount.papers`` names a paper folder (``docs/papers-as-data.md``): its object is
the folder (a path or string), or a callable returning it.  Entry points are looked up only when a command asks for
the papers (:func:`plugins`), never on ``import silcount``.  A paper is read (:func:`silcount.papers.registry.
read_folder`) and checked (every claim names a registered rule, :mod:`silcount.papers.claims.rules`): a broken
``--paper`` folder fails the command with one line naming it; a broken entry point is left out with one line naming
it, and the built-ins and other papers keep working.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

from silcount.counting import models
from silcount.papers.registry import BrokenPaper, Paper, forget, read_folder

ENTRY_POINT_GROUP = "silcount.papers"


def _entry_point_folder(ep) -> Path:
    obj = ep.load()
    return Path(obj() if callable(obj) else obj)


def plugins(warn: Callable[[str], None] | None = None) -> tuple[Paper, ...]:
    """The papers of the ``silcount.papers`` entry points.  A broken one is left out, with one line naming it
    passed to ``warn`` (default: printed on stderr), so that the others and the built-ins keep working."""
    from importlib.metadata import entry_points

    say = warn or (lambda line: print(line, file=sys.stderr))
    out = []
    for ep in sorted(entry_points(group=ENTRY_POINT_GROUP), key=lambda e: e.name):
        label = f"entry point {ep.name!r} ({ep.value})"
        try:
            out.append(check(read_folder(_entry_point_folder(ep), name=label), label))
        except BrokenPaper as exc:
            say(f"silcount: {exc} (left out)")
        except Exception as exc:  # the plugin's own code failed to load: left out, and said
            say(f"silcount: paper {label}: {type(exc).__name__}: {exc} (left out)")
    return tuple(out)


def check(paper: Paper, where: str = "") -> Paper:
    """``paper``, once every claim's ``check`` names a registered rule (else :class:`BrokenPaper`, naming ``where``,
    default the paper's folder)."""
    from silcount.papers.claims.rules import rules

    known = rules()
    for name in paper.claims:
        for c in models.load(name).get("claims", []):
            if c.get("check") not in known:
                forget(paper)
                raise BrokenPaper(
                    f"paper {where or paper.folder}: {name}.toml: claim {c.get('id')!r} names no known check "
                    f"{c.get('check')!r}"
                )
    return paper


def from_folders(folders: list[Path]) -> tuple[Paper, ...]:
    """The papers of ``--paper DIR`` options, each read and checked (:class:`BrokenPaper` names the folder)."""
    return tuple(check(read_folder(Path(f))) for f in folders)
