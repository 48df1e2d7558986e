"""The calibration as one computation: timings + tallies -> predictions, summaries, FPS table, ranking evidence.

Timing is noisy, so what is committed is a *measurement*: the timings of one
run (``silcount/models/cycles/timings-<cpu model>.csv``, written by ``silcount calibrate
--out DIR`` as ``DIR/timings.csv`` and copied there by hand).  The report of
``silcount report`` (:func:`silcount.cli.calibrate.report`) recomputes the
tallies from the code and the predictions from that file, so it is the same
bytes on every run; a live ``silcount calibrate`` times afresh.

Two fits are reported: over every sample, and over the meshes of at least
:data:`LARGE_FACES` faces only (refitted), where the loops, not the set-up, take the time.
Both are the papers' four algorithms' alone; the literature's detectors
(:func:`~silcount.calibrate.timing.literature`), when the timings time them,
are predicted with the first fit's scales and reported apart.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from silcount.calibrate import fps, predict, timing
from silcount.counting.cycles import Profile, builtin_profiles, cycles_dir
from silcount.errors import UnreadableInput
from silcount.mesh.model import Mesh

LARGE_FACES = 320
"""The second fit keeps meshes with at least this many faces (icosphere2 up): below it a call's fixed
cost (the numpy set-up of :func:`~silcount.detectors.plain_edge_ids`: facing flags, edge-id lookup),
which no per-operation weight can model, is a large share of its time."""


@dataclass
class Calibration:
    """Everything ``silcount calibrate`` reports."""

    cpu_model: str
    timings_source: str
    samples: pd.DataFrame
    predictions: pd.DataFrame
    per_mesh: pd.DataFrame
    summary: pd.DataFrame
    summary_large: pd.DataFrame
    fps: pd.DataFrame
    literature_samples: pd.DataFrame  # gaussmap and cones, when the timings have them (else no rows)
    literature_predictions: pd.DataFrame  # their predictions with ``summary``'s scales
    literature: pd.DataFrame  # per (model, profile, detector): predicted/measured ratios (predict.per_detector)
    literature_meshes: pd.DataFrame  # per mesh: measured seconds of every timed detector, summed over the lights
    within: pd.DataFrame  # the papers' four, each within its own samples with the shared fit (per_detector)
    within_large: pd.DataFrame  # the same for the refit on meshes of at least LARGE_FACES faces
    left_out: tuple[str, ...] = ()  # timed meshes that load today with another face count, and why


def committed_timings() -> Path | None:
    """The committed timings file (the first ``silcount/models/cycles/timings-*.csv``), or None."""
    found = sorted(cycles_dir().glob("timings-*.csv"))
    return found[0] if found else None


def read_timings(path: Path) -> pd.DataFrame:
    try:
        frame = pd.read_csv(path)
    except (OSError, ValueError) as exc:
        raise UnreadableInput(f"cannot read timings {path}: {exc}") from exc
    missing = {"cpu_model", *timing.KEY, "seconds"} - set(frame.columns)
    if missing:
        raise UnreadableInput(f"timings {path} lack columns {', '.join(sorted(missing))}")
    return frame


def calibrate(
    meshes: list[tuple[str, Mesh]],
    times: pd.DataFrame,
    cpu_model: str,
    source: str,
    profiles: dict[str, Profile] | None = None,
    n_lights: int = timing.LIGHTS,
    show: bool | None = False,
) -> Calibration:
    """Predict ``times`` (one row per mesh, detector, light) from the tallies of ``meshes`` under every profile."""
    profiles = builtin_profiles() if profiles is None else profiles
    lit = tuple(d for d in timing.literature() if d in set(times["detector"]))
    every = timing.samples(timing.tallies(meshes, n_lights, show, timing.algorithms() + lit), times)
    papers = every["detector"].isin(timing.algorithms())
    samples = every[papers].reset_index(drop=True)
    lit_samples = every[~papers].reset_index(drop=True)
    pred = predict.weighted(samples, profiles)
    lit_pred = predict.weighted(lit_samples, profiles, predict.scales_of(pred)) if lit else pred.iloc[:0]
    meshes_table = predict.per_mesh(pred)
    large = samples[samples["faces"] >= LARGE_FACES]
    pred_large = predict.weighted(large, profiles) if len(large) else pred.iloc[:0]
    summary_large = predict.summary(pred_large, predict.per_mesh(pred_large) if len(large) else meshes_table.iloc[:0])
    return Calibration(
        cpu_model,
        source,
        samples,
        pred,
        meshes_table,
        predict.summary(pred, meshes_table),
        summary_large,
        fps.fps_table(),
        lit_samples,
        lit_pred,
        predict.per_detector(lit_pred),
        measured_per_mesh(every) if lit else every.iloc[:0, :0],
        predict.per_detector(pred),
        predict.per_detector(pred_large),
    )


def measured_per_mesh(samples: pd.DataFrame) -> pd.DataFrame:
    """One row per mesh: faces, then each detector's measured seconds summed over the lights, and their order."""
    sums = samples.groupby(["mesh", "detector"], sort=False)["seconds"].sum().unstack("detector")
    sums = sums.reindex(samples["mesh"].unique())  # unstack sorts by name: back to the samples' order (by size)
    dets = [d for d in timing.timed() if d in sums.columns]
    faces = samples.drop_duplicates("mesh").set_index("mesh")["faces"]
    out = sums[dets].rename(columns=lambda d: f"{d}_s")
    out.insert(0, "faces", faces.loc[out.index].astype(int))

    def order(row: pd.Series) -> str:
        return " < ".join(sorted(dets, key=lambda d: float(row[f"{d}_s"])))

    out["measured_order"] = [order(row) for _, row in out.iterrows()]
    return out.reset_index()


