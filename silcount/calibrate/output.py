"""Writing a :class:`~silcount.calibrate.calibration.Calibration`: Markdown, CSV, JSON and the figures.

Every float is rounded to 4 significant digits, so the same inputs give the
same bytes; the JSON follows ``docs/schemas/calibrate.schema.json``.  Files, under ``out_dir``:
``calibrate.md``, ``calibrate.csv`` (the summary), ``calibrate_large.csv`` (the
summary over the larger meshes), ``calibrate_meshes.csv``
(per mesh), ``fps.csv``, ``calibrate.json``, ``calibrate_<model>.png`` (one per
cost model), and with ``with_timings`` the raw ``timings.csv`` of a live run.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd

from silcount.atomic import atomic_path, make_folder, write_text
from silcount.calibrate.calibration import LARGE_FACES, Calibration
from silcount.calibrate.timing import LITERATURE, MODELS, TIMED
from silcount.detectors import STYLES

SCHEMA = "silcount-calibrate/1"
DIGITS = 4


def _round(x):
    if isinstance(x, float):
        if math.isnan(x) or math.isinf(x):
            return None
        return float(f"{x:.{DIGITS}g}")
    return x


def rounded(frame: pd.DataFrame) -> pd.DataFrame:
    return frame.map(_round)


def _records(frame: pd.DataFrame) -> list[dict]:
    return [
        {k: (v.item() if hasattr(v, "item") else v) for k, v in row.items()}
        for row in rounded(frame).to_dict("records")
    ]


def to_json(cal: Calibration) -> str:
    doc = {
        "schema": SCHEMA,
        "cpu_model": cal.cpu_model,
        "timings": cal.timings_source,
        "samples": len(cal.samples),
        "summary": _records(cal.summary),
        "large_faces": LARGE_FACES,
        "summary_large": _records(cal.summary_large),
        "per_mesh": _records(cal.per_mesh),
        "fps": _records(cal.fps),
        "left_out": list(cal.left_out),
        "within": _records(cal.within),
        "within_large": _records(cal.within_large),
        "literature": {
            "detectors": sorted(set(cal.literature_samples["detector"]), key=TIMED.index),
            "samples": len(cal.literature_samples),
            "summary": _records(cal.literature),
            "per_mesh": _records(cal.literature_meshes),
        },
    }
    return json.dumps(doc, indent=2, sort_keys=False) + "\n"


def to_markdown(cal: Calibration) -> str:
    best = cal.summary.sort_values(["r2", "profile"], ascending=[False, True], kind="stable").iloc[0]
    lines = [
        "# Do the counts predict time?",
        "",
        f"Timings: `{cal.timings_source}` ({cal.cpu_model}), {len(cal.samples)} samples "
        "(mesh x algorithm x light), time of each algorithm's compiled uncounted loops "
        "(each detector module's `plain_edge_ids`), "
        "best of the repeats. Predicted time = tally x profile x one scale per (model, profile), fitted in log space.",
        "",
        f"Best fit: model `{best['model']}`, profile `{best['profile']}`, R^2 = {_round(float(best['r2']))}.",
        "",
        *(
            [f"Left out (the timed file loads today as another mesh): {'; '.join(cal.left_out)}.", ""]
            if cal.left_out
            else []
        ),
        "## Per cost model and profile",
        "",
        rounded(cal.summary).to_markdown(index=False),
        "",
        "r2: of log time; ratio: predicted / measured (worst: farthest from 1); rank_rho: Spearman of the "
        "algorithms' order per mesh, mean over meshes; fastest_agree: meshes whose predicted fastest is the "
        "measured fastest.",
        "",
        f"## Meshes of at least {LARGE_FACES} faces only (refitted)",
        "",
        "Below that size a call's fixed cost (the numpy set-up of `plain_edge_ids`), which no per-operation weight "
        "can model, is a large share of its time.",
        "",
        rounded(cal.summary_large).to_markdown(index=False),
        "",
        "Within each algorithm (see the next section), with this refit:",
        "",
        within_table(cal.within_large).to_markdown(index=False),
        "",
        "## Within each algorithm (the first fit, each algorithm's own samples)",
        "",
        "R^2 of log time over one algorithm's samples with the scale fitted on all four: a fit across the "
        "algorithms can explain most of the spread of log time by the gaps between them and still predict one "
        "algorithm's time from mesh to mesh poorly (negative: worse than that algorithm's own mean time).",
        "",
        within_table(cal.within).to_markdown(index=False),
        "",
        "## Per mesh",
        "",
        rounded(cal.per_mesh).to_markdown(index=False),
        "",
        "## The papers' FPS against their own model (the HSD paper's P IV 2.8 GHz and bunny, 2207 edges; the "
        "EESD paper, whose TA, VnV and EESD rates these are, names no machine or mesh)",
        "",
        rounded(cal.fps).to_markdown(index=False),
        "",
        "detect_ms: the paper's printed closed form, paper cycles, at 2.8e9 cycles/s; frame_ms = 1000 / FPS.",
        "",
        *_literature_lines(cal),
    ]
    return "\n".join(lines)


def within_table(within: pd.DataFrame) -> pd.DataFrame:
    """R^2 within each algorithm's samples, one row per (model, profile), one column per algorithm."""
    if within.empty:
        return pd.DataFrame(columns=["model", "profile"])
    wide = within.pivot_table(index=["model", "profile"], columns="detector", values="r2", sort=False, dropna=False)
    order = [d for d in TIMED if d in wide.columns]
    return rounded(wide[order].rename(columns=lambda d: f"r2 {d}").reset_index())


