"""What every figure shares: one style and one deterministic writer (PNG and SVG).

``svg.hashsalt`` fixes the SVG ids and the metadata that carries the date or
the matplotlib version is dropped, so regenerated figures are byte-identical.
Files are written through :mod:`silcount.atomic`. matplotlib is imported by
the caller (this module only touches the figure it is handed).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from silcount.atomic import atomic_path

STYLE: dict[str, Any] = {
    "svg.hashsalt": "silcount",
    "font.size": 10,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.axisbelow": True,
}


def save_figure(fig: Any, out_dir: Path, stem: str) -> list[Path]:
    """Write ``fig`` as ``<stem>.png`` and ``<stem>.svg`` under ``out_dir``, close it, return the paths."""
    import matplotlib.pyplot as plt

    paths = []
    for ext, meta in (("png", {"Software": None}), ("svg", {"Date": None, "Creator": None})):
        path = Path(out_dir) / f"{stem}.{ext}"
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=ext, dpi=110, metadata=meta, bbox_inches="tight")
        paths.append(path)
    plt.close(fig)
    return paths
