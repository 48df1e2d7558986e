"""The papers' figures, redrawn: operations by kind, cycle totals, growth.

* ``operations``: operations by kind per algorithm at the tables' points
  (EESD paper Figs. 7 and 8, HSD paper Figs. 5 and 6), as printed (the
  papers' closed forms) and as corrected (per-line costs x loop structure with
  corrected per-line costs; :mod:`silcount.papers.formulas`);
* ``cycles``: cycle-weighted totals per algorithm (EESD paper Fig. 9) for
  each cycle profile (:mod:`silcount.counting.cycles`), printed vs corrected;
* ``growth``: measured tallies vs faces, log-log, with fitted exponents and
  complexity classes (:mod:`silcount.papers.growth`, :mod:`silcount.study.classes`).

PNG and SVG via matplotlib's Agg backend, with fixed metadata and
``svg.hashsalt`` so regenerated files are byte-identical.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from silcount.atomic import make_folder, write_text  # noqa: E402
from silcount.counting.cycles import builtin_profiles  # noqa: E402
from silcount.detectors import get, names, with_role  # noqa: E402
from silcount.papers import formulas as F  # noqa: E402
from silcount.papers import growth as sweep  # noqa: E402
from silcount.plots import STYLE, save_figure  # noqa: E402
from silcount.study.classes import choose  # noqa: E402

if TYPE_CHECKING:
    from silcount.papers.registry import Paper

POINTS = ({"n": 10, "m": 5}, {"n": 100, "m": 10})
KINDS = (("mul", "Mult"), ("add", "Add"), ("cmp", "Compare"), ("read", "Read"), ("write", "Write"))
COLOURS = {"TA": "#1b6ca8", "VnV": "#d1495b", "EESD": "#2e933c", "HSD": "#edae49", "reference": "#555555",
           "Gauss map": "#7b3294", "normal cones": "#00a6a6"}  # fmt: skip


def _value(model: str, which: str, point: dict) -> dict[str, float]:
    return {k: float(x) for k, x in F.evaluate(F.forms(model)[which], **point).items()}


def algorithms(papers: "tuple[Paper, ...] | None" = None) -> tuple[tuple[str, str], ...]:
    """``(label, model)`` of the algorithms the figures draw: each paper's ``figures`` (default: the built-ins)."""
    from silcount.papers import registry

    return tuple(f for p in (registry.builtin() if papers is None else papers) for f in p.figures)


def _algorithm_colour(name: str, i: int) -> str:
    """A paper algorithm's colour: :data:`COLOURS` by its label, else matplotlib's i-th."""
    return COLOURS.get(name, f"C{i}")


def operations(out_dir: Path, papers: "tuple[Paper, ...] | None" = None) -> list[Path]:
    """Operations by kind per algorithm, printed vs corrected, at each table point (log scale)."""
    algos = algorithms(papers)
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), sharey="row")
    width = 0.8 / len(algos)
    x = np.arange(len(KINDS))
    for row, point in enumerate(POINTS):
        for col, (which, title) in enumerate((("printed", "as printed"), ("corrected", "corrected"))):
            ax = axes[row, col]
            for i, (name, model) in enumerate(algos):
                vals = _value(model, which, point)
                heights = [max(vals[k], 0.5) for k, _ in KINDS]
                ax.bar(
                    x + (i - (len(algos) - 1) / 2) * width, heights, width, label=name, color=_algorithm_colour(name, i)
                )
            ax.set_yscale("log")
            ax.set_xticks(x, [label for _, label in KINDS])
            ax.set_title(f"n = {point['n']}, m = {point['m']}: {title}")
            if col == 0:
                ax.set_ylabel("operations (count, log scale)")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.suptitle(
        "Operations by kind per algorithm: the papers' closed forms vs the corrected re-derivation\n"
        "(a zero count is drawn at 0.5)"
    )
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    fig.legend(
        handles,
        labels,
        title="algorithm",
        ncols=len(algos),
        loc="upper center",
        bbox_to_anchor=(0.5, 0.935),
        fontsize=9,
    )
    return save_figure(fig, out_dir, "operations")


