"""Shared fixtures: the real meshes of ../shared/data, found through SILCOUNT_MESH_DIR."""
from __future__ import annotations

import os
from pathlib import Path

import pytest


def mesh_dir() -> Path | None:
    d = os.environ.get("SILCOUNT_MESH_DIR")
    return Path(d) if d else None


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