def from_committed(corpus: Path | None = None, show: bool | None = False) -> Calibration:
    """The calibration of the committed timings on the icosphere series, or on the corpus under ``corpus``.

    With ``corpus``, the meshes are the corpus files the committed timings time (by path); a
    timed file missing from ``corpus`` fails, naming it.
    """
    path = committed_timings()
    if path is None:
        raise UnreadableInput(f"no committed timings (timings-*.csv) under {cycles_dir()}")
    times = read_timings(path)
    if corpus is None:
        meshes = timing.series_meshes()
    else:
        from silcount.mesh.io import load_mesh

        meshes = []
        for name in sorted(set(times["mesh"]) - set(timing.SERIES)):
            if not (corpus / name).is_file():
                raise UnreadableInput(f"committed timings time {name}, which is not under {corpus}")
            mesh = load_mesh(corpus / name)
            mesh.name = name
            meshes.append(("corpus", mesh))
    meshes, left_out = _as_timed(meshes, times)
    times = times[times["mesh"].isin({m.name for _, m in meshes})].drop(columns=["faces"], errors="ignore")
    if not len(times):
        raise UnreadableInput(f"committed timings {path.name} time none of these meshes")
    n_lights = int(times["light"].max()) + 1
    cpu = str(times["cpu_model"].iloc[0])
    cal = calibrate(meshes, times, cpu, f"silcount/models/cycles/{path.name}", n_lights=n_lights, show=show)
    cal.left_out = left_out
    return cal


def _as_timed(meshes: list[tuple[str, Mesh]], times: pd.DataFrame) -> tuple[list[tuple[str, Mesh]], tuple[str, ...]]:
    """The meshes that load today as they were timed (the timings' ``faces``), and a line for each other one.

    A loader change can turn a timed file into another mesh (suzanne.ply was timed as 968 triangles; its
    500 polygons are kept as polygons today): pairing its old times with today's tallies would be wrong.
    """
    if "faces" not in times.columns:
        return meshes, ()
    timed = times.groupby("mesh")["faces"].first()
    kept, left_out = [], []
    for group, mesh in meshes:
        if mesh.name in timed.index and int(timed[mesh.name]) != mesh.n_faces:
            left_out.append(f"{mesh.name}: timed with {int(timed[mesh.name])} faces, loads today with {mesh.n_faces}")
        else:
            kept.append((group, mesh))
    return kept, tuple(left_out)


def ranking_evidence(cal: Calibration | None = None) -> dict:
    """Per mesh: the measured fastest algorithm and order, and each (model, profile)'s predicted ones.

    For the claims that rank algorithms by cycles (EESD fastest; TA and VnV
    five and six times HSD; the FPS orders): ``measured`` gives the measured
    seconds (summed over the lights) per algorithm, so a claim can say whether
    measured time agrees with its ranking.  Built from the committed timings
    unless ``cal`` is given.  ``summary`` (every mesh) and ``summary_large`` (meshes of at least
    :data:`LARGE_FACES` faces) give per model and profile R^2, mean rank rho and on how many
    meshes the predicted fastest is the measured fastest.
    """
    cal = from_committed() if cal is None else cal
    out: dict = {"cpu_model": cal.cpu_model, "timings": cal.timings_source, "meshes": {}, "summary": {}}
    sums = cal.samples.groupby(["mesh", "detector"])["seconds"].sum()
    for mesh, sub in cal.per_mesh.groupby("mesh", sort=False):
        first = sub.iloc[0]
        entry = out["meshes"].setdefault(
            mesh,
            {
                "faces": int(first["faces"]),
                "measured_seconds": {d: float(s) for d, s in sums[mesh].items()},
                "measured_order": first["measured_order"].split(" < "),
                "measured_fastest": first["measured_order"].split(" < ")[0],
                "predicted": {},
            },
        )
        rec: dict[Any, Any]
        for rec in sub.to_dict("records"):
            order = str(rec["predicted_order"]).split(" < ")
            entry["predicted"].setdefault(rec["model"], {})[rec["profile"]] = {
                "order": order,
                "fastest": order[0],
                "fastest_agrees": bool(rec["fastest_agrees"]),
                "rank_rho": None if pd.isna(rec["rank_rho"]) else float(rec["rank_rho"]),
            }
    for key, table in (("summary", cal.summary), ("summary_large", cal.summary_large)):
        out[key] = {}
        for rec in table.to_dict("records"):
            out[key].setdefault(rec["model"], {})[rec["profile"]] = {
                "r2": float(rec["r2"]),
                "rank_rho": float(rec["rank_rho"]),
                "fastest_agree": int(rec["fastest_agree"]),
                "meshes": int(rec["meshes"]),
            }
    return out