CYCLE_PANELS = ("paper", "unit", "skylake-latency", "znver3-latency")


def cycles(out_dir: Path, papers: "tuple[Paper, ...] | None" = None) -> list[Path]:
    """Cycle-weighted totals per algorithm, printed vs corrected, for the paper's profile and CPU models.

    The latency profiles only (throughput and measured ones are in ``reports/calibrate/``), so that each
    panel stays readable.
    """
    algos = algorithms(papers)
    profiles = {k: v for k, v in builtin_profiles().items() if k in CYCLE_PANELS}
    fig, axes = plt.subplots(len(POINTS), len(profiles), figsize=(2.9 * len(profiles) + 1, 6.5))
    names = [name for name, _ in algos]
    x = np.arange(len(names))
    for row, point in enumerate(POINTS):
        for col, (pname, prof) in enumerate(profiles.items()):
            ax = axes[row, col]
            for j, (which, hatch) in enumerate((("printed", ""), ("corrected", "//"))):
                tot = [prof.cycles(_value(model, which, point)) for _, model in algos]
                ax.bar(
                    x + (j - 0.5) * 0.4,
                    tot,
                    0.4,
                    color=[_algorithm_colour(n, i) for i, n in enumerate(names)],
                    hatch=hatch,
                    edgecolor="black",
                    linewidth=0.5,
                    label=which,
                )
            ax.set_xticks(x, names)
            ax.set_yscale("log")
            ax.set_title(f"{pname}\nn = {point['n']}, m = {point['m']}", fontsize=9)
            if col == 0:
                ax.set_ylabel("cycles (log scale)")
    handles = [plt.Rectangle((0, 0), 1, 1, facecolor="white", edgecolor="black", hatch=h) for h in ("", "//")]
    fig.legend(handles, ["as printed", "corrected"], loc="upper right", ncols=2)
    fig.suptitle("Cycle-weighted totals per algorithm and cycle profile", x=0.4)
    fig.tight_layout()
    return save_figure(fig, out_dir, "cycles")


def _line(det: str) -> str:
    """HSD dashed (it overlays TA), the literature's hierarchies dash-dotted, the others solid."""
    return "--" if det == "hsd" else "-." if det in with_role("literature") else "-"


def _colour(det: str) -> str:
    """Detector ``det``'s colour in these figures: :data:`COLOURS` by its label, else its spec's own."""
    spec = get(det)
    return COLOURS.get(spec.label, spec.style[0])


def growth(out_dir: Path, runs: tuple[sweep.Run, ...] | None = None) -> list[Path]:
    """Measured total operations vs faces (icosphere sweep), log-log, with fitted exponents and classes."""
    runs = sweep.sweep(with_real=False) if runs is None else runs
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8), sharey=True)
    apart = 0.0  # HSD against TA, the largest relative difference of their totals
    for ax, model in zip(axes, ("paper", "true")):
        faces_all = []
        by_det: dict[str, list[float]] = {}
        for det in names():
            series = sorted(
                (r for r in runs if r.detector == det and not r.error and r.mesh in sweep.SWEEP_MESHES),
                key=lambda r: r.faces,
            )
            if not series or any(model not in r.tally for r in series):  # no such cost model: no line
                continue
            faces = [r.faces for r in series]
            totals = [sum(r.tally[model].values()) for r in series]
            b, c = sweep.fit_exponent(faces, totals), choose(faces, totals)
            faces_all += faces
            by_det[det] = [float(t) for t in totals]
            ax.plot(
                faces,
                totals,
                marker="o",
                color=_colour(det),
                label=f"{get(det).label}: F^{b:.2f}, {c.chosen} (w {c.weight:.2f})"
                + (" (~ TA)" if det == "hsd" else ""),
                linestyle=_line(det),
            )
        if "hsd" in by_det and "ta" in by_det and len(by_det["hsd"]) == len(by_det["ta"]):
            ta, hsd = np.array(by_det["ta"], dtype=float), np.array(by_det["hsd"], dtype=float)
            apart = max(apart, float(np.max(np.abs(hsd - ta) / ta)))
        f = np.array(sorted(set(faces_all)), dtype=float)
        if f.size:
            ax.plot(f, 10 * f**2, "k:", label="10 F^2 (the papers' O(n^2))")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("faces F (icosphere0 to icosphere4)")
        ax.set_title(f"'{model}' cost model")
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncols=2)  # below the axis label
    axes[0].set_ylabel("operations per silhouette query (all kinds)")
    fig.suptitle(
        "Measured growth of operation counts (fast engine, one point light); legend: fitted exponent, class by AIC "
        "(Akaike weight)\n"
        f"HSD within {apart:.1%} of TA here: icospheres have no coplanar neighbours to merge\n"
        "Gauss map and normal cones: the query, without the tree's build"
    )
    fig.tight_layout()
    return save_figure(fig, out_dir, "growth")


