"""Shared fixtures (the real meshes of ../shared/data, found through SILCOUNT_MESH_DIR) and test settings.

The suite leaves the checkout as it found it: numba's cache goes to
``$NUMBA_CACHE_DIR`` (the Makefile points it into ``.venv``; here a user cache
folder when unset), and hypothesis keeps its example database in a temporary
folder.  Hypothesis profiles: ``ci`` (the default) and ``long`` (10x the
examples, the database kept under the user cache), chosen by
``SILCOUNT_HYPOTHESIS_PROFILE``.  Tests set ``max_examples=examples(n)``
(``strategies.examples``), which is ``n`` under ``ci`` and ``10 n`` under
``long``; the profile's own ``max_examples`` applies to tests that set none.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

os.environ.setdefault("NUMBA_CACHE_DIR", str(Path.home() / ".cache" / "silcount" / "numba"))

import pytest  # noqa: E402
from hypothesis import HealthCheck, settings  # noqa: E402
from hypothesis.database import DirectoryBasedExampleDatabase  # noqa: E402

settings.register_profile(
    "ci",
    database=DirectoryBasedExampleDatabase(tempfile.mkdtemp(prefix="silcount-hypothesis-")),
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "long",
    max_examples=1000,
    suppress_health_check=[HealthCheck.too_slow],
    database=DirectoryBasedExampleDatabase(str(Path.home() / ".cache" / "silcount" / "hypothesis")),
)
settings.load_profile(os.environ.get("SILCOUNT_HYPOTHESIS_PROFILE", "ci"))


def mesh_dir() -> Path | None:
    """``SILCOUNT_MESH_DIR`` made absolute (a relative one is the caller's working directory's)."""
    d = os.environ.get("SILCOUNT_MESH_DIR")
    return Path(d).resolve() if d else None


@pytest.fixture
def shared_mesh():
    """Return a loader for a mesh of ../shared/data, skipping with the reason when it is unavailable."""
    import silcount

    def get(name: str, weld_tolerance: float = 0.0):
        d = mesh_dir()
        if d is None:
            pytest.skip("SILCOUNT_MESH_DIR is unset: the shared real meshes are not available")
        path = d / name
        if not path.exists():
            pytest.skip(f"{path} does not exist")
        return silcount.load_mesh(path, weld_tolerance=weld_tolerance)

    return get


@pytest.fixture(scope="session")
def all_claims():
    """Every claim, judged with the render experiments, as the report judges them (``tests/test_claims_*.py``)."""
    from silcount.papers import claims

    return claims.all_claims(claims.default_evidence())


@pytest.fixture(scope="session")
def by_key(all_claims):
    """The claims by key."""
    return {c.key: c for c in all_claims}
