"""The report section "The frame budget" and the papers' frame rates answered by it (issue 41 items 4, 5).

Renders from the committed measurements (:mod:`silcount.render.budget`, ``frame-budget.csv``): the same
files on every run.  Written under ``<out>/frame/``:

* ``budget.md``: each case's dominant stage by operations, by software time and by llvmpipe time and
  whether the two renderers agree; the stage sums against the frames' wall times; the face count F at
  which detection falls below 10 % of the frame; the papers' frame-rate claims answered (Amdahl's law);
* ``budget-shares.csv``: every stage's share of every frame, in operations and in time, both renderers;
* ``budget-stages.png``/``.svg``: stacked stage times against F on the corpus meshes.

The FPS answers (EESD paper Sec. 6: TA 69.93, VnV 65.51, EESD 73.16 FPS; HSD paper Secs. I and VIII:
"from 69.93 to 75.53", P IV 2.8 GHz, the bunny's 2207 edges): a detector ``k`` times faster, taking a
share ``s`` of the frame, leaves a frame of ``(1 - s) + s / k`` (Amdahl); a printed frame-time change
``r = 1 - FPS_before / FPS_after`` needs ``s >= r / (1 - 1 / k)`` (``s >= r`` for an infinitely fast
detector).  ``k`` is the papers' own: their cycle model at 2.8 GHz (:func:`silcount.calibrate.fps.paper_cycles`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from silcount.atomic import make_folder, write_text
from silcount.render.budget import PERTRIANGLE, read
from silcount.render.opengl import STAGES

THRESHOLD = 0.10
"""Detection's share of the frame the issue asks about."""
TOLERANCE = 0.05
"""The stage times must add up to within 5 % of the frame's wall time."""
CLOCK_HZ = 2.8e9
BUNNY_EDGES = 2207
PAIRS = (
    ("EESD 2012 Sec. 6", "eesd2012-ta", 69.93, "eesd2012-eesd", 73.16),
    ("EESD 2012 Sec. 6", "eesd2012-vnv", 65.51, "eesd2012-eesd", 73.16),
    ("EESD 2012 Sec. 6", "eesd2012-vnv", 65.51, "eesd2012-ta", 69.93),
    ("HSD 2011 Secs. II, VIII", "hsd2011-ta", 69.93, "hsd2011-hsd", 75.53),
)
"""(source, model before, FPS before, model after, FPS after): each printed frame-rate change between two
algorithms (TA is HSD's 'conventional' 69.93 FPS baseline, the EESD paper's TA figure)."""
N_READINGS = (("n = E/6 (the papers' e_n = 6n)", BUNNY_EDGES / 6), ("n = F = 2E/3 (faces)", 2 * BUNNY_EDGES / 3))
"""The readings of n for the bunny's 2207 edges, as :func:`silcount.calibrate.fps.fps_table` takes them."""


def short(scene: str) -> str:
    """A corpus scene's mesh, short enough for an axis label: ``decimated-knight-x4`` -> ``knight``."""
    return scene.split("-x")[0].split("-")[-1]


def case_label(method: str, detector: str) -> str:
    return "per-triangle" if method == PERTRIANGLE else f"z-fail {detector}"


def shares(table: pd.DataFrame) -> pd.DataFrame:
    """Every stage's share of its frame: ``ops_share`` (the software frame's counted operations, the same
    frame either renderer draws), ``software`` and ``llvmpipe`` (stage time / frame wall time)."""
    keys = ["scene", "faces", "size", "method", "detector", "stage"]
    sw = table[table.renderer == "software"].set_index(keys)
    gl = table[table.renderer == "llvmpipe"].set_index(keys)
    ops = sw["operations"].astype(float)
    frame_ops = ops.groupby(level=keys[:-1]).transform("sum")
    out = pd.DataFrame(
        {
            "ops_share": ops / frame_ops,
            "software": sw["seconds"] / sw["frame_seconds"],
            "llvmpipe": gl["seconds"] / gl["frame_seconds"],
            "software_ms": 1e3 * sw["seconds"],
            "llvmpipe_ms": 1e3 * gl["seconds"],
            "software_leads": sw["leads"],
            "llvmpipe_leads": gl["leads"],
        }
    )
    return out.reset_index()


