"""The papers a command judges: ``--paper DIR`` folders, or the built-ins and the ``silcount.papers`` entry points.

An entry point of the group ``silcount.papers`` names a paper folder (``docs/papers-as-data.md``): its object is
the folder (a path or string), or a callable returning it.  Entry points are looked up only when a command asks for
the papers (:func:`plugins`), never on ``import silcount``.  A paper is read (:func:`silcount.papers.registry.
read_folder`) and checked (every claim names a registered rule, :mod:`silcount.papers.claims.rules`; in a paper
with a text, every quote is at its lines): a broken
``--paper`` folder fails the command with one line naming it; a broken entry point is left out with one line naming
it, and the built-ins and other papers keep working.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

from silcount.counting import models
from silcount.papers.registry import BrokenPaper, Paper, builtin, forget, read_folder

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
    """``paper``, once every claim's ``check`` names a registered rule and, for a paper with a text, every claim's
    ``quote`` occurs in it over its ``lines`` (:func:`silcount.papers.quotes.check`); else :class:`BrokenPaper`,
    naming ``where`` (default the paper's folder), and the paper is forgotten."""
    try:
        _check(paper)
    except BrokenPaper as exc:
        forget(paper)
        raise BrokenPaper(f"paper {where or paper.folder}: {exc}") from exc
    return paper


def _check(paper: Paper) -> None:
    from silcount.papers.claims.rules import rules
    from silcount.papers.quotes import check as quoted

    known, text = rules(), _text(paper)
    for name in paper.claims:
        data = models.load(name)
        if data.get("source_file") != paper.source:
            raise BrokenPaper(
                f"{name}.toml: source_file {data.get('source_file')!r} is not the paper's {paper.source!r} "
                "(its text's file name, or its id when it has none)"
            )
        for c in data.get("claims", []):
            if c.get("check") not in known:
                raise BrokenPaper(f"{name}.toml: claim {c.get('id')!r} names no known check {c.get('check')!r}")
            if text is not None and not quoted(text, c.get("quote", ""), c.get("lines", "0")):
                raise BrokenPaper(
                    f"{name}.toml: claim {c.get('id')!r}: its quote is not at lines {c.get('lines')} of {paper.text}"
                )


def _text(paper: Paper) -> str | None:
    """The paper's text, None when it has none (its claims then have no quote checks)."""
    path = paper.text_path()
    if path is None:
        return None
    try:
        return path.read_text(encoding="utf-8")
    except OSError as exc:
        raise BrokenPaper(f"its text {paper.text}: {exc}") from exc


def from_folders(folders: list[Path]) -> tuple[Paper, ...]:
    """The papers of ``--paper DIR`` options, each read and checked (:class:`BrokenPaper` names the folder)."""
    return tuple(check(read_folder(Path(f))) for f in folders)


def chosen(folders: list[Path] | None) -> tuple[Paper, ...] | None:
    """What a command judges: the ``--paper`` folders' papers; without any, None (the built-ins) unless entry points
    add papers (then the built-ins and theirs; a broken one is left out with one line on stderr)."""
    if folders:
        return from_folders(folders)
    installed = plugins()
    return builtin() + installed if installed else None
