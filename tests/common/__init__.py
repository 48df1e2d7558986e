"""The suite's own helpers (as hypothesis keeps its in ``tests/common/``): the CLI run in-process, the skip
when the shared scenes are absent.  Assertions useful beyond this suite are public, in :mod:`silcount.testing`.
"""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

NO_SHARED_SCENES = "shared scenes not found: set SILCOUNT_SCENE_DIR or provide ../shared/scenes"


def run_cli(*argv: str) -> tuple[int, str, str]:
    """``silcount ARGV...`` in this process: its exit code, standard output and standard error."""
    from silcount.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        rc = main(list(argv))
    return rc, out.getvalue(), err.getvalue()


def shared_scenes() -> Path:
    """The shared scenes' folder (:func:`silcount.cli.render.shared_scene_dir`); the test is skipped, saying
    why, when there is none."""
    from silcount.cli.render import shared_scene_dir

    d = shared_scene_dir()
    if d is None:
        pytest.skip(NO_SHARED_SCENES)
    return d


def forget_user_papers() -> None:
    """Drop the model names and papers that earlier tests read from folders of their own (``--paper``),
    so that each test reads its own."""
    from silcount.counting import models
    from silcount.papers import registry

    models._ADDED.clear()
    models.load.cache_clear()
    registry._READ.clear()
