"""The detectors silcount knows: the built-ins and the installed plug-ins, each a :class:`.spec.DetectorSpec`.

:func:`register_detector` adds one.  The registry fills itself on first use (never at ``import silcount``):
first the seven built-ins (:mod:`.builtin`, each registered by :func:`register_detector` like any other; :func:`get`
answers a built-in's name before that, from its own module alone),
then every entry point of the group :data:`GROUP` of the installed distributions (:mod:`importlib.metadata`),
in the order of their names.  A plug-in that fails to import, whose entry point is not a complete
:class:`DetectorSpec`, or whose name is already taken, is left out with one line naming it (a
:class:`PluginWarning`), and every other detector keeps working; asking for it by name is then an unknown
detector.  Every consumer (audit, corpus, calibrate, figures, tables, render, report) iterates
:func:`names` or :func:`specs`, in registration order.
"""

from __future__ import annotations

import os
import threading
import warnings
from importlib.metadata import EntryPoint, entry_points

from silcount.detectors.spec import DetectorSpec
from silcount.errors import BadArgument, check_choice

GROUP = "silcount.detectors"
_QUIET = "SILCOUNT_PLUGINS_WARNED"  # set once the warnings are shown: worker processes do not repeat them

_SPECS: dict[str, DetectorSpec] = {}
_SOURCES: dict[str, str] = {}  # name -> "built-in" or the plug-in's entry point
_FAILED: dict[str, str] = {}  # entry point name -> why it was left out
_LOCK = threading.RLock()
_state = {"discovered": False}


class PluginWarning(UserWarning):
    """A detector plug-in was left out; the message names it and says why."""


def register_detector(spec: DetectorSpec, *, source: str = "registered") -> None:
    """Add ``spec`` to the registry (after the built-ins and installed plug-ins, which are found first).

    Raises :class:`~silcount.errors.BadArgument` if ``spec`` is not a :class:`DetectorSpec` or its name is
    taken.  ``source`` says where it came from in messages.
    """
    with _LOCK:
        _discover()
        try:
            _add(spec, source)
        except BadArgument as exc:
            raise BadArgument(f"register_detector: {exc}") from None


def _add(spec: object, source: str) -> None:
    if not isinstance(spec, DetectorSpec):
        raise BadArgument(f"expected a silcount DetectorSpec, got {type(spec).__name__}")
    if spec.name in _SPECS:
        raise BadArgument(f"the name {spec.name!r} is taken by the {_SOURCES[spec.name]} detector")
    _SPECS[spec.name] = spec
    _SOURCES[spec.name] = source


def _discover() -> None:
    if _state["discovered"]:
        return
    _state["discovered"] = True  # first, so that a plug-in's own register_detector call does not recurse
    from silcount.detectors import builtin

    for spec in builtin.specs():
        _add(spec, "built-in")
    for ep in sorted(entry_points(group=GROUP), key=lambda e: (e.name, e.value)):
        _load(ep)
    if _FAILED:
        os.environ[_QUIET] = "1"  # inherited by the worker processes started later, which stay quiet


def _load(ep: EntryPoint) -> None:
    """Register one entry point's spec, or leave it out with one line naming it."""
    where = f"detector plug-in {ep.name!r} ({ep.value})"
    try:
        spec = ep.load()
        _add(spec, f"plug-in {ep.name!r}")
    except Exception as exc:  # any failure of a third party's code: the plug-in is left out, and said so
        why = str(exc) if isinstance(exc, BadArgument) else f"{type(exc).__name__}: {exc}"
        _FAILED[ep.name] = why
        if not os.environ.get(_QUIET):
            # one line: a warning of its own location, no source line under it
            warnings.warn_explicit(f"{where} left out: {why}", PluginWarning, "silcount", 0)


def names() -> tuple[str, ...]:
    """Every registered detector's name, in registration order (the built-ins first)."""
    with _LOCK:
        _discover()
        return tuple(_SPECS)


def specs() -> tuple[DetectorSpec, ...]:
    """Every registered :class:`DetectorSpec`, in registration order."""
    with _LOCK:
        _discover()
        return tuple(_SPECS.values())


def get(name: str, *, error: type[Exception] = BadArgument, prefix: str = "") -> DetectorSpec:
    """The spec of detector ``name``; ``error`` (one line listing the names) for an unknown one, naming the
    plug-in if it is one that was left out.

    A built-in is answered before the registry fills (a plug-in can never take a built-in's name), so a
    command that asks for built-ins by name imports neither the other detectors nor the plug-ins."""
    from silcount.detectors import builtin

    if name in builtin.MODULES:
        return builtin.spec(name)
    known = names()
    if name not in known and name in _FAILED:
        raise error(f"{prefix}detector {name!r}: its plug-in was left out: {_FAILED[name]}")
    check_choice("detector", name, known, prefix=prefix, error=error)
    return _SPECS[name]


def with_role(role: str) -> tuple[str, ...]:
    """The names of the detectors of ``role`` (:data:`.spec.ROLES`), in registration order."""
    return tuple(s.name for s in specs() if s.role == role)


def source_of(name: str) -> str:
    """Where detector ``name`` came from: ``built-in``, ``plug-in '<entry point>'`` or ``registered``."""
    get(name)
    return _SOURCES[name]


def failed() -> dict[str, str]:
    """The plug-ins left out: entry point name -> why."""
    names()
    return dict(_FAILED)


__all__ = [
    "GROUP",
    "PluginWarning",
    "failed",
    "get",
    "names",
    "register_detector",
    "source_of",
    "specs",
    "with_role",
]
