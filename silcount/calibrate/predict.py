"""Do the counts predict time?  Tally x profile, one fitted scale per profile, against measured time.

For each cost model (``paper``, ``true``) and cycle profile
(:func:`silcount.counting.cycles.builtin_profiles`), every sample (mesh,
algorithm, light) gets ``w = profile.cycles(tally)``; the prediction is
``s * w`` with one scale ``s`` per (model, profile), fitted by least squares
in log space (``log s = mean(log t - log w)``, which minimises
``sum (log t - log s w)^2``).  Reported per (model, profile):

* ``r2``: 1 - SS_res / SS_tot of ``log t`` (the fraction of the spread of
  log time the weighted count explains, with the one scale);
* ``median_ratio`` and ``worst_ratio`` of predicted to measured time (worst:
  farthest from 1 in either direction);
* ``rank_rho``: Spearman's rank correlation of the algorithms' order per mesh
  (time and weighted count summed over the lights), averaged over meshes;
* ``fastest_agree``: on how many meshes the predicted fastest algorithm is
  the measured fastest (ties in the prediction count as the first, by
  detector name, which the summary table shows as a disagreement if wrong).

The literature's detectors (``gaussmap``, ``cones``) are not fitted: their
samples are predicted with the scale fitted on the papers' four
(``weighted(..., scales=scales_of(fit))``) and reported apart
(:func:`literature_summary`), so the four's numbers do not move.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from silcount.calibrate.timing import MODELS
from silcount.counting.cycles import TRUE_KINDS, Profile


def weighted(
    samples: pd.DataFrame, profiles: dict[str, Profile], scales: dict[tuple[str, str], float] | None = None
) -> pd.DataFrame:
    """Long table: one row per (model, profile, sample) with ``weighted``, ``predicted`` and ``ratio``.

    The scale of each (model, profile) is fitted on ``samples``, or taken from ``scales`` when given.
    """
    frames = []
    for model in MODELS:
        tallies = samples[[f"{model}_{k}" for k in TRUE_KINDS]].to_numpy(dtype=float)
        for name, prof in profiles.items():
            w = np.array([prof.cycles(dict(zip(TRUE_KINDS, row))) for row in tallies], dtype=float)
            frame = samples[["group", "mesh", "faces", "edges", "detector", "light", "seconds"]].copy()
            frame.insert(0, "profile", name)
            frame.insert(0, "model", model)
            frame["weighted"] = w
            if scales is None:
                log_s = float(np.mean(np.log(frame["seconds"]) - np.log(w)))
            else:
                log_s = float(np.log(scales[(model, name)]))
            frame["scale"] = np.exp(log_s)
            frame["predicted"] = np.exp(log_s) * w
            frame["ratio"] = frame["predicted"] / frame["seconds"]
            frames.append(frame)
    return pd.concat(frames, ignore_index=True)


def _spearman(a: np.ndarray, b: np.ndarray) -> float:
    from scipy.stats import spearmanr

    if len(a) < 2 or np.ptp(a) == 0 or np.ptp(b) == 0:
        return float("nan")
    return float(spearmanr(a, b).statistic)


def per_mesh(pred: pd.DataFrame) -> pd.DataFrame:
    """One row per (model, profile, mesh): measured and predicted order, rank correlation, fastest agreement."""
    rows = []
    faces = dict(zip(pred["mesh"], pred["faces"].tolist()))
    sums = pred.groupby(["model", "profile", "group", "mesh", "detector"], sort=False)[["seconds", "predicted"]].sum()
    for (model, profile, group, mesh), sub in sums.groupby(level=[0, 1, 2, 3], sort=False):
        dets = sub.index.get_level_values("detector").to_numpy()
        t, p = sub["seconds"].to_numpy(), sub["predicted"].to_numpy()
        measured = [str(d) for d in dets[np.argsort(t, kind="stable")]]
        predicted = [str(d) for d in dets[np.argsort(p, kind="stable")]]
        rows.append(
            {
                "model": model,
                "profile": profile,
                "group": group,
                "mesh": mesh,
                "faces": int(faces[mesh]),
                "measured_order": " < ".join(measured),
                "predicted_order": " < ".join(predicted),
                "rank_rho": _spearman(t, p),
                "fastest_agrees": measured[0] == predicted[0],
            }
        )
    return pd.DataFrame(rows)


def summary(pred: pd.DataFrame, meshes: pd.DataFrame) -> pd.DataFrame:
    """One row per (model, profile): scale, R^2, median and worst ratio, mean rank rho, fastest agreement."""
    rows = []
    for (model, profile), sub in pred.groupby(["model", "profile"], sort=False):
        y = np.log(sub["seconds"].to_numpy())
        yhat = np.log(sub["predicted"].to_numpy())
        ratio = sub["ratio"].to_numpy()
        mine = meshes[(meshes["model"] == model) & (meshes["profile"] == profile)]
        rows.append(
            {
                "model": model,
                "profile": profile,
                "samples": len(sub),
                "scale": float(sub["scale"].iloc[0]),
                "r2": 1.0 - float(np.sum((y - yhat) ** 2) / np.sum((y - y.mean()) ** 2)),
                "median_ratio": float(np.median(ratio)),
                "worst_ratio": float(ratio[np.argmax(np.abs(np.log(ratio)))]),
                "rank_rho": float(np.nanmean(mine["rank_rho"])) if mine["rank_rho"].notna().any() else float("nan"),
                "fastest_agree": int(mine["fastest_agrees"].sum()),
                "meshes": len(mine),
            }
        )
    return pd.DataFrame(rows)


def scales_of(pred: pd.DataFrame) -> dict[tuple[str, str], float]:
    """The fitted scale of each (model, profile) of :func:`weighted`'s table."""
    first = pred.drop_duplicates(["model", "profile"])
    return {(str(m), str(p)): float(v) for m, p, v in zip(first["model"], first["profile"], first["scale"])}


def per_detector(pred: pd.DataFrame) -> pd.DataFrame:
    """One row per (model, profile, detector): how well a fit's scale predicts that detector's own samples.

    ``r2`` is of log time within the detector's samples with the given scale (it may be negative: worse than
    the detector's own mean); ``median_ratio``, ``worst_ratio`` as in :func:`summary`.  A fit across the
    algorithms can explain most of the spread between them while predicting one algorithm from mesh to mesh
    poorly: this is the second question.
    """
    rows = []
    for (model, profile, det), sub in pred.groupby(["model", "profile", "detector"], sort=False):
        y = np.log(sub["seconds"].to_numpy())
        yhat = np.log(sub["predicted"].to_numpy())
        ratio = sub["ratio"].to_numpy()
        ss_tot = float(np.sum((y - y.mean()) ** 2))
        rows.append(
            {
                "model": model,
                "profile": profile,
                "detector": det,
                "samples": len(sub),
                "r2": 1.0 - float(np.sum((y - yhat) ** 2)) / ss_tot if ss_tot > 0 else float("nan"),
                "median_ratio": float(np.median(ratio)),
                "worst_ratio": float(ratio[np.argmax(np.abs(np.log(ratio)))]),
            }
        )
    columns = ["model", "profile", "detector", "samples", "r2", "median_ratio", "worst_ratio"]
    return pd.DataFrame(rows, columns=columns)
