"""The small error hierarchy of silcount.

The library raises these; only the CLI turns them into one line on stderr and
an exit code (see ``silcount.cli.main``).  Exit codes are part of the public
contract and documented in the README.
"""

from __future__ import annotations

from collections.abc import Collection


class SilcountError(Exception):
    """Base class. ``exit_code`` is what the CLI exits with."""

    exit_code = 1


class UnreadableInput(SilcountError):
    """The file cannot be read or parsed (missing, a directory, empty, corrupt, unknown format)."""

    exit_code = 3


class UnwritableOutput(SilcountError):
    """An output cannot be written (a folder that cannot be made, a directory in the way, no permission, a full
    disk); see :mod:`silcount.atomic` for the rule every command follows."""

    exit_code = 3


class InvalidMesh(SilcountError):
    """The file parsed, but the geometry cannot be audited (NaN/Inf, bad indices, no faces, too large)."""

    exit_code = 4


class BadArgument(SilcountError):
    """A command-line or API argument is malformed (a light on a face plane, a zero direction, ...)."""

    exit_code = 2


def check_choice(
    what: str,
    value: object,
    choices: Collection[str],
    *,
    prefix: str = "",
    error: type[Exception] = BadArgument,
) -> None:
    """Raise ``error`` (:class:`BadArgument` unless told) if ``value`` is not one of ``choices``.

    The message is ``{prefix}unknown {what} {value!r}; choose from a, b, c``, the choices in their order
    (a dict's keys for a dict).
    """
    if value not in choices:
        raise error(f"{prefix}unknown {what} {value!r}; choose from {', '.join(choices)}")


class TooMuchWork(InvalidMesh):
    """One computation on a mesh would exceed the work limit (``--max-work``, ``$SILCOUNT_MAX_WORK``).

    Raised between chunks of a long compiled loop (:mod:`silcount.mesh.chunks`) once the work done passes the
    limit; ``what`` names the computation.  The audit reports the other detectors and names this one.
    """

    exit_code = 4

    def __init__(self, what: str, done: int, limit: int) -> None:
        self.what, self.done, self.limit = what, done, limit
        super().__init__(
            f"{what}: over {limit:,} elementary tests ({done:,} done when stopped); "
            "set --max-work or $SILCOUNT_MAX_WORK to raise the limit"
        )


class NoOpenGL(SilcountError):
    """The OpenGL frame cannot run here: the ``gl`` extra (moderngl, PyOpenGL) is not installed, no headless EGL
    context opens, or the driver refuses the framebuffer or the shaders (:mod:`silcount.render.opengl`)."""