def _top_two(col: pd.Series) -> str:
    """The largest and second-largest shares, in %: how close the dominant stage's lead is."""
    a, b = sorted(col.to_numpy(float), reverse=True)[:2]
    return f"{100 * a:.1f}/{100 * b:.1f}"


def _led(leads: pd.Series) -> str:
    """``k/n``: the repeated frames in which the most frequent leader led, of all of them."""
    return f"{int(leads.max())}/{int(leads.sum())}"


def _agreement(top_sw: str, top_gl: str, settled: bool) -> str:
    """``yes`` (the same dominant stage), ``NO`` (different ones, each renderer's led every one of its repeated
    frames) or ``unsettled`` (different ones, and one renderer's repeated frames named different leaders: its
    lead is within its own frame-to-frame spread, so no stage dominates it)."""
    if top_sw == top_gl:
        return "yes"
    return "NO" if settled else "unsettled"


def _ratio(a: float, b: float) -> float:
    """``a / b`` to 2 places; NaN where ``b`` is 0 (a stage neither renderer ran)."""
    return round(float(a) / float(b), 2) if b else float("nan")


def dominance(sh: pd.DataFrame) -> pd.DataFrame:
    """Per frame: the dominant stage by operations, software time and llvmpipe time (the kept frame's), whether
    the renderers agree (:func:`_agreement`), how many repeated frames each renderer's leader led; detection's
    shares."""
    rows = []
    for (scene, faces, size, method, detector), g in sh.groupby(
        ["scene", "faces", "size", "method", "detector"], sort=False
    ):
        g = g.set_index("stage")
        top = {col: str(g[col].idxmax()) for col in ("ops_share", "software", "llvmpipe")}
        detection = {col: 100 * float(g[col]["detection"]) for col in ("ops_share", "software", "llvmpipe")}
        settled = all(g[f"{r}_leads"].max() == g[f"{r}_leads"].sum() for r in ("software", "llvmpipe"))
        rest = g.drop(index="detection")
        rows.append(
            {
                "scene": scene,
                "F": faces,
                "size": size,
                "case": case_label(str(method), str(detector)),
                "ops": top["ops_share"],
                "software": top["software"],
                "llvmpipe": top["llvmpipe"],
                "agree": _agreement(top["software"], top["llvmpipe"], settled),
                "sw led": _led(g["software_leads"]),
                "gl led": _led(g["llvmpipe_leads"]),
                "sw 1st/2nd %": _top_two(g["software"]),
                "gl 1st/2nd %": _top_two(g["llvmpipe"]),
                "detection ops %": detection["ops_share"],
                "detection sw %": detection["software"],
                "detection gl %": detection["llvmpipe"],
                "detection sw/gl ms": f"{g['software_ms']['detection']:.2f}/{g['llvmpipe_ms']['detection']:.2f}",
                "detection sw/gl": _ratio(g["software_ms"]["detection"], g["llvmpipe_ms"]["detection"]),
                "rest gl/sw": _ratio(rest["llvmpipe_ms"].sum(), rest["software_ms"].sum()),
            }
        )
    return pd.DataFrame(rows)


def detection_led_alone(dom: pd.DataFrame) -> str:
    """A sentence on the disagreements (:func:`dominance`'s rows) where the software frame's dominant stage is
    detection: the detector is the same code on the same CPU in both frames, so its times are compared, and the
    other stages' (``rest``)."""
    cases = dom[(dom.agree != "yes") & (dom.software == "detection") & (dom.llvmpipe != "detection")]
    if cases.empty:
        return ""
    det, rest = cases["detection sw/gl"], cases["rest gl/sw"]
    return (
        f"In the {len(cases)} of them where the software frame's dominant stage is detection and llvmpipe's is "
        f"not, the detector (the same code on the same CPU in both frames) took {det.min():.2f}-{det.max():.2f} "
        f"times as long in the software frame as in llvmpipe's, while llvmpipe's other stages took "
        f"{rest.min():.2f}-{rest.max():.2f} times the software's: the renderers differ in how fast they "
        "rasterise, not in the detector, and the faster rasteriser leaves detection in the lead."
    )


