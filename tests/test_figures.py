"""Figures: written, deterministic, and equal to the committed copies."""

from __future__ import annotations

from pathlib import Path

import pytest

from silcount.papers import figures

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    out = tmp_path_factory.mktemp("figures")
    return out / "figures", figures.write_all(out / "figures")


def test_report_parts_are_the_figures():
    # `silcount report` names the parts without importing matplotlib; the names must be the writers'
    from silcount.cli import figures as cli_figures

    assert cli_figures.PARTS == tuple(figures.PARTS)


def test_every_figure_in_png_and_svg(generated):
    _, paths = generated
    names = sorted(p.name for p in paths)
    stems = ("operations", "cycles", "growth", "growth_by_kind")
    assert names == sorted([f"{stem}.{ext}" for stem in stems for ext in ("png", "svg")] + ["growth.md"])
    assert all(p.stat().st_size > 10_000 for p in paths if p.suffix != ".md")


def test_svg_is_deterministic_and_committed(generated):
    out, _ = generated
    assert (out / "growth.md").read_text() == (ROOT / "reports" / "figures" / "growth.md").read_text()
    for stem in ("operations", "cycles", "growth", "growth_by_kind"):
        svg = (out / f"{stem}.svg").read_text()
        assert "<dc:date>" not in svg
        assert svg == (ROOT / "reports" / "figures" / f"{stem}.svg").read_text(), (
            "reports/figures is stale: run `silcount figures --out reports/figures`"
        )
