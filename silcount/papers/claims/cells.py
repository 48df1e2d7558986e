"""One claim per printed table cell (EESD paper Sec. 6, Tables 1 and 2).

A cell HOLDS when it is the papers'-convention count of its algorithm at the
table's point (the annotations summed, every condition true, the then-branch
charged); the reason names the flags of :mod:`silcount.papers.tables`
(``typo``: printed differs from the paper's own closed form; ``model``: the
closed form differs from its annotations) and which printed ``=`` moves it.
Measured counts (a named closed mesh near the point) are shown, never judged.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import sympy as sp

from silcount.counting import models
from silcount.papers import formulas as F
from silcount.papers import tables as T
from silcount.papers.claims.base import FAILS, HOLDS, Claim
from silcount.papers.claims.derivations import slip_of

if TYPE_CHECKING:
    from silcount.papers.registry import Paper

KIND_OF = {label: kind for kind, label in T.KIND_LABEL.items()}


def digit_slip(printed: int, value: int) -> str:
    """Name a one-digit slip between two integers (the PDF conversion or a typo), or ''."""
    a, b = str(printed), str(value)
    if len(a) + 1 == len(b) and any(b[:i] + b[i + 1 :] == a for i in range(len(b))):
        return "one digit dropped: likely the PDF-to-text conversion (or typesetting)"
    if len(a) == len(b) and sum(x != y for x, y in zip(a, b)) == 1:
        return "one digit differs: likely a typo in the paper"
    return ""


def _why(model: str, kind: str) -> str:
    causes = [
        f"the printed '{cur}' changes it by {sp.sstr(d[kind])}" for _, cur, d in F.expansion_steps(model) if kind in d
    ]
    conv, first = F.paper_forms(model)["convention"][kind], F.paper_forms(model)["first"][kind]
    if sp.expand(conv - first) != 0:
        causes.append(f"the first printed line leaves out {sp.sstr(sp.factor(conv - first))} of its annotations")
    return "; ".join(causes)


def cell_claims(papers: "tuple[Paper, ...] | None" = None) -> list[Claim]:
    """A claim per printed cell of the tables of ``papers`` (default: the built-ins)."""
    df = T.tables_frame(papers)
    out = []
    for paper_file in T.table_files(papers):
        data = models.load(paper_file)
        for table in data.get("tables", []):
            for row in (r for r in table["rows"] if "cells" in r):
                cells = df[(df["table"] == table["id"]) & (df["algorithm"] == row["label"])]
                for _, c in cells.iterrows():
                    kind = KIND_OF[c["operation"]]
                    printed, closed, conv = int(c["printed"]), int(c["closed_form"]), int(c["convention"])
                    notes = []
                    if c["typo"]:
                        slip = digit_slip(printed, closed)
                        notes.append(
                            f"typo: the paper's own closed form gives {closed}" + (f" ({slip})" if slip else "")
                        )
                    else:
                        notes.append("equals the paper's own closed form")
                    if c["model"]:
                        notes.append(
                            f"model: the closed form differs from its annotations ({_why(row['model'], kind)})"
                        )
                    notes.append(f"tight worst case {c['worst_case']}")
                    out.append(
                        Claim(
                            key=f"{table['id']} {row['algorithm']} {kind}",
                            family="table cell",
                            paper=data["source_file"],
                            section=table["section"],
                            lines=row["lines"],
                            quote=row["quote"],
                            statement=f"{table['id']} ({table['caption']}): {row['label']} needs {printed} "
                            f"{c['operation']}",
                            printed=str(printed),
                            rederived=f"{conv} (convention); closed form {closed}; worst case {c['worst_case']}",
                            measured=f"{c['measured']} (true), {c['measured_paper_model']} (paper cost model) on "
                            f"{c['measured_on']}",
                            verdict=HOLDS if printed == conv else FAILS,
                            reason="; ".join(notes) + ".",
                            # the printed closed form's own slip, not a new one: only a typo is the cell's own
                            follows_from=slip_of(row["model"], kind) if printed != conv and not c["typo"] else "",
                        )
                    )
    return out
