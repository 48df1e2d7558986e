"""Output files: every file silcount writes appears whole or not at all, where the one rule below says.

A file is written to a temporary name in its destination directory, then
renamed over the destination with ``os.replace`` (atomic on POSIX), so an
error or an interrupt never leaves half a report, mask or figure behind.

The rule for output paths, the same for every command (``audit``, ``render``,
``report``, ``tables``, ``figures``, ``corpus``, ``calibrate``): the missing
folders of an output path are created (as ``mkdir -p``), and a path that
cannot be written (a directory where a file goes, a file where a folder goes,
a folder that cannot be made, no permission, a read-only or full file system)
is one :class:`~silcount.errors.UnwritableOutput` naming the path and the
reason (exit 3).  :func:`check_writable` applies the rule before a command's
work, so that a bad ``--out`` fails at once rather than after a long render.

A written file gets the mode ``open()`` would give it: the temporary file is
created with mode 0o666, which the kernel reduces by the umask (and by a
folder's default ACL).  ``tempfile.mkstemp`` would create it 0o600 whatever the
umask, and ``os.replace`` keeps that mode, so other users could not read the
reports.
"""

from __future__ import annotations

import errno
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from silcount.errors import UnwritableOutput

_FLAGS = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)


def _reason(exc: OSError) -> str:
    return exc.strerror or str(exc)


def _folder_problem(p: Path) -> str | None:
    """Create folder ``p`` and its missing parents; what went wrong, or None."""
    try:
        p.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):  # a file where a folder of the path goes
        blocker = next((a for a in (p, *p.parents) if a.exists() and not a.is_dir()), p)
        return f"{blocker} is a file, not a folder"
    except OSError as exc:
        where = f" (creating {exc.filename})" if exc.filename and os.fspath(exc.filename) != os.fspath(p) else ""
        return f"{_reason(exc)}{where}"
    return None


def make_folder(path: str | os.PathLike) -> Path:
    """Create folder ``path`` and its missing parents; any failure is :class:`UnwritableOutput` naming it."""
    p = Path(path)
    if problem := _folder_problem(p):
        raise UnwritableOutput(f"cannot create folder {p}: {problem}")
    return p


def _make_parent(p: Path) -> None:
    """Create the folder of file ``p``; any failure is :class:`UnwritableOutput` naming the file."""
    if problem := _folder_problem(p.parent):
        raise UnwritableOutput(f"cannot write {p}: {problem}")


def _new_file_beside(p: Path) -> Path:
    """Create an empty file of a fresh name beside ``p`` (same suffix), mode 0o666 less the umask.  The name's
    8 hex digits are ``os.urandom``'s, as :mod:`secrets`' are (whose import of :mod:`hmac` cost 6 ms of a
    ``silcount render``)."""
    for _ in range(tempfile.TMP_MAX):
        tmp = p.parent / f".{p.name}.{os.urandom(4).hex()}{p.suffix or '.tmp'}"
        try:
            os.close(os.open(tmp, _FLAGS, 0o666))
        except FileExistsError:
            continue
        return tmp
    raise FileExistsError(errno.EEXIST, "no unused temporary file name", str(p.parent))


def check_writable(path: str | os.PathLike, *, folder: bool = False) -> Path:
    """Apply the output rule now: create the folder of ``path`` (``path`` itself when ``folder``) and create
    and remove a temporary file in it, as writing will; :class:`UnwritableOutput` if any of it fails.

    A real write is the only honest test: ``os.access`` answers yes to root on a read-only folder.
    """
    p = Path(path)
    if not folder and p.is_dir():
        raise UnwritableOutput(f"cannot write {p}: {os.strerror(errno.EISDIR)}")
    if folder:
        make_folder(p)
    else:
        _make_parent(p)
    try:
        _new_file_beside(p / ".probe" if folder else p).unlink()
    except OSError as exc:
        raise UnwritableOutput(f"cannot write {p if not folder else f'in {p}'}: {_reason(exc)}") from None
    return p


@contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path`` (same suffix); on success rename it to ``path``.

    Missing folders are created; an ``OSError`` (making the temporary file, writing it, renaming it) becomes
    :class:`UnwritableOutput` naming ``path``, with the temporary file removed.
    """
    p = Path(path)
    _make_parent(p)
    try:
        tmp = _new_file_beside(p)
    except OSError as exc:
        raise UnwritableOutput(f"cannot write {p}: {_reason(exc)}") from None
    try:
        yield tmp
        os.replace(tmp, p)
    except BaseException as exc:
        tmp.unlink(missing_ok=True)
        if isinstance(exc, OSError):
            raise UnwritableOutput(f"cannot write {p}: {_reason(exc)}") from None
        raise


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write UTF-8 ``text`` to ``path`` atomically; returns the path."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)