def _literature_lines(cal: Calibration) -> list[str]:
    """The literature's detectors, predicted with the papers' four's scales (not refitted)."""
    head = ["## The literature's hierarchies (gaussmap, cones), predicted with the four's fit", ""]
    if not len(cal.literature_samples):
        return head + ["These timings do not time them: `silcount calibrate` (a live run) does.", ""]
    return head + [
        f"{len(cal.literature_samples)} samples (mesh x detector x light). Time: each light's query, the fast "
        "engine's compiled traversal of the tree cached with the mesh (`hierarchy_query.query_fast`, one thread; "
        "the tree is built before the clock starts), the ids sorted; tally: the query's (the build is apart). "
        "Predicted = tally x profile x the scale fitted above on the papers' four algorithms (all meshes), "
        "not refitted.",
        "",
        rounded(cal.literature).to_markdown(index=False),
        "",
        "r2: of log time with the four's scale (negative: worse than the detector's own mean); ratio: predicted / "
        "measured (worst: farthest from 1).",
        "",
        "### Measured seconds per mesh (summed over the lights), every timed detector",
        "",
        rounded(cal.literature_meshes).to_markdown(index=False),
        "",
    ]


def figure(cal: Calibration, model: str, path: Path) -> Path:
    """Predicted against measured time, one panel per profile, algorithms coloured (log-log)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = {name: colour for name, (colour, _) in STYLES.items()}  # the literature (x): the four's scale, not fitted
    lit = cal.literature_predictions
    pred = pd.concat([cal.predictions, lit]) if len(lit) else cal.predictions
    pred = pred[pred["model"] == model]
    profiles = list(dict.fromkeys(pred["profile"]))
    cols = 3
    rows = math.ceil(len(profiles) / cols)
    with plt.rc_context({"svg.hashsalt": "silcount", "font.size": 9}):
        fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 3.6 * rows), squeeze=False)
        lo, hi = pred[["seconds", "predicted"]].min().min() / 2, pred[["seconds", "predicted"]].max().max() * 2
        for ax, prof in zip(axes.flat, profiles):
            sub = pred[pred["profile"] == prof]
            for det, colour in colours.items():
                d = sub[sub["detector"] == det]
                if len(d):
                    fitted = det not in LITERATURE
                    ax.scatter(d["seconds"], d["predicted"], s=12, color=colour, marker="o" if fitted else "x",
                               label=det if fitted else f"{det} (not fitted)")  # fmt: skip
            ax.plot([lo, hi], [lo, hi], color="#888888", lw=0.8)
            r2 = cal.summary[(cal.summary["model"] == model) & (cal.summary["profile"] == prof)]["r2"].iloc[0]
            ax.set(xscale="log", yscale="log", xlim=(lo, hi), ylim=(lo, hi), title=f"{prof}\nR^2 {r2:.3f}")
            ax.set_xlabel("measured s")
            ax.set_ylabel("predicted s")
            ax.minorticks_off()  # log minor ticks over ~6 decades dominate the drawing time
            ax.grid(alpha=0.3)
        for ax in list(axes.flat)[len(profiles) :]:
            ax.axis("off")
        axes.flat[0].legend(loc="upper left", fontsize=8)
        fig.suptitle(f"cost model '{model}': predicted vs measured detection time ({cal.cpu_model})")
        fig.tight_layout()
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format="png", dpi=90, metadata={"Software": None})
        plt.close(fig)
    return path


def write(cal: Calibration, out_dir: Path, with_timings: bool = False, figures: bool = True) -> list[Path]:
    """Write every file of the calibration (the figures unless ``figures`` is false) under ``out_dir``."""
    make_folder(out_dir)
    paths = [
        write_text(out_dir / "calibrate.md", to_markdown(cal)),
        write_text(out_dir / "calibrate.csv", rounded(cal.summary).to_csv(index=False)),
        write_text(out_dir / "calibrate_large.csv", rounded(cal.summary_large).to_csv(index=False)),
        write_text(out_dir / "calibrate_meshes.csv", rounded(cal.per_mesh).to_csv(index=False)),
        write_text(out_dir / "fps.csv", rounded(cal.fps).to_csv(index=False)),
        write_text(out_dir / "calibrate.json", to_json(cal)),
    ]
    if figures:
        paths += [figure(cal, model, out_dir / f"calibrate_{model}.png") for model in MODELS]
    if with_timings:
        every = pd.concat([cal.samples, cal.literature_samples]) if len(cal.literature_samples) else cal.samples
        times = every[["mesh", "faces", "detector", "light", "seconds"]].copy()
        times.insert(0, "cpu_model", cal.cpu_model)
        paths.append(write_text(out_dir / "timings.csv", times.to_csv(index=False)))
    return paths
