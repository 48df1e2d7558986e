"""The papers' detectors beside the literature's: per light kind means, output-sensitivity fits, findings.

The papers (HSD 2011, EESD 2012) rank TA, VnV, HSD and EESD among
themselves; ``gaussmap`` (Gooch et al., I3D 1999) and ``cones`` (Johnson and
Cohen, I3D 2001; Sander et al., SIGGRAPH 2000) are the output-sensitive
detectors the literature already had, and ``reference`` silcount's O(E) yardstick
(``docs/literature.md``).  Everything here is computed on the client from the
sweep's tables (nothing is cached apart from them):

* :func:`kind_frame`: one row per (mesh, level, light kind, ``intended`` run)
  with the means per light of ``s`` (the silhouette, reference edges), the
  ``true`` and ``paper`` totals, edges visited and their fraction of E, the
  hierarchy's ``edges tested`` (``steps_edge_test``), the time per light of
  that light kind and the run's per-mesh ``build`` total.
* :func:`output_fits`: for ``gaussmap`` and ``cones`` and each light kind,
  edges tested per light (``steps_edge_test``, mean per mesh) against ``s``,
  against ``F`` and against ``s log2 F``
  (:func:`silcount.study.fits.power_fit`: least squares in log-log, bootstrap
  interval over meshes), named ``<detector>:<light kind>:edge_test~s``,
  ``~F`` and ``~s_log2F``.  An exponent of 1 against ``s log2 F`` is the
  ``O(s log F)`` the hierarchies are built for; against ``F``, 1 is no
  better than testing every edge.
* :func:`band_table` and :func:`findings`, for :mod:`.literature_page`.

Size bands are decades of F (``100-999`` ...).  A band's value is the
*median over its meshes* of each mesh's mean per light; a time is the median
over the band's meshes that were timed, with ``(timed/meshes)`` when some were
not (past the limits of :mod:`.work`, or a sweep without times).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from silcount.detectors import get, with_role
from silcount.study.fits import power_fit

if TYPE_CHECKING:
    import pandas as pd

    from silcount.study.work import Settings


def yardsticks() -> tuple[str, ...]:
    """The detectors set beside the papers': the yardsticks (the reference first), then the literature's."""
    return (*with_role("yardstick"), *with_role("literature"))


def order() -> tuple[str, ...]:
    """Every registered detector in the pages' order: the papers', then :func:`yardsticks`."""
    return (*with_role("paper"), *yardsticks())


def label(det: str) -> str:
    """How tables and figures name detector ``det``."""
    return get(det).label


CLAIMS = (("hsd", "ta"), ("hsd", "vnv"), ("eesd", "ta"), ("eesd", "vnv"))
"""The orderings the papers' conclusions rank (HSD 2011 Sec. VII; EESD 2012 Sec. 6): first below second."""
AGAINST = {"s": "s", "F": "F", "s_log2F": "s log2 F"}
KEYS = ["file", "level", "light_kind"]


def size_of(frame: pd.DataFrame, against: str) -> np.ndarray:
    s, faces = frame["s"].to_numpy(float), frame["faces"].to_numpy(float)
    if against == "s":
        return s
    if against == "F":
        return faces
    return s * np.log2(np.maximum(faces, 1.0))


def kind_frame(rows: pd.DataFrame, meshes: pd.DataFrame, settings: Settings) -> pd.DataFrame:
    """Per (file, level, light kind, detector) means per light; see the module docstring."""
    import pandas as pd

    intended = [key for key, name, variant in settings.runs() if variant == "intended" and name in order()]
    cols = ["file", "level", "light_kind", "detector", "s", "true_ops", "paper_ops", "visited", "visited_fraction"]
    cols += ["edge_test", "faces", "edges", "kind", "time_s", "build_total"]
    if rows.empty:
        return pd.DataFrame(columns=cols)
    part = rows[rows["detector"].isin(intended)]
    named = {
        "reference_edges": "s",
        "true_total": "true_ops",
        "paper_total": "paper_ops",
        "edges_visited": "visited",
        "edges_visited_fraction": "visited_fraction",
        "steps_edge_test": "edge_test",
    }
    have = {c: n for c, n in named.items() if c in part}
    out = part.groupby(KEYS + ["detector"], sort=False)[list(have)].mean().rename(columns=have).reset_index()
    info = meshes[meshes["error"] == ""].set_index(["file", "level"])
    out = out.merge(info[["faces", "edges", "kind"]], left_on=["file", "level"], right_index=True, how="inner")

    def lookup(rec: dict, column: str):
        key = (rec["file"], rec["level"])
        value = info[column][key] if column in info and key in info.index else None
        return None if value is None or value != value else float(value)

    recs = out.to_dict(orient="records")
    out["time_s"] = [lookup(r, f"time_per_light_s:{r['light_kind']}:{r['detector']}") for r in recs]
    out["build_total"] = [lookup(r, f"{r['detector']}:build_total") for r in recs]
    for c in cols:
        if c not in out:
            out[c] = np.nan
    out["_order"] = out["detector"].map(order().index)
    out = out.sort_values(KEYS + ["_order"], kind="stable").drop(columns="_order")
    return out[cols].reset_index(drop=True)


