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
* ``literature``: ``true`` operations per light against faces, log-log, for
  the papers' four detectors, ``reference``, ``gaussmap`` and ``cones``
  (``intended``), one panel per light kind, each with its fit over the
  panel's meshes (:mod:`silcount.study.literature`).
* ``output_sensitivity``: the hierarchies' edges tested per light against
  ``s log2 F`` (``s`` the silhouette), with the fits of
  :func:`silcount.study.literature.output_fits` and the line ``y = x``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from silcount.detectors import get, with_role
from silcount.plots import STYLE, save_figure
from silcount.study.fits import power_fit
from silcount.study.literature import AGAINST, label, order, size_of

KIND_COLOURS = {"closed": "#1b6ca8", "open": "#d1495b", "flat": "#2e933c"}
LEVEL_MARKERS = ("o", "s", "^", "D", "v")
RUN_COLOURS = ("#555555", "#1b6ca8", "#d1495b", "#edae49", "#2e933c", "#7b4ea3", "#e07a1f", "#3aa5a5", "#a0522d")


def _line(ax, fit: dict | None, xs: np.ndarray, label: str, **kw) -> None:
    if fit and fit.get("alpha") is not None:
        lo, hi = fit["alpha_ci"] or (float("nan"), float("nan"))
        x = fit.get("against", "F")
        x = x if x in ("F", "s") else f"({x})"
        ax.plot(
            xs,
            fit["c"] * xs ** fit["alpha"],
            label=f"{label}: {fit['c']:.3g} {x}^{fit['alpha']:.3f} [{lo:.3f}, {hi:.3f}], {fit['meshes']} meshes",
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


def _span(values) -> np.ndarray:
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    return np.geomspace(max(float(v.min()) / 2, 1.0), float(v.max()) * 2, 50) if v.size else np.array([])


def literature(frame, out_dir: Path) -> list[Path]:
    """``true`` operations per light against F, the seven detectors, one panel per light kind (``frame``:
    :func:`silcount.study.literature.kind_frame`)."""
    import matplotlib.pyplot as plt

    kinds = sorted(set(frame["light_kind"])) or ["directional"]
    fig, axes = plt.subplots(1, len(kinds), figsize=(8.5 * len(kinds), 6), squeeze=False, sharey=True)
    xs = _span(frame["faces"])
    for ax, kind in zip(axes[0], kinds):
        for det in order():
            part = frame[(frame["detector"] == det) & (frame["light_kind"] == kind)]
            if part.empty:
                continue
            colour, marker = get(det).style
            ax.scatter(part["faces"], part["true_ops"], s=14, c=colour, marker=marker, alpha=0.65)
            fit = power_fit(part["faces"], part["true_ops"], f"every mesh, {kind} lights")
            if fit["alpha"] is not None:
                _line(ax, fit, xs, label(det), c=colour, ls="-" if det in with_role("paper") else "--")
            else:
                ax.scatter([], [], c=colour, marker=marker, label=label(det))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("faces F")
        ax.set_ylabel("true operations per light (mean over the lights)")
        ax.set_title(f"The papers' detectors beside the literature's: {kind} lights")
        ax.legend(fontsize=7, loc="upper left")
    return save_figure(fig, out_dir, "literature")


def output_sensitivity(frame, fits: dict, out_dir: Path) -> list[Path]:
    """The hierarchies' edges tested per light against ``s log2 F``, with their fits and ``y = x``."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.5, 6))
    part = frame[frame["detector"].isin(with_role("literature"))]
    xs = _span(size_of(part, AGAINST["s_log2F"])) if len(part) else np.array([])
    for det in with_role("literature"):
        for kind, filled in (("directional", True), ("point", False)):
            one = part[(part["detector"] == det) & (part["light_kind"] == kind)]
            if one.empty:
                continue
            colour, marker = get(det).style
            face = colour if filled else "none"
            ax.scatter(size_of(one, AGAINST["s_log2F"]), one["edge_test"], s=16, marker=marker, facecolors=face,
                       edgecolors=colour, alpha=0.7)  # fmt: skip
            fit = fits.get(f"{det}:{kind}:edge_test~s_log2F")
            name = f"{label(det)}, {kind}"
            if fit and fit.get("alpha") is not None and xs.size:
                _line(ax, fit, xs, name, c=colour, ls="-" if filled else ":")
            else:
                ax.scatter([], [], marker=marker, facecolors=face, edgecolors=colour, label=name)
    if xs.size:
        ax.plot(xs, xs, c="#999999", lw=0.8, ls="--", label="y = x (for scale)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("s log2 F (s: silhouette edges, mean over the lights)")
    ax.set_ylabel("edges tested per light (mean over the lights)")
    ax.set_title("Output sensitivity of the hierarchies: edges tested against s log2 F")
    ax.legend(fontsize=7, loc="upper left")
    return save_figure(fig, out_dir, "output_sensitivity")


def write_figures(meshes, fits: dict, runs: list[str], out_dir: Path, frame=None) -> list[Path]:
    """Every figure under ``out_dir``; ``hsd_merge`` only when both TA and HSD (intended) ran; ``literature``
    and ``output_sensitivity`` only with ``frame`` (:func:`silcount.study.literature.kind_frame`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with plt.rc_context(STYLE):  # type: ignore[arg-type]  # matplotlib's stubs want literal rc keys
        paths = silhouette(meshes, fits, out_dir) + operations(meshes, fits, runs, out_dir)
        if "ta" in runs and "hsd" in runs:
            paths += hsd_merge(meshes, out_dir)
        if frame is not None:
            paths += literature(frame, out_dir)
            if frame["detector"].isin(with_role("literature")).any():
                paths += output_sensitivity(frame, fits, out_dir)
    return paths
