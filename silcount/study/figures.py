"""The corpus's figures (PNG and SVG, matplotlib's Agg backend, fixed metadata: byte-identical reruns).

* ``silhouette``: silhouette edges (mean over the lights) against faces,
  log-log, one point per mesh and level coloured by kind (closed, open,
  flat) and shaped by level; the fits over every mesh and over the closed
  ones; McGuire's reported ``0.7 F^0.8`` (JGT 2004) and a convex ``F^0.5``
  line (``c = 1``) for scale.
* ``operations``: total operations per light against faces, one panel per cost
  model, one colour per detector run, with each fit.
* ``hsd_merge``: HSD's merge ratio (faces / coplanar polygons) against its
  measured saving over TA, ``1 - HSD/TA`` of the total operations per light
  (both ``intended``), per cost model: the "buildings" claim (HSD 2011 Sec. VII:
  coplanar faces are where HSD should pay).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from silcount.plots import STYLE, save_figure

KIND_COLOURS = {"closed": "#1b6ca8", "open": "#d1495b", "flat": "#2e933c"}
LEVEL_MARKERS = ("o", "s", "^", "D", "v")
RUN_COLOURS = ("#555555", "#1b6ca8", "#d1495b", "#edae49", "#2e933c", "#7b4ea3", "#e07a1f", "#3aa5a5", "#a0522d")


def _line(ax, fit: dict | None, xs: np.ndarray, label: str, **kw) -> None:
    if fit and fit.get("alpha") is not None:
        lo, hi = fit["alpha_ci"] or (float("nan"), float("nan"))
        ax.plot(
            xs,
            fit["c"] * xs ** fit["alpha"],
            label=f"{label}: {fit['c']:.3g} F^{fit['alpha']:.3f} [{lo:.3f}, {hi:.3f}], {fit['meshes']} meshes",
            **kw,
        )


def silhouette(meshes, fits: dict, out_dir: Path) -> list[Path]:
    import matplotlib.pyplot as plt

    ok = meshes[meshes["error"] == ""]
    fig, ax = plt.subplots(figsize=(8, 6))
    for kind, colour in KIND_COLOURS.items():
        for level in sorted(ok["level"].unique()):
            part = ok[(ok["kind"] == kind) & (ok["level"] == level)]
            if len(part):
                ax.scatter(
                    part["faces"],
                    part["silhouette_edges_mean"],
                    s=22,
                    c=colour,
                    alpha=0.8,
                    marker=LEVEL_MARKERS[int(level) % len(LEVEL_MARKERS)],
                    label=f"{kind}, level {level}",
                )
    xs = np.geomspace(max(float(ok["faces"].min()) / 2, 1.0), float(ok["faces"].max()) * 2, 50) if len(ok) else None
    if xs is not None:
        _line(ax, fits.get("silhouette_edges"), xs, "fit, every mesh", c="black")
        _line(ax, fits.get("silhouette_edges:closed"), xs, "fit, closed", c=KIND_COLOURS["closed"], ls="-.")
        _line(ax, fits.get("silhouette_edges:level0"), xs, "fit, sources", c="#777777", lw=1)
        ax.plot(xs, 0.7 * xs**0.8, c="#7b4ea3", ls="--", label="McGuire 2004: 0.7 F^0.8")
        ax.plot(xs, xs**0.5, c="#999999", ls=":", label="convex: F^0.5 (for scale)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("faces F")
    ax.set_ylabel("silhouette edges (mean over lights)")
    ax.set_title("Silhouette size against face count")
    ax.legend(fontsize=7, loc="upper left")
    return save_figure(fig, out_dir, "silhouette")


def operations(meshes, fits: dict, runs: list[str], out_dir: Path) -> list[Path]:
    import matplotlib.pyplot as plt

    ok = meshes[meshes["error"] == ""]
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), sharex=True)
    xs = np.geomspace(max(float(ok["faces"].min()) / 2, 1.0), float(ok["faces"].max()) * 2, 50) if len(ok) else None
    for ax, model in zip(axes, ("paper", "true")):
        for i, run in enumerate(runs):
            col = f"{run}:{model}_total"
            if col not in ok or xs is None:
                continue
            colour = RUN_COLOURS[i % len(RUN_COLOURS)]
            ax.scatter(ok["faces"], ok[col], s=10, c=colour, alpha=0.6)
            fit = fits.get(f"{run}:{model}")
            if fit and fit.get("alpha") is not None:
                _line(ax, fit, xs, run, c=colour)
            else:
                ax.scatter([], [], c=colour, label=run)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("faces F")
        ax.set_ylabel("operations per light")
        ax.set_title(f"{model} cost model")
        ax.legend(fontsize=7, loc="upper left")
    return save_figure(fig, out_dir, "operations")


def hsd_merge(meshes, out_dir: Path) -> list[Path]:
    import matplotlib.pyplot as plt

    ok = meshes[meshes["error"] == ""]
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for model, colour in (("paper", "#edae49"), ("true", "#1b6ca8")):
        ta, hsd = f"ta:{model}_total", f"hsd:{model}_total"
        if ta in ok and hsd in ok:
            saving = 1.0 - ok[hsd] / ok[ta]
            ax.scatter(ok["merge_ratio"], saving, s=20, c=colour, alpha=0.8, label=f"{model} model")
    ax.axhline(0.0, c="black", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("merge ratio: faces / coplanar polygons")
    ax.set_ylabel("HSD's saving over TA: 1 - HSD/TA (operations per light)")
    ax.set_title("Where coplanar merging pays (HSD 2011 Sec. VII, 'buildings')")
    ax.legend(fontsize=8)
    return save_figure(fig, out_dir, "hsd_merge")


def write_figures(meshes, fits: dict, runs: list[str], out_dir: Path) -> list[Path]:
    """Every figure under ``out_dir``; ``hsd_merge`` only when both TA and HSD (intended) ran."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with plt.rc_context(STYLE):  # type: ignore[arg-type]  # matplotlib's stubs want literal rc keys
        paths = silhouette(meshes, fits, out_dir) + operations(meshes, fits, runs, out_dir)
        if "ta" in runs and "hsd" in runs:
            paths += hsd_merge(meshes, out_dir)
    return paths
