"""The papers' operation-count tables, one pandas DataFrame: printed, closed form, convention, worst case, measured.

EESD paper Sec. 6, Tables 1 and 2 (n=10, m=5; n=100, m=10), and the HSD
paper's Figs. 5 and 6 at the same points (charts lost in the PDF conversion:
no printed numbers, so their ``printed`` is empty).  Columns per cell
(operation kind, algorithm, reading):

* ``printed``: the table cell as printed (empty where the paper prints none);
* ``closed_form``: the paper's own last closed-form line evaluated at the point;
* ``convention``: the papers' convention, every condition true and the
  then-branch charged (:func:`silcount.papers.formulas.convention`);
* ``worst_case``: every conditional at its dearest arm (:func:`~silcount.papers.formulas.worst_case`);
* ``measured``, ``measured_paper_model``, ``measured_on``: the detector's true
  tally and its ``paper`` cost model on a named closed mesh near the point
  (:func:`silcount.papers.growth.table_mesh`).  No closed mesh has the table's
  n and m (see there): these are evidence of scale, never a verdict;
* ``typo``: printed differs from the paper's own closed form;
* ``model``: the closed form differs from its annotations (the convention).

``reading`` names the loop-bound reading (HSD: "decreased by 1"); rows of a
model with one reading leave it empty.  Every format carries every column.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

from silcount.atomic import make_folder, write_text
from silcount.counting import models

if TYPE_CHECKING:
    import pandas as pd

TABLE_FILES = ("eesd2012-paper", "hsd2011-paper")
KIND_ORDER = ("mul", "add", "cmp", "read", "write")
KIND_LABEL = {"mul": "Multiple", "add": "Add", "cmp": "Compare", "read": "Read", "write": "Write"}
FORMATS = ("md", "csv", "tex")
COLUMNS = (
    "table",
    "paper",
    "where",
    "n",
    "m",
    "algorithm",
    "reading",
    "operation",
    "printed",
    "closed_form",
    "convention",
    "worst_case",
    "measured",
    "measured_paper_model",
    "measured_on",
    "typo",
    "model",
)


@cache
def _measured(detector: str, n: int, m: float):
    from silcount.papers import growth

    return growth.run(detector, growth.table_mesh(n, m))


def _int(x) -> int:
    import sympy as sp

    value = sp.nsimplify(x)
    if not value.is_Integer:
        raise ValueError(f"a table value is not an integer: {value}")
    return int(value)


@cache
def _rows() -> tuple[dict, ...]:
    from silcount.papers import formulas as F

    out = []
    for paper_file in TABLE_FILES:
        data = models.load(paper_file)
        for table in data.get("tables", []):
            point = table["point"]
            for row in table["rows"]:
                run = _measured(row["algorithm"], point["n"], point["m"])
                where = f"Sec. {table['section']}" + (f", lines {row['lines']}" if "lines" in row else "")
                for reading in F.readings(row["model"]):
                    pf = F.paper_forms(row["model"], reading)
                    values = {which: F.evaluate(pf[which], **point) for which in ("printed", "convention", "worst")}
                    for kind in KIND_ORDER:
                        printed = row["cells"][kind] if "cells" in row else None
                        closed = _int(values["printed"][kind])
                        conv = _int(values["convention"][kind])
                        out.append(
                            {
                                "table": table["id"],
                                "paper": data["source_file"],
                                "where": where,
                                "n": point["n"],
                                "m": point["m"],
                                "algorithm": row["label"],
                                "reading": reading,
                                "operation": KIND_LABEL[kind],
                                "printed": printed,
                                "closed_form": closed,
                                "convention": conv,
                                "worst_case": _int(values["worst"][kind]),
                                "measured": run.tally["true"][kind],
                                "measured_paper_model": run.tally["paper"][kind],
                                "measured_on": f"{run.mesh} (F={run.faces}, E={run.edges}, m={run.mean_sides:.2f}; "
                                f"{run.detector} {run.variant}, fast engine, one point light)",
                                "typo": printed is not None and printed != closed,
                                "model": closed != conv,
                            }
                        )
    return tuple(out)


def tables_frame() -> "pd.DataFrame":
    """Every cell of every table (and every reading), in the papers' order, with the columns of :data:`COLUMNS`."""
    import pandas as pd

    df = pd.DataFrame(list(_rows()), columns=list(COLUMNS))
    df["printed"] = df["printed"].astype("Int64")
    return df


def _text_frame(df: "pd.DataFrame") -> "pd.DataFrame":
    out = df.astype(object).where(df.notna(), "-")
    for col in ("typo", "model"):
        out[col] = df[col].map({True: "yes", False: "no"})
    return out


def render_csv(df: "pd.DataFrame | None" = None) -> str:
    df = tables_frame() if df is None else df
    return df.to_csv(index=False, lineterminator="\n", na_rep="")


def render_md(df: "pd.DataFrame | None" = None) -> str:
    df = tables_frame() if df is None else df
    text = _text_frame(df)
    lines = [
        "# The papers' operation-count tables",
        "",
        "Generated by `silcount tables` (`silcount.papers.tables`). Per cell: *printed* (empty: the paper prints no "
        "number), the paper's own *closed form* evaluated, the papers' *convention* (every condition true, the "
        "then-branch charged), the tight *worst case* (every conditional at its dearest arm), and *measured* counts "
        "on the named closed mesh (never at the table's n and m: no closed mesh has them). Flags: *typo* = printed "
        "differs from the closed form; *model* = the closed form differs from its annotations (the convention).",
        "",
    ]
    for table in dict.fromkeys(df["table"]):
        part = text[df["table"] == table]
        lines += [f"## {table}", "", part.to_markdown(index=False, disable_numparse=True), ""]
    return "\n".join(lines)


def render_tex(df: "pd.DataFrame | None" = None) -> str:
    df = tables_frame() if df is None else df
    styler = _text_frame(df).style.hide(axis="index").format(escape="latex")
    body = styler.to_latex(hrules=True, column_format="l" * len(df.columns))
    return "% Generated by `silcount tables --format tex` (silcount.papers.tables): every column, every cell.\n" + body


RENDER = {"md": render_md, "csv": render_csv, "tex": render_tex}


def format_tables(fmt: str) -> str:
    return RENDER[fmt]()


def report(out_dir: Path) -> list[Path]:
    """The committed outputs: ``<out_dir>/tables/tables.{md,csv,tex}``."""
    return write_all(Path(out_dir) / "tables")


def write_all(out_dir: Path) -> list[Path]:
    """Write ``tables.md``, ``tables.csv`` and ``tables.tex`` into ``out_dir``, all from one frame."""
    out_dir = Path(out_dir)
    make_folder(out_dir)
    df = tables_frame()
    return [write_text(out_dir / f"tables.{fmt}", RENDER[fmt](df)) for fmt in FORMATS]