def growth_by_kind(out_dir: Path, runs: tuple[sweep.Run, ...] | None = None) -> list[Path]:
    """Measured tallies per operation kind vs faces, log-log, one panel per kind and cost model."""
    runs = sweep.sweep(with_real=False) if runs is None else runs
    kinds = [k for k, _ in KINDS]
    fig, axes = plt.subplots(2, len(kinds), figsize=(15, 6.5), sharex=True)
    exps = sweep.exponents(runs)
    for row, model in enumerate(("paper", "true")):
        for col, (kind, kind_label) in enumerate(KINDS):
            ax = axes[row, col]
            for det in names():
                series = sorted(
                    (r for r in runs if r.detector == det and not r.error and r.mesh in sweep.SWEEP_MESHES),
                    key=lambda r: r.faces,
                )
                pts = [(r.faces, r.tally[model][kind]) for r in series if r.tally.get(model, {}).get(kind, 0) > 0]
                if not pts:
                    continue
                b = exps[(det, model, kind)]
                ax.plot(
                    *zip(*pts),
                    marker="o",
                    markersize=3,
                    color=_colour(det),
                    linestyle=_line(det),
                    label=f"{get(det).label} {b:.2f}",
                )
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_title(f"{kind_label} ('{model}' model)", fontsize=9)
            ax.legend(fontsize=7, title="exponent", title_fontsize=7, loc="upper left")  # where "best" put every one
            if row == 1:
                ax.set_xlabel("faces F")
            if col == 0:
                ax.set_ylabel("count per query")
    fig.suptitle(
        "Measured operation counts by kind vs faces "
        "(icosphere sweep, log-log; legend: fitted exponent b in count ~ F^b)"
    )
    fig.tight_layout()
    return save_figure(fig, out_dir, "growth_by_kind")


def exponent_table(runs: tuple[sweep.Run, ...] | None = None) -> str:
    """The fitted exponents as a markdown table (written beside the growth plots)."""
    runs = sweep.sweep(with_real=False) if runs is None else runs
    exps = sweep.exponents(runs)
    lines = [
        "# Measured growth: fitted exponent b in count ~ F^b",
        "",
        "Fast engine, the detectors' measured variants (each detector spec's `growth_variant`), one point light, "
        f"meshes {', '.join(sweep.SWEEP_MESHES)}. The papers claim O(n^2) with n = faces. '-' = no nonzero count. "
        "gaussmap and cones: the query's counts, without the tree's build (their `notes['build']`).",
        "",
        "| detector | cost model | " + " | ".join(label for _, label in KINDS) + " |",
        "|---|---|" + "---:|" * len(KINDS),
    ]
    dets = names()
    for det in dets:
        for model in ("paper", "true"):
            if (det, model, KINDS[0][0]) not in exps:  # the detector has no such cost model: empty cells
                lines.append(f"| {det} | {model} |" + " |" * len(KINDS))
                continue
            vals = [exps.get((det, model, k)) for k, _ in KINDS]
            lines.append(f"| {det} | {model} | " + " | ".join("-" if v is None else f"{v:.2f}" for v in vals) + " |")
    no_paper = [det for det in dets if get(det).paper_model is None]
    lines += ["", *(f"{det}: no paper cost model, its paper row is empty." for det in no_paper)] if no_paper else []
    lines += ["", *class_table(runs)]
    lines += [
        "",
        "| mesh | faces | " + " | ".join(f"{d} true total" for d in dets) + " |",
        "|---|---:|" + "---:|" * len(dets),
    ]
    for mesh in sweep.SWEEP_MESHES:
        row = {r.detector: r for r in runs if r.mesh == mesh}
        faces = next(iter(row.values())).faces
        lines.append(
            f"| {mesh} | {faces} | "
            + " | ".join(
                str(sum(row[d].tally["true"].values())) if d in row and not row[d].error else "-" for d in dets
            )
            + " |"
        )
    return "\n".join(lines) + "\n"