def output_fits(rows: pd.DataFrame, meshes: pd.DataFrame, settings: Settings) -> dict[str, dict]:
    """``<detector>:<light kind>:edge_test~<x>`` for ``gaussmap`` and ``cones``, x in ``s``, ``F``, ``s log2 F``."""
    frame = kind_frame(rows, meshes, settings)
    out: dict[str, dict] = {}
    for det in with_role("literature"):
        for kind in sorted(set(frame["light_kind"])):
            part = frame[(frame["detector"] == det) & (frame["light_kind"] == kind)]
            if part.empty:
                continue
            for key, against in AGAINST.items():
                what = f"every mesh, {kind} lights, edges tested per light"
                x = size_of(part, against)
                out[f"{det}:{kind}:edge_test~{key}"] = power_fit(x, part["edge_test"], what, against)
    return out


def decade(faces: float) -> int:
    """``floor(log10 F)`` (0 for ``F <= 1``)."""
    return int(math.floor(math.log10(max(float(faces), 1.0))))


def band_of(faces: float) -> str:
    """The decade of ``faces``: ``"1,000-9,999"``."""
    lo = 10 ** decade(faces)
    return f"{lo:,}-{10 * lo - 1:,}"


def band_table(frame: pd.DataFrame) -> list[dict]:
    """Per (band, light kind): ``{"band", "light_kind", "meshes", "detectors": {det: {"true_ops", ...}}}``,
    bands by increasing F, each value the median over the band's meshes (``timed``: how many had a time)."""
    out = []
    frame = frame.assign(band=frame["faces"].map(band_of), decade=frame["faces"].map(decade))
    seen = frame.sort_values(["decade", "light_kind"], kind="stable").drop_duplicates(["band", "light_kind"])
    for band, kind in zip(seen["band"], seen["light_kind"]):
        part = frame[(frame["band"] == band) & (frame["light_kind"] == kind)]
        dets = {}
        for det in order():
            d = part[part["detector"] == det]
            if d.empty:
                continue
            times = d["time_s"].dropna()
            dets[det] = {
                "true_ops": float(d["true_ops"].median()),
                "visited_fraction": float(d["visited_fraction"].median()),
                "time_s": float(times.median()) if len(times) else None,
                "timed": int(len(times)),
                "meshes": int(len(d)),
            }
        out.append({"band": band, "light_kind": kind, "meshes": int(part[KEYS].drop_duplicates().shape[0]),
                    "detectors": dets})  # fmt: skip
    return out


def _names(dets) -> str:
    names = [label(d) for d in dets]
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _unit(n_kinds: int) -> str:
    return "meshes" if n_kinds == 1 else "(mesh, light kind) pairs"


def _compare(wide: pd.DataFrame, low: str, high: str, what: str, unit: str) -> str | None:
    pair = wide[[low, high]].dropna() if low in wide and high in wide else None
    if pair is None or pair.empty:
        return None
    wins = int((pair[low] < pair[high]).sum())
    ratio = float((pair[low] / pair[high]).median())
    return f"in {what} on {wins} of {len(pair)} {unit} (median {label(low)}/{label(high)} {ratio:.3g})"


def _best_paper(wide: pd.DataFrame, frame: pd.DataFrame, what: str, unit: str) -> str | None:
    papers = [d for d in with_role("paper") if d in wide]
    yard = [d for d in yardsticks() if d in wide]
    if not papers or not yard:
        return None
    both = wide[papers + yard].dropna()
    if both.empty:
        return None
    best_paper, best_yard = both[papers].min(axis=1), both[yard].min(axis=1)
    beat = both[best_paper < best_yard]
    text = f"{what}: the lowest of {_names(papers)} below the lowest of {_names(yard)} on {len(beat)} of "
    text += f"{len(both)} {unit}"
    if len(beat):
        faces = frame.drop_duplicates(KEYS).set_index(KEYS)["faces"]
        who = beat[papers].idxmin(axis=1)
        cases = [f"{idx[0]} ({label(who[idx])}, {int(faces[idx]):,} faces)" for idx in beat.index[:6]]
        text += ": " + "; ".join(cases) + (" ..." if len(beat) > 6 else "")
    ratio = float((best_paper / best_yard).median())
    return text + f"; the lowest of the first four over the lowest of the others: median {ratio:.3g}x."


