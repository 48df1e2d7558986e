"""Figures: written, deterministic, and equal to the committed copies."""
from __future__ import annotations

from pathlib import Path

import pytest

from silcount import figures

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    out = tmp_path_factory.mktemp("figures")
    return out / "figures", figures.report(out)


def test_every_figure_in_png_and_svg(generated):
    _, paths = generated
    names = sorted(p.name for p in paths)
    assert names == sorted(f"{stem}.{ext}" for stem in ("operations", "cycles", "growth") for ext in ("png", "svg"))
    assert all(p.stat().st_size > 10_000 for p in paths)


def test_svg_is_deterministic_and_committed(generated):
    out, _ = generated
    for stem in ("operations", "cycles", "growth"):
        svg = (out / f"{stem}.svg").read_text()
        assert "<dc:date>" not in svg
        assert svg == (ROOT / "reports" / "figures" / f"{stem}.svg").read_text(), \
            "reports/figures is stale: run `silcount figures --out reports/figures`"