def stage_sums(table: pd.DataFrame) -> pd.DataFrame:
    """Per renderer: the least and greatest (stage-time sum / frame wall time) over every frame."""
    frames = table.groupby(["scene", "size", "renderer", "method", "detector"], sort=False).agg(
        total=("seconds", "sum"), frame=("frame_seconds", "first")
    )
    ratio = (frames["total"] / frames["frame"]).rename("ratio").reset_index()
    out = ratio.groupby("renderer")["ratio"].agg(["count", "min", "max"]).reset_index()
    out["worst |sum/frame - 1| %"] = 100 * np.maximum((out["max"] - 1).abs(), (out["min"] - 1).abs())
    out["within 5 %"] = np.where(out["worst |sum/frame - 1| %"] <= 100 * TOLERANCE, "yes", "NO")
    return out


def crossing(faces: np.ndarray, share: np.ndarray) -> tuple[float, float, str]:
    """Least squares of log10 share on log10 F (a power law ``share = a F^b``): the slope b and the F at
    which it gives :data:`THRESHOLD`, with where that F lies against the measured range."""
    keep = share > 0
    f, s = np.log10(faces[keep]), np.log10(share[keep])
    if len(np.unique(f)) < 2:
        return float("nan"), float("nan"), "too few points"
    b, a = np.polyfit(f, s, 1)
    if np.all(share < THRESHOLD) and b <= 0:
        return float(b), float("nan"), "below 10 % at every F, and falling"
    if b == 0:
        return float(b), float("nan"), "flat"
    at = 10 ** ((np.log10(THRESHOLD) - a) / b)
    lo, hi = faces.min(), faces.max()
    where = "within the measured F" if lo <= at <= hi else "extrapolated"
    side = "below 10 % for F < F10" if b > 0 else "below 10 % for F > F10"
    return float(b), float(at), f"{side}; {where}"


def _f10(at: float, lo: float, hi: float) -> str:
    """F10 as shown: beyond 100 times the measured range it is only a bound (a near-flat fit's crossing)."""
    if np.isnan(at):
        return "-"
    if at > 100 * hi:
        return f"> {100 * hi:,.0f}"
    if at < lo / 100:
        return f"< {lo / 100:,.0f}"
    return f"{at:,.0f}"


def detection_fits(sh: pd.DataFrame, corpus: list[str]) -> pd.DataFrame:
    """Per detector, renderer and size: detection's share against F on the corpus series (:func:`crossing`)."""
    det = sh[(sh.stage == "detection") & (sh.method != PERTRIANGLE) & sh.scene.isin(corpus)]
    rows = []
    for (detector, size), g in det.groupby(["detector", "size"], sort=False):
        for renderer in ("software", "llvmpipe"):
            b, at, note = crossing(g.faces.to_numpy(float), g[renderer].to_numpy(float))
            rows.append(
                {
                    "detector": detector,
                    "size": size,
                    "renderer": renderer,
                    "share at F min..max %": f"{100 * g[renderer].min():.2f}..{100 * g[renderer].max():.2f}",
                    "slope b": round(b, 2),
                    "F10": _f10(at, g.faces.min(), g.faces.max()),
                    "reading": note,
                }
            )
    return pd.DataFrame(rows)


def fps_answers(sh: pd.DataFrame) -> pd.DataFrame:
    """Each printed FPS change under each n reading: the papers' own detection times at 2.8 GHz, their
    speed-up k, the share s needed for the printed change, and the change k gives at the measured shares."""
    from silcount.calibrate.fps import paper_cycles

    det = sh[(sh.stage == "detection") & (sh.method != PERTRIANGLE)]
    rows = []
    for source, before, fps_b, after, fps_a in PAIRS:
        algo_b = before.split("-")[1]
        measured = det[det.detector == algo_b]
        r = 1 - fps_b / fps_a  # the frame's printed relative shortening
        for reading, n in N_READINGS:
            t_b, t_a = (1e3 * paper_cycles(m, n, 3) / CLOCK_HZ for m in (before, after))
            k = t_b / t_a
            need = r / (1 - 1 / k) if k > 1 else float("inf")
            row = {
                "source": source,
                "change": f"{before.split('-')[1].upper()} {fps_b} -> {after.split('-')[1].upper()} {fps_a}",
                "reading": reading,
                "frame ms": f"{1e3 / fps_b:.2f} -> {1e3 / fps_a:.2f}",
                "printed shortening %": round(100 * r, 2),
                "model detection ms": f"{t_b:.2f} -> {t_a:.2f}",
                "model saving / frame saving": round((t_b - t_a) / (1e3 / fps_b - 1e3 / fps_a), 2),
                "k": round(k, 3),
                "needed s %": "none (k <= 1)" if k <= 1 else f"{100 * need:.1f}",
                "model s %": round(100 * t_b / (1e3 / fps_b), 1),
            }
            for renderer in ("software", "llvmpipe"):
                s = float(measured[renderer].max())
                fps = fps_b / ((1 - s) + s / k)
                row[f"max measured s % ({renderer})"] = round(100 * s, 2)
                row[f"FPS at that s ({renderer})"] = round(fps, 2)
            rows.append(row)
    return pd.DataFrame(rows)


