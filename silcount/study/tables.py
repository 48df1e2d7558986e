"""The corpus's tables and JSON document, built from the units' results (client side, pandas).

* **rows** (``corpus.parquet``): one row per mesh x light x detector run:
  ``file, level, sha256, faces, light, light_kind, light_x/y/z`` (the
  direction towards a directional light, the position of a point light),
  ``detector`` (``ta``, ``ta:literal``, ...), ``variant``, ``reference_edges``
  (the silhouette size under that light), ``silhouette_edges`` (what the
  detector found), ``missed_edges``/``extra_edges`` against the reference,
  ``edges_visited`` and ``edges_visited_fraction`` (of E; see
  each detector spec's ``visited_step``), ``steps_<step>`` (the
  detector's own step counts, empty for the steps of other detectors), then
  per cost model ``M`` (``paper``, ``true``) the counts ``M_add`` ...
  ``M_write``, their sum ``M_total`` and ``M_cycles_<profile>`` per cycle
  profile.
* **meshes** (``meshes.csv``): one row per mesh and level: the statistics of
  :func:`silcount.study.work.mesh_record`, ``silhouette_edges_mean``/``_std``,
  ``time_per_light_s:<detector>`` and ``time_per_light_s:<light kind>:<detector>``,
  per run ``<run>:<column>`` the *mean per light* of every count, step and cycle
  column above, and for a run with a per-mesh preprocessing (the trees of
  ``gaussmap`` and ``cones``, HSD's merge) ``<run>:build_<kind>``,
  ``<run>:build_total`` (its ``true`` tally, once per mesh) and
  ``<run>:tree_bytes``; ``error`` (empty when the mesh was audited).
* **fits**: :func:`fits` (see :mod:`silcount.study.fits`).

Rows are sorted by file, level, light and the settings' run order, so the
tables do not depend on the scheduler, the worker count or completion order.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from silcount.study.fits import power_fit
from silcount.study.literature import output_fits
from silcount.study.work import Settings
from silcount.version import __version__

if TYPE_CHECKING:
    import pandas as pd

SCHEMA = "silcount-corpus/1"
MESH_FIELDS = (
    "vertices",
    "faces",
    "edges",
    "closed",
    "kind",
    "boundary_edges",
    "nonmanifold_edges",
    "mean_sides",
    "coplanar_polygons",
    "merge_ratio",
    "lights",
    "silhouette_edges_mean",
    "silhouette_edges_std",
)
INT_FIELDS = (
    "level",
    "vertices",
    "faces",
    "edges",
    "boundary_edges",
    "nonmanifold_edges",
    "coplanar_polygons",
    "lights",
)
PER_RUN = ("silhouette_edges", "missed_edges", "extra_edges")
VISITED = ("edges_visited", "edges_visited_fraction")


def rows_frame(labels: list[str], results: list[dict]) -> pd.DataFrame:
    """The per-(mesh, light, run) table from the units' columnar rows; meshes that failed have no rows here.

    Columns: ``file, level, sha256, faces``, then the units' columns in order of first appearance (a cached
    result and a fresh one list them alike); a unit without a column holds ``None`` there.
    """
    import pandas as pd

    parts = []
    for label, res in zip(labels, results):
        given = dict(zip(res["rows"]["columns"], res["rows"]["values"]))
        n = len(next(iter(given.values()), []))
        if n:
            head = {"file": label, "level": res["level"], "sha256": res["sha256"], "faces": res["mesh"].get("faces")}
            parts.append((n, {**{k: [v] * n for k, v in head.items()}, **given}))
    if not parts:
        return pd.DataFrame.from_records([])  # no rows, no columns (an object index, as for an empty record list)
    names = list(dict.fromkeys(k for _, part in parts for k in part))
    frame = pd.DataFrame({k: [v for n, part in parts for v in part.get(k, [None] * n)] for k in names})
    return frame.sort_values(["file", "level", "light"], kind="stable").reset_index(drop=True)


def value_columns(rows: pd.DataFrame) -> list[str]:
    """The count and cycle columns (``paper_add`` ... ``true_cycles_unit``), in table order."""
    return [c for c in rows.columns if c.startswith(("paper_", "true_"))]


def step_columns(rows: pd.DataFrame) -> list[str]:
    """The ``steps_<step>`` columns, in table order."""
    return [c for c in rows.columns if c.startswith("steps_")]


def _build_columns(run: str, build: dict | None) -> dict:
    if not build:
        return {}
    out = {f"{run}:build_{k}": int(v) for k, v in sorted(build["true"].items())}
    out[f"{run}:build_total"] = int(sum(build["true"].values()))
    if "tree_bytes" in build:
        out[f"{run}:tree_bytes"] = int(build["tree_bytes"])
    return out


def meshes_frame(labels: list[str], results: list[dict], rows: pd.DataFrame, settings: Settings) -> pd.DataFrame:
    """One row per (file, level): statistics, silhouette size, times, mean tallies per light, error."""
    import pandas as pd

    runs = [key for key, _, _ in settings.runs()]
    means = {}
    if not rows.empty:
        cols = list(PER_RUN) + [c for c in VISITED if c in rows] + step_columns(rows) + value_columns(rows)
        grouped = rows.groupby(["file", "level", "detector"], sort=False)[cols].mean()
        means = {idx: grouped.loc[idx].dropna() for idx in grouped.index}  # a run's own steps only
    records = []
    for label, res in zip(labels, results):
        mesh = res["mesh"]
        rec = {"file": label, "level": res["level"], "sha256": res["sha256"]}
        rec.update({k: mesh.get(k) for k in MESH_FIELDS})
        times = mesh.get("time_per_light_s") or {}
        rec.update({f"time_per_light_s:{d}": times.get(d) for d in settings.detectors})
        for kind, kind_times in (mesh.get("time_by_light_kind") or {}).items():
            rec.update({f"time_per_light_s:{kind}:{d}": kind_times.get(d) for d in settings.detectors})
        rec["time_errors"] = "; ".join(mesh.get("time_errors") or [])
        for run in runs:
            m = means.get((label, res["level"], run))
            if m is not None:
                rec.update({f"{run}:{c}": float(v) for c, v in m.items()})
                rec.update(_build_columns(run, (mesh.get("build") or {}).get(run)))
        rec["error"] = res.get("error") or ""
        records.append(rec)
    frame = pd.DataFrame.from_records(records)
    return frame.sort_values(["file", "level"], kind="stable").reset_index(drop=True)


def fits(meshes: pd.DataFrame, settings: Settings, rows: pd.DataFrame | None = None) -> dict[str, dict]:
    """``silhouette_edges`` (every mesh), ``silhouette_edges:closed``, the same over sources only
    (``:level0``, when the sweep subdivides), ``<run>:<model>`` (total operations per light, every mesh),
    and with ``rows`` the output-sensitivity fits of :func:`silcount.study.literature.output_fits`."""
    ok = meshes[meshes["error"] == ""]
    out = {}
    subsets = [("", ok, "every mesh"), (":closed", ok[ok["closed"].astype(bool)], "closed meshes")]
    if (ok["level"] > 0).any():
        src = ok[ok["level"] == 0]
        subsets += [
            (":level0", src, "sources (level 0)"),
            (":closed:level0", src[src["closed"].astype(bool)], "closed sources (level 0)"),
        ]
    for suffix, part, what in subsets:
        out[f"silhouette_edges{suffix}"] = power_fit(part["faces"], part["silhouette_edges_mean"], what)
    for run, _, _ in settings.runs():
        for model in ("paper", "true"):
            col = f"{run}:{model}_total"
            if col in ok:
                out[f"{run}:{model}"] = power_fit(ok["faces"], ok[col], f"every mesh, {model} model")
    if rows is not None and not rows.empty:
        out.update(output_fits(rows, meshes, settings))
    return out


def _clean(value, integer: bool = False):
    """JSON-ready: numpy scalars to Python, NaN to None, ``integer`` columns (float after a missing value) to int."""
    if hasattr(value, "item"):
        value = value.item()
    if isinstance(value, float) and value != value:
        return None
    return int(value) if integer and value is not None else value


def mesh_documents(meshes: pd.DataFrame, rows: pd.DataFrame, settings: Settings) -> list[dict]:
    """``meshes`` of the JSON document: the table's row, with per-run values nested by model."""
    values = value_columns(rows) if not rows.empty else []
    docs = []
    for rec in meshes.to_dict(orient="records"):
        doc = {k: _clean(rec[k], k in INT_FIELDS) for k in ("file", "level", "sha256", *MESH_FIELDS)}
        doc["time_per_light_s"] = {d: _clean(rec[f"time_per_light_s:{d}"]) for d in settings.detectors}
        columns = [str(c) for c in rec]
        kinds = sorted({c.split(":")[1] for c in columns if c.count(":") == 2 and c.startswith("time_per_light_s:")})
        doc["time_by_light_kind"] = {
            kind: {d: _clean(rec.get(f"time_per_light_s:{kind}:{d}")) for d in settings.detectors} for kind in kinds
        }
        doc["time_errors"] = rec["time_errors"]
        doc["detectors"] = {}
        for run, _, _ in settings.runs():
            if rec.get(f"{run}:silhouette_edges") is None or rec["error"]:
                continue
            entry: dict = {k: _clean(rec[f"{run}:{k}"]) for k in PER_RUN}
            entry.update({k: _clean(rec.get(f"{run}:{k}")) for k in VISITED})
            steps = {c[len("steps_") :]: _clean(rec.get(f"{run}:{c}")) for c in step_columns(rows)}
            entry["steps"] = {k: v for k, v in steps.items() if v is not None}
            for model in ("paper", "true"):
                cols = [c for c in values if c.startswith(f"{model}_")]
                # a detector without this cost model (no paper model): its values empty (None)
                entry[model] = {c[len(model) + 1 :]: _clean(rec.get(f"{run}:{c}")) for c in cols}
            build = _clean(rec.get(f"{run}:build_total"))
            if build is not None:
                built = [c for c in columns if c.startswith(f"{run}:build_") and _clean(rec[c]) is not None]
                entry["build"] = {c[len(f"{run}:build_") :]: _clean(rec[c], True) for c in built}
                entry["tree_bytes"] = _clean(rec.get(f"{run}:tree_bytes"), True)
            doc["detectors"][run] = entry
        doc["error"] = rec["error"] or None
        docs.append(doc)
    return docs


def document(meshes: pd.DataFrame, rows: pd.DataFrame, fit: dict, settings: Settings, levels: list[int]) -> dict:
    """The ``silcount-corpus/1`` object (``docs/schemas/corpus.schema.json``)."""
    return {
        "schema": SCHEMA,
        "silcount_version": __version__,
        "settings": {**settings.as_dict(), "subdivide": list(levels)},
        "meshes": mesh_documents(meshes, rows, settings),
        "fits": fit,
    }
