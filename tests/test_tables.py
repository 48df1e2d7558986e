"""The tables report: printed cells from the paper text, CSV shape, regeneration."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import pytest

from silcount.cli.main import main
from silcount.papers import tables

ROOT = Path(__file__).resolve().parent.parent

# EESD paper Sec. 6, Tables 1 and 2, copied from the text (Multiple, Add, Compare, Read, Write).
PAPER_TEXT = {
    ("EESD Table 1", "ta"): (150, 80, 3000, 3110, 100),
    ("EESD Table 1", "vnv"): (6000, 5400, 660, 4860, 60),
    ("EESD Table 1", "eesd"): (1980, 2160, 600, 120, 120),
    ("EESD Table 2", "ta"): (2000, 800, 600000, 601800, 2000),
    ("EESD Table 2", "vnv"): (600000, 540000, 60600, 48600, 600),
    ("EESD Table 2", "eesd"): (181800, 183600, 60000, 1200, 1200),
}


def test_printed_cells_are_the_paper_text():
    for (table, algorithm), values in PAPER_TEXT.items():
        got = {c.operation: c.printed for c in tables.cells() if c.table == table and c.algorithm == algorithm}
        assert tuple(int(got[k]) for k in tables.KIND_ORDER) == values


def test_hsd_tables_print_the_closed_form():
    hsd = [c for c in tables.cells() if c.table.startswith("HSD")]
    assert len(hsd) == 30 and all(c.printed == c.printed_form and not c.printed_is_cell for c in hsd)
    # HSD printed sum at n=10: (6n^2+n)C = 610, 11n M = 110 (Sec. 6.3)
    row = {c.operation: c.printed for c in hsd if c.table == "HSD Fig. 5" and c.algorithm == "hsd"}
    assert (row["cmp"], row["mul"]) == ("610", "110")


def test_csv_columns(capsys):
    assert main(["tables", "--format", "csv"]) == 0
    rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    assert rows[0] == ["table", "algorithm", "operation", "printed", "rederived", "measured", "agrees"]
    assert len(rows) == 1 + 60


def test_tex_and_md_render():
    assert "\\begin{tabular}" in tables.render("tex")
    assert "| Triangle Algorithm | Read | **3110** |" in tables.render("md")


@pytest.mark.parametrize("name", ["tables.md", "tables.csv", "tables.tex"])
def test_committed_reports_are_regenerated(tmp_path, name):
    tables.report(tmp_path)
    tmp_path = tmp_path / "tables"
    assert (ROOT / "reports" / "tables" / name).read_text() == (tmp_path / name).read_text(), (
        "reports/tables is stale: run `silcount tables --out reports/tables` (or `silcount report`)"
    )
