"""The tables report: one DataFrame, printed cells from the paper text, flags by hand, three formats, regeneration."""

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
    ("EESD Table 1", "Triangle Algorithm"): (150, 80, 3000, 3110, 100),
    ("EESD Table 1", "Visible-non visible Algorithm"): (6000, 5400, 660, 4860, 60),
    ("EESD Table 1", "Extended Edge Algorithm"): (1980, 2160, 600, 120, 120),
    ("EESD Table 2", "Triangle Algorithm"): (2000, 800, 600000, 601800, 2000),
    ("EESD Table 2", "Visible-non visible Algorithm"): (600000, 540000, 60600, 48600, 600),
    ("EESD Table 2", "Extended Edge Algorithm"): (181800, 183600, 60000, 1200, 1200),
}
ORDER = ("Multiple", "Add", "Compare", "Read", "Write")


@pytest.fixture(scope="module")
def df():
    return tables.tables_frame()


def test_printed_cells_are_the_paper_text(df):
    for (table, algorithm), values in PAPER_TEXT.items():
        rows = df[(df["table"] == table) & (df["algorithm"] == algorithm)].set_index("operation")
        assert tuple(int(rows.loc[k, "printed"]) for k in ORDER) == values


def test_flags_by_hand(df):
    def cell(table, algorithm, op):
        return df[(df["table"] == table) & (df["algorithm"] == algorithm) & (df["operation"] == op)].iloc[0]

    ta_read = cell("EESD Table 1", "Triangle Algorithm", "Read")  # 6n^2m + mn + 8n = 3130 vs printed 3110
    assert (ta_read["closed_form"], ta_read["typo"], ta_read["model"]) == (3130, True, False)
    ta_cmp = cell("EESD Table 1", "Triangle Algorithm", "Compare")  # n(1 + 6nm) = 3010; the closed form 3000
    assert (ta_cmp["closed_form"], ta_cmp["convention"], ta_cmp["typo"], ta_cmp["model"]) == (3000, 3010, False, True)
    eesd_add = cell("EESD Table 2", "Extended Edge Algorithm", "Add")  # 36n + 24n^2 = 243600
    assert (eesd_add["convention"], eesd_add["model"]) == (243600, True)


def test_hsd_rows_print_nothing_and_carry_both_readings(df):
    hsd = df[df["table"].str.startswith("HSD")]
    assert hsd["printed"].isna().all()
    rows = hsd[(hsd["table"] == "HSD Fig. 5") & (hsd["algorithm"] == "HSD")]
    assert len(rows) == 10 and rows["reading"].nunique() == 2
    # HSD Sec. 6.3 printed sum at n=10: (6n^2+n)C = 610 with one side; m - 1 = 4 sides: n(1 + 4 * 6n) = 2410
    cmp = rows[rows["operation"] == "Compare"].set_index("reading")["convention"]
    assert sorted(cmp.tolist()) == [610, 2410]
    # the HSD paper's add (1W+1R+2W) is dearer than the charged delete: worst case 3 writes per side
    w = hsd[(hsd["table"] == "HSD Fig. 5") & (hsd["algorithm"] == "TA") & (hsd["operation"] == "Write")]
    assert w["worst_case"].item() == 3 * 5 * 10


def test_every_format_carries_every_column(capsys):
    assert main(["tables", "--format", "csv"]) == 0
    rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    assert rows[0] == list(tables.COLUMNS) and len(rows) == 1 + 70
    md, tex = tables.format_tables("md"), tables.format_tables("tex")
    assert all(f"| {col}" in md or f"|{col}" in md or f" {col} |" in md for col in tables.COLUMNS)
    header = next(line for line in tex.splitlines() if line.startswith("table &"))
    assert header.count("&") == len(tables.COLUMNS) - 1


@pytest.mark.parametrize("name", ["tables.md", "tables.csv", "tables.tex"])
def test_committed_reports_are_regenerated(tmp_path, name):
    tables.report(tmp_path)
    assert (ROOT / "reports" / "tables" / name).read_text() == (tmp_path / "tables" / name).read_text(), (
        "reports/tables is stale: run silcount.papers.tables.report('reports')"
    )
