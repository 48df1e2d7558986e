"""Writing a sweep: ``--out DIR`` files and the ``text``/``md``/``json`` renderings for stdout.

``--out DIR`` receives ``corpus.parquet`` (pyarrow; the rows table of
:mod:`silcount.study.tables`), ``meshes.csv``, ``fits.json``, ``summary.md``
(the summary and fits tables below), when ``gaussmap`` or ``cones`` ran
``literature.md`` (:mod:`silcount.study.literature_page`, linked from
``summary.md``) and the figures of :mod:`silcount.study.figures`, each
written atomically.

The *summary* table has one row per mesh and level: ``file, level, faces,
kind, coplanar_polygons, silhouette_edges_mean, silhouette_edges_std,
error``; the *fits* table one row per fit: ``fit, subset, against`` (the
size ``x`` of ``y ~ c x^alpha``: ``F`` but for the output-sensitivity fits),
``meshes, alpha, alpha_lo, alpha_hi, c``, ``class`` (the complexity class, its Akaike weight and bootstrap
share) and ``runner_up``.  ``text`` and ``md`` print both (every column);
``json`` prints the whole ``silcount-corpus/1`` document.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

from silcount.atomic import atomic_path, make_folder, write_text

if TYPE_CHECKING:
    import pandas as pd

    from silcount.study import CorpusResult

FORMATS = ("text", "md", "json")
SUMMARY = (
    "file",
    "level",
    "faces",
    "kind",
    "coplanar_polygons",
    "silhouette_edges_mean",
    "silhouette_edges_std",
    "error",
)


def summary_frame(meshes: pd.DataFrame) -> pd.DataFrame:
    out = meshes[list(SUMMARY)].copy()
    for col in ("silhouette_edges_mean", "silhouette_edges_std"):
        out[col] = out[col].map(lambda v: "" if v != v or v is None else f"{v:.1f}")
    for col in ("faces", "coplanar_polygons"):
        out[col] = out[col].map(lambda v: "" if v != v or v is None else f"{int(v)}")
    return out.fillna("")


def _class(c: dict | None) -> str:
    """``n^2 (w 0.83, boot 0.59)``: the chosen class, its Akaike weight and its bootstrap share; empty for none."""
    return "" if c is None else f"{c['chosen']} (w {c['weight']:.2f}, boot {c['share']:.2f})"


def _runner_up(c: dict | None) -> str:
    return "" if c is None else f"{c['runner_up']} (w {c['runner_up_weight']:.2f})"


def fits_frame(fits: dict) -> pd.DataFrame:
    import pandas as pd

    def num(v, spec: str) -> str:
        return "" if v is None else format(v, spec)

    return pd.DataFrame.from_records(
        [
            {
                "fit": name,
                "subset": f["subset"],
                "against": f["against"],
                "meshes": f["meshes"],
                "alpha": num(f["alpha"], ".3f"),
                "alpha_lo": num(f["alpha_ci"] and f["alpha_ci"][0], ".3f"),
                "alpha_hi": num(f["alpha_ci"] and f["alpha_ci"][1], ".3f"),
                "c": num(f["c"], ".4g"),
                "class": _class(f.get("classes")),
                "runner_up": _runner_up(f.get("classes")),
            }
            for name, f in fits.items()
        ],
        columns=["fit", "subset", "against", "meshes", "alpha", "alpha_lo", "alpha_hi", "c", "class", "runner_up"],
    )


def missing_lines(detectors: tuple[str, ...]) -> list[str]:
    """One line per detector that lacks a part the sweep uses: its columns are empty (none for the built-ins)."""
    from silcount.detectors import get

    empty = {"paper model": "its paper_ columns are empty", "plain loops": "its time column is empty"}
    return [
        f"detector {name}: no {part}, {empty[part]}"
        for name in detectors
        for part in get(name).missing
        if part in empty
    ]


def render_json(result: CorpusResult) -> str:
    return json.dumps(result.document, indent=2, sort_keys=False) + "\n"


def format_corpus(result: CorpusResult, form: str) -> str:
    """The sweep as ``text``, ``md`` or ``json``."""
    if form == "json":
        return render_json(result)
    summary, fits = summary_frame(result.meshes), fits_frame(result.fits)
    failed = f"{result.failed} of {len(result.meshes)} meshes could not be audited (see error)\n"
    failed += "".join(f"{line}\n" for line in missing_lines(result.settings.detectors))
    md = form == "md"
    head, gap = ("## ", "\n") if md else ("", "")  # markdown: headings, a blank line around each table
    meshes, fits_text = (t.to_markdown(index=False) if md else t.to_string(index=False) for t in (summary, fits))
    return (
        f"{head}Meshes\n{gap}{meshes}\n{gap}{failed}"
        f"\n{head}Fits: y ~ c x^alpha, x = F unless stated (95% bootstrap interval for alpha); class: the complexity "
        "class chosen by AIC, its Akaike weight w and its share of 1000 bootstrap resamples (docs/complexity.md)\n"
        f"{gap}{fits_text}\n"
    )


def write_out(result: CorpusResult, out_dir: Path, with_rows: bool = True) -> list[Path]:
    """Every ``--out`` file under ``out_dir`` (``with_rows=False`` leaves out ``corpus.parquet``)."""
    from silcount.detectors import with_role
    from silcount.study.figures import write_figures
    from silcount.study.literature import kind_frame
    from silcount.study.literature_page import TITLE, page

    make_folder(out_dir)
    paths = []
    if with_rows:
        path = out_dir / "corpus.parquet"
        with atomic_path(path) as tmp:
            result.rows.to_parquet(tmp, engine="pyarrow", index=False)
        paths.append(path)
    paths.append(write_text(out_dir / "meshes.csv", result.meshes.to_csv(index=False)))
    paths.append(write_text(out_dir / "fits.json", json.dumps(result.fits, indent=2) + "\n"))
    frame = kind_frame(result.rows, result.meshes, result.settings)
    with_page = bool(set(with_role("literature")) & set(result.settings.detectors))
    link = f"See [{TITLE}](literature.md).\n\n" if with_page else ""
    paths.append(write_text(out_dir / "summary.md", "# silcount corpus\n\n" + link + format_corpus(result, "md")))
    if with_page:
        text = page(frame, result.fits, result.settings, result.failed)
        paths.append(write_text(out_dir / "literature.md", text))
    runs = [key for key, _, _ in result.settings.runs()]
    return paths + write_figures(result.meshes, result.fits, runs, out_dir, frame if with_page else None)
