"""The papers silcount judges, each a folder of TOML files (``docs/papers-as-data.md``).

A paper folder holds ``paper.toml`` (its metadata and the names of its other
files) and, each named there, its algorithms' annotated pseudo-code
(``silcount/models/README.md``), its tables and its claims files.  The three
built-in papers are folders of package data, ``silcount/models/papers/<id>/``,
read through :func:`silcount.counting.models.models_dir` (``importlib.resources``).
A user's paper is a folder given with ``--paper DIR``, or one named by an
entry point of the group ``silcount.papers`` (:mod:`silcount.papers.plugins`).

``paper.toml``: ``id``, ``label``, ``title``, ``citation``; ``text``, the plain
text its quotes are checked against (a path relative to the folder, or a name
in ``$SILCOUNT_PAPERS_DIR``), omitted when silcount has no text of it; and the
lists ``algorithms``, ``tables``, ``claims`` (file names without ``.toml``) and
``figures`` (``{label, model}`` of the algorithms its figures draw).
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from silcount.counting import models
from silcount.errors import UnreadableInput

MANIFEST = "paper.toml"
LISTS = ("algorithms", "tables", "claims")


class BrokenPaper(UnreadableInput):
    """A paper folder cannot be read: its TOML does not parse, a field or a file is missing, a check is unknown."""


@dataclass(frozen=True)
class Paper:
    """One paper as data: its metadata and the model names of its files (loaded with ``models.load``)."""

    id: str
    label: str
    title: str
    citation: str
    folder: Path
    text: str  # the text file its quotes are checked against; "" when silcount has none
    algorithms: tuple[str, ...]
    tables: tuple[str, ...]
    claims: tuple[str, ...]
    figures: tuple[tuple[str, str], ...]
    builtin: bool

    @property
    def source(self) -> str:
        """What its claims carry as ``paper``: the text file's name, or the paper's id when it has no text."""
        return Path(self.text).name if self.text else self.id

    def text_path(self) -> Path | None:
        """The text file: relative to the folder if it is there, else in ``$SILCOUNT_PAPERS_DIR``; None: no text."""
        if not self.text:
            return None
        local = self.folder / self.text
        if local.is_file():
            return local
        return Path(os.environ.get("SILCOUNT_PAPERS_DIR", "")) / self.text


def _fail(where: object, what: str) -> BrokenPaper:
    return BrokenPaper(f"paper {where}: {what}")


def read_folder(folder: Path, *, builtin: bool = False, name: str = "") -> Paper:
    """The paper of ``folder`` (``name``: the entry point that named it, for the error); a folder outside the
    package has its files added to :func:`silcount.counting.models.load` by name.  Raises :class:`BrokenPaper`."""
    where = name or folder
    manifest = folder / MANIFEST
    try:
        with open(manifest, "rb") as fh:
            meta = tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise _fail(where, f"cannot read {manifest}: {exc}") from exc
    missing = [k for k in ("id", "label", "title", "citation") if not isinstance(meta.get(k), str)]
    if missing:
        raise _fail(where, f"{manifest} lacks {', '.join(missing)}")
    files = {k: tuple(meta.get(k, ())) for k in LISTS}
    figures = tuple((f["label"], f["model"]) for f in meta.get("figures", ()))
    if not builtin:
        names = sorted({m for listed in files.values() for m in listed} | {m for _, m in figures})
        for model in names:  # every file parses before any is added
            path = folder / f"{model}.toml"
            try:
                with open(path, "rb") as fh:
                    tomllib.load(fh)
            except (OSError, tomllib.TOMLDecodeError) as exc:
                raise _fail(where, f"{path.name}: {exc}") from exc
        try:
            for model in names:
                models.add_file(model, folder / f"{model}.toml")
        except ValueError as exc:
            models.drop_files(n for n in names if models.model_path(n).parent == folder)
            raise _fail(where, str(exc)) from exc
    paper = Paper(
        id=meta["id"],
        label=meta["label"],
        title=meta["title"],
        citation=meta["citation"],
        folder=folder,
        text=meta.get("text", ""),
        figures=figures,
        builtin=builtin,
        **files,
    )
    if not builtin:
        _READ[paper.source] = paper
    return paper


_READ: dict[str, Paper] = {}
"""The papers read from folders outside the package, by :attr:`Paper.source`."""


@cache
def builtin() -> tuple[Paper, ...]:
    """The built-in papers, ``silcount/models/papers/<id>/``, in their folders' order."""
    root = models.models_dir() / "papers"
    return tuple(read_folder(p.parent, builtin=True) for p in sorted(root.glob(f"*/{MANIFEST}")))


def forget(paper: Paper) -> None:
    """Forget a paper read from a folder (found broken after it was read): its files and its source."""
    models.drop_files(n for n in (*paper.algorithms, *paper.tables, *paper.claims, *(m for _, m in paper.figures)))
    _READ.pop(paper.source, None)


def known() -> tuple[Paper, ...]:
    """The built-in papers and every paper read so far from a folder."""
    return builtin() + tuple(_READ.values())


def by_source(source: str) -> Paper:
    """The paper whose claims carry ``source`` as ``paper`` (:attr:`Paper.source`)."""
    for p in known():
        if p.source == source:
            return p
    raise KeyError(f"no paper has the source {source!r}")


def claim_files() -> tuple[str, ...]:
    """The claims files of every known paper (:func:`known`)."""
    return tuple(name for p in known() for name in p.claims)