def _fewest(ops: pd.DataFrame) -> str:
    """Who needs the fewest operations, mesh by mesh, a tie named as one ('a tie of A and B'), most first."""
    best = ops.eq(ops.min(axis=1), axis=0)
    ranked = [d for d in order() if d in best]
    counts: dict[tuple[str, ...], int] = {}
    for row in best[ranked].itertuples(index=False):
        who = tuple(d for d, won in zip(ranked, row) if won)
        counts[who] = counts.get(who, 0) + 1
    parts = []
    for who, n in sorted(counts.items(), key=lambda kv: (-kv[1], [ranked.index(d) for d in kv[0]])):
        names = [label(d) for d in who]
        named = names[0] if len(names) == 1 else "a tie of " + ", ".join(names[:-1]) + " and " + names[-1]
        parts.append(f"{named} on {int(n)}")
    return ", ".join(parts) + f" of {len(ops)}"


def findings(frame: pd.DataFrame, fits: dict, timed: bool) -> list[str]:
    """The findings paragraph's sentences, each computed from ``frame`` (:func:`kind_frame`) and ``fits``."""
    out: list[str] = []
    if frame.empty:
        return ["No mesh was audited: nothing to compare."]
    unit = _unit(frame["light_kind"].nunique())
    ops = frame.pivot_table(index=KEYS, columns="detector", values="true_ops", aggfunc="first")
    times = frame.pivot_table(index=KEYS, columns="detector", values="time_s", aggfunc="first")
    for low, high in CLAIMS:
        parts = [_compare(ops, low, high, "true operations per light", unit)]
        parts += [_compare(times, low, high, "time per light", f"timed {unit}")] if timed else []
        found = [p for p in parts if p]
        if found:
            out.append(f"{label(low)} below {label(high)}: " + "; ".join(found) + ".")
    line = _best_paper(ops, frame, "True operations per light", unit)
    out += [line] if line else []
    if timed:
        line = _best_paper(times, frame, "Time per light", f"timed {unit}")
        out += [line] if line else []
    else:
        out.append("Times: not measured in this sweep (`silcount report` writes none, so that its output is "
                   "byte-identical; `silcount corpus ... --out DIR` measures them).")  # fmt: skip
    out.append(f"Fewest true operations per light: {_fewest(ops.dropna(how='all'))} {unit}.")
    for det in with_role("literature"):
        for kind in sorted(set(frame["light_kind"])):
            out += _sensitivity(det, kind, frame, fits)
    return out


def _sensitivity(det: str, kind: str, frame: pd.DataFrame, fits: dict) -> list[str]:
    got: dict[str, dict] = {key: fits.get(f"{det}:{kind}:edge_test~{key}") or {} for key in AGAINST}
    if not all(f.get("alpha") is not None for f in got.values()):
        return []

    def show(key: str) -> str:
        f = got[key]
        ci = f["alpha_ci"] or (float("nan"), float("nan"))
        x = AGAINST[key] if key in ("s", "F") else f"({AGAINST[key]})"
        return f"{x}^{f['alpha']:.2f} [{ci[0]:.2f}, {ci[1]:.2f}]"

    def verdict(key: str, what: str) -> str:
        lo, hi = got[key]["alpha_ci"] or (float("nan"), float("nan"))
        return f"consistent with {what}" if lo <= 1.0 <= hi else f"{'below' if hi < 1.0 else 'above'} {what}"

    part = frame[(frame["detector"] == det) & (frame["light_kind"] == kind)]
    text = (
        f"{label(det)}, {kind} lights: edges tested per light grow as {show('s')}, {show('F')} and "
        f"{show('s_log2F')} (95% intervals: {verdict('s_log2F', 'O(s log F)')}; "
        f"{verdict('F', 'a fixed share of the edges (linear in F)')}); "
        f"median {part['visited_fraction'].median():.3g} of E tested"
    )
    ref = frame[(frame["detector"] == "reference") & (frame["light_kind"] == kind)].set_index(KEYS)["true_ops"]
    mine = part.set_index(KEYS)
    saving = (ref.reindex(mine.index) - mine["true_ops"]).to_numpy(float)
    build = mine["build_total"].to_numpy(float)
    pays = saving > 0
    if pays.any() and np.isfinite(build[pays]).all():
        even = np.ceil(build[pays] / saving[pays])
        text += (
            f"; build plus queries cost fewer true operations than the reference's queries after a median of "
            f"{np.median(even):.0f} lights, on the {int(pays.sum())} of {len(mine)} meshes where its query is "
            f"the cheaper"
        )
    return [text + "."]