def class_table(runs: tuple[sweep.Run, ...]) -> list[str]:
    """The total operations' complexity class beside their exponent, per detector and cost model (markdown lines)."""
    lines = [
        "## Complexity class of the total operations",
        "",
        "Each class cost = a g(n) of 1, log n, sqrt n, n, n log n, n^1.5, n^2, n^2 log n, n^3 (n = F) fitted on "
        "log cost, chosen by AIC; w: its Akaike weight; bootstrap: the share of 1000 resamples of the "
        f"{len(sweep.SWEEP_MESHES)} meshes choosing it (docs/complexity.md). Five sizes over 2.4 decades: the class "
        "is the single term closest over this range, not an asymptote (TA's total mixes terms in n and n^2).",
        "",
        "| detector | cost model | exponent b | class | w | bootstrap | runner-up | its w |",
        "|---|---|---:|---|---:|---:|---|---:|",
    ]
    for det in names():
        series = sorted((r for r in runs if r.detector == det and r.mesh in sweep.SWEEP_MESHES), key=lambda r: r.faces)
        for model in ("paper", "true"):
            if not series or any(model not in r.tally for r in series):  # no such cost model: no row
                continue
            faces, totals = [r.faces for r in series], [sum(r.tally[model].values()) for r in series]
            b, c = sweep.fit_exponent(faces, totals), choose(faces, totals)
            lines.append(
                f"| {det} | {model} | {b:.2f} | {c.chosen} | {c.weight:.2f} | {c.share:.2f} | "
                f"{c.runner_up} | {c.runner_up_weight:.2f} |"
            )
    return lines


def _growth_table(out_dir: Path) -> list[Path]:
    table = out_dir / "growth.md"
    write_text(table, exponent_table())
    return [table]


# Each writes its own files only, so `silcount report` runs them in parallel (dearest first).
PARTS: dict[str, Callable[[Path], list[Path]]] = {
    "growth_by_kind": growth_by_kind,
    "operations": operations,
    "cycles": cycles,
    "growth": growth,
    "growth_table": _growth_table,
}


def write_part(out_dir: Path, name: str) -> list[Path]:
    """Write figure ``name`` of :data:`PARTS` (PNG and SVG, or the growth table) into ``out_dir``."""
    out_dir = Path(out_dir)
    make_folder(out_dir)
    with plt.rc_context(STYLE):  # type: ignore[arg-type]
        return PARTS[name](out_dir)


def report(out_dir: Path, name: str) -> list[Path]:
    """Figure ``name`` of :data:`PARTS` under ``<out_dir>/figures/`` (a part of `silcount report`)."""
    return write_part(Path(out_dir) / "figures", name)


def write_all(out_dir: Path) -> list[Path]:
    """Write every figure (PNG and SVG) and the growth table into ``out_dir``."""
    return [path for name in PARTS for path in write_part(out_dir, name)]


def write_papers(out_dir: Path, papers: "tuple[Paper, ...]") -> list[Path]:
    """The figures drawn from ``papers``' own algorithms (operations and cycles), into ``out_dir``; none when
    they name no algorithm for their figures (the measured growth plots are silcount's, drawn by :func:`write_all`)."""
    if not algorithms(papers):
        return []
    out_dir = Path(out_dir)
    make_folder(out_dir)
    with plt.rc_context(STYLE):  # type: ignore[arg-type]
        return operations(out_dir, papers) + cycles(out_dir, papers)