def figure(table: pd.DataFrame, corpus: list[str], out_dir: Path) -> list[Path]:
    """Stacked stage times against F: corpus meshes at 1024^2, rows software / llvmpipe, columns z-fail
    (reference detector) / per-triangle."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from silcount.plots import STYLE, save_figure

    data = table[table.scene.isin(corpus) & (table["size"] == table["size"].max())]
    cases = (("zfail", "reference"), (PERTRIANGLE, ""))
    colours = dict(zip(STAGES, plt.get_cmap("tab10")(np.arange(len(STAGES))), strict=True))
    with plt.rc_context(STYLE):  # type: ignore[arg-type]  # matplotlib's stubs want literal rc keys
        fig, axes = plt.subplots(2, 2, figsize=(12.5, 7.5), sharex=True)
        for i, renderer in enumerate(("software", "llvmpipe")):
            for j, (method, detector) in enumerate(cases):
                ax = axes[i, j]
                d = data[(data.renderer == renderer) & (data.method == method) & (data.detector == detector)]
                wide = d.pivot_table(index=["faces", "scene"], columns="stage", values="seconds").sort_index()
                x = np.arange(len(wide))
                bottom = np.zeros(len(wide))
                for stage in STAGES:
                    ms = 1e3 * wide[stage].to_numpy()
                    ax.bar(x, ms, bottom=bottom, color=colours[stage], label=stage, width=0.7)
                    bottom += ms
                ax.set_xticks(x, [f"{f:,}\n{short(s)}" for f, s in wide.index], fontsize=8)
                ax.set_title(f"{renderer}: {case_label(method, detector)}, {int(d['size'].iloc[0])}^2")
                ax.set_ylabel("ms per frame")
        for ax in axes[1]:
            ax.set_xlabel("F, caster faces (each mesh at 1, 4, 16 x)")
        handles, labels = axes[0, 0].get_legend_handles_labels()
        fig.legend(handles[::-1], labels[::-1], loc="center right", title="stage\n(detection:\nthe bottom band)")
        fig.tight_layout(rect=(0, 0, 0.88, 1))
        return save_figure(fig, out_dir, "budget-stages")


def _md(df: pd.DataFrame) -> str:
    return df.to_markdown(index=False, floatfmt=".2f")


def markdown(table: pd.DataFrame, meta: dict, corpus: list[str]) -> str:
    """The section's text (module docstring)."""
    sh = shares(table)
    dom = dominance(sh)
    by_scene = (
        dom.groupby(["scene", "size"], sort=False)["agree"]
        .agg(
            agree=lambda a: f"{(a == 'yes').sum()}/{len(a)}",
            disagree=lambda a: int((a == "NO").sum()),
            unsettled=lambda a: int((a == "unsettled").sum()),
        )
        .reset_index()
    )
    count = dom.agree.value_counts()
    whole = dom[dom.case.isin(["z-fail reference", "per-triangle"])]
    lines = [
        "# The frame budget",
        "",
        "Was detection the bottleneck? Every stage of the shadow-volume frame, counted and timed, on silcount's "
        "software renderer and on Mesa llvmpipe (issue 41). Times are the committed measurements "
        "(`silcount/models/measured/frame-budget.csv`), not this run's: "
        f"{meta['gl_renderer']}, {meta['cores']} cores, load (1, 5, 15 min) {meta['load_before']} before and "
        f"{meta['load_after']} after; {meta['kept']} (`{meta['command']}`). Every frame is z-fail with each "
        "built-in detector (fast engine, intended variant) or the per-triangle baseline (no detector). "
        "Operations are the software frame's exact counts (docs/rendering.md), the same frame either renderer "
        "draws. A CPU rasteriser is not the papers' 2011 NVIDIA GPU: these are this machine's shares.",
        "",
        "## The stage times against the frame's wall time",
        "",
        _md(stage_sums(table)),
        "",
        "## Which stage dominates",
        "",
        "Agreement of software and llvmpipe on the stage taking the most time in the kept frame, per scene "
        "and resolution (cases agreeing / cases). Where they differ, the frame is `NO` if each renderer's "
        f"dominant stage led every one of its {meta['repeat']} repeated frames, and `unsettled` if one "
        "renderer's repeated frames named different leaders (its lead is within its own frame-to-frame spread: "
        "that renderer has no dominant stage to agree with); `sw led` and `gl led` give how many of them "
        "the most frequent leader led.",
        "",
        _md(by_scene),
        "",
        f"Over all {len(dom)} frames: {count.get('yes', 0)} agree, {count.get('NO', 0)} disagree, "
        f"{count.get('unsettled', 0)} unsettled. The z-fail (reference) and "
        "per-triangle frames (every detector's row, and every stage's share, are in `budget-shares.csv`):",
        "",
        _md(whole),
        "",
        "Frames where the renderers disagree (1st/2nd: the two largest time shares, how close the lead is):",
        "",
        _md(dom[dom.agree != "yes"]) if (dom.agree != "yes").any() else "none.",
        "",
        detection_led_alone(dom),
        "",
        "## When is detection below 10 % of the frame?",
        "",
        f"Detection's time share against F on the corpus meshes ({', '.join(corpus)}): a power law "
        "share = a F^b fitted by least squares on log10 share against log10 F over the nine points of each "
        "detector, renderer and size; F10 is where the fit gives 10 %; beyond 100 times the measured F it "
        "is shown as a bound only.",
        "",
        _md(detection_fits(sh, corpus)),
        "",
        "Detection's share on every frame (z-fail), by operations and time:",
        "",
        _md(
            dom[dom.case != "per-triangle"]
            .groupby("case")[["detection ops %", "detection sw %", "detection gl %"]]
            .agg(["min", "max"])
            .round(2)
            .reset_index()
            .set_axis(["case", "ops % min", "ops % max", "sw % min", "sw % max", "gl % min", "gl % max"], axis=1)
        ),
        "",
        "![stacked stage times against F](budget-stages.png)",
        "",
        "## The papers' frame rates, answered",
        "",
        "Amdahl: a detector k times faster taking a share s of the frame leaves a frame of (1 - s) + s / k. "
        "A printed change from FPS_before to FPS_after shortens the frame by r = 1 - FPS_before / FPS_after, "
        "which needs s >= r / (1 - 1/k) (s >= r even for an infinitely fast detector); a needed share above "
        "100 % is impossible on any hardware. k and the model's detection times are the papers' own cycle "
        "model (their printed closed forms, their cycle weights) at their stated 2.8 GHz, on the bunny's "
        "2207 edges, under both readings of n; 'model saving / frame saving' sets the detection time the "
        "model says the faster algorithm saves against the frame time the FPS figures say it saved. The "
        "measured s is the baseline detector's largest detection share over every scene and resolution here "
        "(silcount's detector, this machine: not the papers' share), and the FPS it would give at the "
        "model's k.",
        "",
        _md(fps_answers(sh)),
        "",
    ]
    return "\n".join(lines)


def report(out_dir: Path) -> list[Path]:
    """Write the section under ``out_dir/frame/`` (module docstring); returns the paths."""
    table, meta = read()
    dest = make_folder(out_dir / "frame")
    corpus = sorted({s for s in table.scene if "-x" in s}, key=lambda s: (s.split("-x")[0], int(s.split("-x")[1])))
    paths = [write_text(dest / "budget.md", markdown(table, meta, corpus))]
    paths.append(write_text(dest / "budget-shares.csv", shares(table).to_csv(index=False, float_format="%.6f")))
    paths += figure(table, corpus, dest)
    return paths


__all__ = ["crossing", "dominance", "fps_answers", "report", "shares", "stage_sums"]
