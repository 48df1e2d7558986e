"""One unit of corpus work: one file's bytes at one subdivision level, on any worker.

:func:`audit_task` is what a Dask worker runs.  It receives the file's bytes
(the client read them: workers need no shared filesystem), writes them to a
private temporary file, loads it with :func:`silcount.mesh.io.load_mesh`,
subdivides it (:mod:`silcount.study.subdivide`) and runs every requested
detector under all the lights at once with :func:`silcount.detectors.detect_many`
(identical to :func:`~silcount.detectors.detect` light by light; every built-in
batches its lights, see its docstring), and builds its rows from each batch's
arrays (:class:`silcount.detectors.SilhouetteBatch`), with no object per light.  It returns
plain JSON-ready data and never raises for a bad mesh: the failure becomes the
result's one-line ``error`` (so one file never stops a sweep).

Decisions, named:

* **Lights** (:func:`mesh_lights`): unit directions drawn from
  ``numpy.random.default_rng(SeedSequence([seed, *sha256 words]))``, normal
  then normalised (:func:`silcount.mesh.lights.random_directions`), so a
  mesh's lights depend on ``--seed`` and its own bytes only, never on the
  other files of the sweep.  ``directional`` uses them as directions towards
  the light; ``point`` puts a light at 3x the source's bounding radius from
  its bounding-box centre along each (:func:`silcount.mesh.lights.sphere_lights`); ``both`` is the
  directional set followed by the point set along the *same* directions (a
  paired comparison).  Every subdivision level of a file gets its source's
  lights (subdivision moves no point, so centre and radius are the source's).
* **Silhouette size** per light is the reference detector's edge count
  (:func:`silcount.detectors.detect_many`, all lights in one pass), run whether or
  not ``reference`` is among the detectors; its mean and population standard
  deviation (``ddof=0``) over the lights are the mesh's
  ``silhouette_edges_mean``/``_std``.
* **Time per light** is the wall time of :func:`silcount.detectors.plain_edge_ids`
  (each algorithm's own compiled, uncounted loops, ``intended``), averaged
  over the first ``time_lights`` lights after one warm-up call per process.
  For ``gaussmap`` and ``cones`` that is their fast engine's compiled query
  (:func:`silcount.detectors.hierarchy.query.query_fast`, on one numba thread,
  its ids sorted) on the mesh's tree, which is built (or taken from the
  mesh's cache, where the counted runs left it) *before* the clock starts:
  the time is a query's, the build is not in it (its counted cost is the
  ``build`` record).  The O(E x F) loops of VnV and EESD are timed only while
  ``E x F`` is at most ``time_max_pairs``, the others only up to
  ``time_max_faces`` faces: beyond, ``null`` (one light of VnV on 86,482 faces
  would take minutes).  Every kernel runs on one numba thread while timed.
  ``time_by_light_kind`` times the first
  ``time_lights`` lights of each kind apart; ``time_per_light_s`` is the first
  kind's (with ``both``, the directional lights').
* **Edges visited** per light (each detector spec's ``visited_step``): the edges the per-light
  loop examines, from the detector's own step counts: every edge for
  ``reference``, VnV and EESD (their loops run over all of E); the sides of
  the light-facing faces (polygons, for HSD) that TA and HSD look up in S (an
  edge with both faces lit counts twice); the edges of the leaves the
  hierarchy opened for ``gaussmap`` and ``cones`` (their ``edge_test``).
  ``edges_visited_fraction`` divides by E.  Every step count is a row column
  ``steps_<step>``.
* **Build**: the per-mesh, light-independent preprocessing and its ``true``
  tally (:func:`build_record`): the trees of ``gaussmap`` and ``cones``
  (``notes['build']``, with ``tree_bytes``) and HSD's coplanar merge
  (``notes['merge']``); a query's tally never includes it.
"""

from __future__ import annotations

import hashlib
import tempfile
import time
from dataclasses import asdict, dataclass, field, replace
from functools import cache
from pathlib import Path

import numpy as np

from silcount.counting.arithmetic import KINDS
from silcount.counting.cycles import Profile, builtin_profiles, cycles_of_counts
from silcount.detectors import (
    SilhouetteBatch,
    detect_many,
    get,
    is_reference_run,
    names,
    plain_edge_ids,
    plain_setup,
    runs,
    specs,
)
from silcount.detectors.batch import ABSENT, common_many
from silcount.errors import SilcountError
from silcount.mesh.io import load_mesh
from silcount.mesh.lights import DirectionalLight, Light, PointLight, random_directions, sphere_lights
from silcount.mesh.model import Mesh
from silcount.mesh.stats import coplanar_polygons

LIGHT_KINDS = ("directional", "point", "both")
FLAT_RELATIVE = 1e-9
"""A mesh is *flat* when its vertices' smallest principal extent is at most this times the largest."""


@dataclass(frozen=True)
class Settings:
    """What each mesh is swept with; every field is part of the cache key."""

    lights: int = 64
    light_kind: str = "directional"
    seed: int = 0
    detectors: tuple[str, ...] = field(default_factory=names)  # every registered detector
    variants: tuple[str, ...] = ("intended",)
    engine: str = "fast"
    timing: bool = True
    time_lights: int = 1
    time_max_faces: int = 200_000
    time_max_pairs: int = 100_000_000
    profiles: tuple[str, ...] = field(default_factory=lambda: tuple(builtin_profiles()))

    def runs(self) -> list[tuple[str, str, str]]:
        """(key, detector, variant) per run (:func:`silcount.detectors.runs`), keys as in ``silcount audit``."""
        return runs(self.detectors, self.variants)

    def as_dict(self) -> dict:
        d = asdict(self)
        return {k: list(v) if isinstance(v, tuple) else v for k, v in d.items()}


@dataclass(frozen=True)
class Part:
    """A share of a unit (:mod:`silcount.study.parts`): some of its detectors, under its lights ``lo:hi``."""

    detectors: tuple[str, ...]
    lo: int
    hi: int


def sha256_words(sha256: str) -> list[int]:
    """The 32-byte digest as eight unsigned 32-bit words (a SeedSequence entropy)."""
    raw = bytes.fromhex(sha256)
    return [int.from_bytes(raw[i : i + 4], "little") for i in range(0, 32, 4)]


def mesh_lights(mesh: Mesh, settings: Settings, sha256: str) -> list[Light]:
    """The lights of a file (see the module docstring); ``mesh`` is the source (level 0)."""
    dirs = random_directions(settings.lights, np.random.SeedSequence([int(settings.seed), *sha256_words(sha256)]))
    out: list[Light] = []
    if settings.light_kind in ("directional", "both"):
        out += [DirectionalLight(d) for d in dirs]
    if settings.light_kind in ("point", "both"):
        out += sphere_lights(mesh, dirs)
    return out


def shape_kind(mesh: Mesh) -> str:
    """``closed`` (no boundary edge), ``flat`` (open, every vertex in one plane) or ``open``."""
    if mesh.is_closed:
        return "closed"
    centred = mesh.vertices - mesh.vertices.mean(axis=0)
    s = np.linalg.svd(centred, compute_uv=False) if mesh.n_vertices > 2 else np.zeros(3)
    return "flat" if s[-1] <= FLAT_RELATIVE * max(s[0], np.finfo(float).tiny) else "open"


def mesh_record(mesh: Mesh) -> dict:
    """The per-mesh statistics the corpus reports: those of :func:`silcount.mesh.stats.mesh_statistics` it
    keeps (the same values), computed alone; the audit's others (components, near-duplicate vertices,
    duplicate faces, areas) are not in the corpus's tables."""
    polys = coplanar_polygons(mesh)["polygons"]
    return {
        "vertices": mesh.n_vertices,
        "faces": mesh.n_faces,
        "edges": mesh.n_edges,
        "closed": bool(mesh.is_closed),
        "kind": shape_kind(mesh),
        "boundary_edges": int(mesh.boundary_edges.size),
        "nonmanifold_edges": int(mesh.nonmanifold_edges.size),
        "mean_sides": float(mesh.mean_sides),
        "coplanar_polygons": int(polys),
        "merge_ratio": mesh.n_faces / polys,
    }


def light_record(light: Light) -> dict:
    if isinstance(light, DirectionalLight):
        return {
            "light_kind": "directional",
            "light_x": light.direction[0],
            "light_y": light.direction[1],
            "light_z": light.direction[2],
        }
    return {
        "light_kind": "point",
        "light_x": light.position[0],
        "light_y": light.position[1],
        "light_z": light.position[2],
    }


def run_columns(
    results: SilhouetteBatch, refs: SilhouetteBatch, settings: Settings, profiles: dict[str, Profile], edges: int
) -> dict[str, list]:
    """One detector's batch of lights as columns (name -> one value per light), read from its arrays: edges,
    agreement with the reference ``refs`` (the same lights'), edges visited (of ``edges``), steps, tallies and
    cycles per model (each profile's :func:`~silcount.counting.cycles.cycles_of_counts` over the lights: the
    doubles ``Profile.cycles`` gives).  A ``steps_`` column holds ``None`` for a light whose run did not count
    that step (:func:`row_names`)."""
    n = len(results)
    common = common_many(results, refs)
    found = results.n_edges
    visited = results.step(get(results.detector).visited_step or "") if n else None
    seen = [None] * n if visited is None else [None if v == ABSENT else v for v in visited.tolist()]
    whole = max(edges, 1)
    cols: dict[str, list] = {
        "silhouette_edges": found.tolist(),
        "missed_edges": (refs.n_edges - common).tolist(),
        "extra_edges": (found - common).tolist(),
        "edges_visited": seen,
        "edges_visited_fraction": [None if v is None else v / whole for v in seen],
    }
    for j, step in enumerate(results.step_names):
        cols[f"steps_{step}"] = [None if v == ABSENT else v for v in results.steps[:, j].tolist()]
    tallies = {"true": (results.kinds, results.true)}
    if n and results.paper_model is not None:
        tallies["paper"] = results.paper_counts()
    for model in sorted(tallies) if n else ():
        kinds, counts = tallies[model]
        for j, k in enumerate(KINDS):  # KINDS lead every batch's kinds, never absent
            cols[f"{model}_{k}"] = counts[:, j].tolist()
        cols[f"{model}_total"] = counts[:, : len(KINDS)].sum(axis=1).tolist()
        weighed = cycles_of_counts([profiles[p] for p in settings.profiles], kinds, counts)
        for p, column in zip(settings.profiles, weighed, strict=True):
            cols[f"{model}_cycles_{p}"] = column.tolist()
    return cols


def row_names(cols: dict[str, list], results: SilhouetteBatch) -> list[tuple[str, ...]]:
    """Each light's row keys, sorted: the run's ``cols`` but the ``steps_`` its run did not count."""
    own: dict[tuple[bool, ...], tuple[str, ...]] = {}  # by the steps counted: one entry in practice
    out = []
    for counted in map(tuple, (results.steps != ABSENT).tolist()):
        if counted not in own:
            mine = {s for s, c in zip(results.step_names, counted, strict=True) if c}
            own[counted] = tuple(sorted(k for k in cols if not k.startswith("steps_") or k[6:] in mine))
        out.append(own[counted])
    return out


def interleave(runs: list[tuple[dict[str, list], list[tuple[str, ...]]]], n_lights: int) -> dict:
    """The unit's rows, light by light and each light's runs in order, as :func:`row_columns` gives them.

    ``runs``: each run's columns (one value per light) and each light's own names, sorted (a row's keys);
    the columns are every row's names in order of first appearance, a name a row lacks read as ``None``.
    """
    own = dict.fromkeys(names[i] for i in range(n_lights) for _, names in runs)  # each distinct key list once
    columns = list(dict.fromkeys(k for names in own for k in names))
    blank = [None] * n_lights
    values = [[v for group in zip(*(cols.get(k, blank) for cols, _ in runs)) for v in group] for k in columns]
    return {"columns": columns, "values": values}


def build_record(notes: dict) -> dict | None:
    """A run's per-mesh preprocessing from a light's ``notes``: ``{"true": kind -> count, "steps", "tree_bytes",
    ...}``, or ``None``.

    ``gaussmap``/``cones``: their tree (``notes['build']``, ``build_steps``, ``tree_bytes``, ``leaf_size``,
    ``fanout``); HSD: its coplanar merge (``notes['merge']``'s ``true`` tally and steps).
    """
    if "build" in notes:
        keep = ("tree_bytes", "leaf_size", "fanout")
        return {"true": dict(notes["build"]), "steps": dict(notes["build_steps"]), **{k: notes[k] for k in keep}}
    merged = notes.get("merge")
    if isinstance(merged, dict) and "true" in merged:
        return {"true": dict(merged["true"]), "steps": dict(merged.get("steps", {}))}
    return None


@cache
def _warm_up() -> None:
    """Compile (or load from numba's cache) every plain kernel and query once per process, outside the timings."""
    from silcount.mesh.shapes import icosphere

    mesh = icosphere(1)
    for light in (DirectionalLight((0.3, 0.5, 0.8)), PointLight((3.0, 2.0, 5.0))):
        for spec in specs():
            if spec.plain_edge_ids is not None:
                spec.plain_edge_ids(mesh, light)


def time_per_light(mesh: Mesh, lights: list[Light], settings: Settings) -> tuple[dict[str, float | None], list[str]]:
    """Mean seconds per light of each detector's plain loops (``None`` past the limits; see the docstring),
    and the timings that failed (``None`` too, named); every kernel on one numba thread."""
    import numba

    threads = numba.get_num_threads()
    numba.set_num_threads(1)  # the reference's chunked kernels would otherwise run in parallel above 65,536
    try:
        return _time_per_light(mesh, lights, settings)
    finally:
        numba.set_num_threads(threads)


def _time_per_light(mesh: Mesh, lights: list[Light], settings: Settings) -> tuple[dict[str, float | None], list[str]]:
    out: dict[str, float | None] = {}
    errors: list[str] = []
    sample = lights[: max(settings.time_lights, 1)]
    for name in settings.detectors:
        spec = get(name)
        cost = mesh.n_edges * mesh.n_faces if spec.plain_quadratic else mesh.n_faces
        limit = settings.time_max_pairs if spec.plain_quadratic else settings.time_max_faces
        if not settings.timing or cost > limit or not sample or spec.plain_edge_ids is None:
            out[name] = None
            continue
        _warm_up()
        plain_setup(mesh, name)  # a per-mesh build or merge, outside the clock (cached with the mesh)
        t0 = time.perf_counter()
        try:
            for light in sample:
                plain_edge_ids(mesh, light, name)
        except ZeroDivisionError:  # plain EESD's inlined ray test divides by a zero determinant (grazing ray)
            out[name] = None
            errors.append(f"{name}: ZeroDivisionError in the plain loops")
            continue
        out[name] = (time.perf_counter() - t0) / len(sample)
    return out, errors


def _audit(
    mesh: Mesh, level: int, lights: list[Light], settings: Settings, first: int = 0, timed: list[Light] | None = None
) -> dict:
    """The unit's record and rows; ``lights`` are the unit's lights ``first:`` (a part's), ``timed`` those whose
    first ones are timed (default ``lights``)."""
    from silcount.study.subdivide import subdivide

    mesh = subdivide(mesh, level)
    record = mesh_record(mesh)
    profiles = builtin_profiles()
    refs = detect_many(mesh, lights, "reference")  # every light in one pass; identical to detect per light
    silhouettes = refs.n_edges.astype(np.float64)
    record["lights"] = len(lights)
    record["silhouette_edges_mean"] = float(silhouettes.mean())
    record["silhouette_edges_std"] = float(silhouettes.std())
    lit = [light_record(light) for light in lights]
    per_light: dict[str, list] = {"light": list(range(first, first + len(lights)))}
    per_light.update({k: [r[k] for r in lit] for k in lit[0]} if lit else {})
    per_light["reference_edges"] = refs.n_edges.tolist()
    runs: list[tuple[dict[str, list], list[tuple[str, ...]]]] = []
    builds: dict[str, dict] = {}
    for key, name, variant in settings.runs():  # each detector over every light at once (detect_many)
        if is_reference_run(name, settings.engine):
            results = refs
        else:
            results = detect_many(mesh, lights, name, variant=variant, engine=settings.engine)
        cols = run_columns(results, refs, settings, profiles, mesh.n_edges)
        cols.update(per_light, detector=[key] * len(lights), variant=[variant] * len(lights))
        runs.append((cols, row_names(cols, results)))
        if len(results) and (built := build_record(results.light_notes_of(0))) is not None:
            builds[key] = built  # light-independent: the first light's
    record["build"] = builds
    by_kind: dict[str, dict[str, float | None]] = {}
    record["time_errors"] = []
    timed = lights if timed is None else timed
    timed_kinds = [light_record(light)["light_kind"] for light in timed]
    kinds = list(dict.fromkeys(timed_kinds))
    for kind in kinds:
        same = [light for light, k in zip(timed, timed_kinds, strict=True) if k == kind]
        by_kind[kind], errors = time_per_light(mesh, same, settings)
        record["time_errors"] += [f"{kind} lights: {e}" if len(kinds) > 1 else e for e in errors]
    record["time_by_light_kind"] = by_kind
    record["time_per_light_s"] = next(iter(by_kind.values()), {d: None for d in settings.detectors})
    return {"mesh": record, "rows": interleave(runs, len(lights))}


def row_columns(rows: list[dict]) -> dict:
    """``rows`` as ``{"columns": [name, ...], "values": [[value per row], ...]}``.

    A unit's result crosses a process boundary (pickle) and the cache (JSON): one list per column costs a
    fraction of one dict per row to move and to read back into a frame.  ``columns`` is every row's keys,
    each row's sorted, in order of first appearance (a list, so JSON's sorted keys cannot reorder it); a row
    without a column holds ``None`` there, read as missing.  Only the ``steps_`` columns are missing from some
    rows (each detector has its own steps), and they are never ``None`` themselves, so nothing is lost.
    """
    names = list(dict.fromkeys(k for row in rows for k in sorted(row)))
    return {"columns": names, "values": [[row.get(k) for row in rows] for k in names]}


def audit_task(label: str, data: bytes, level: int, settings: Settings, part: Part | None = None) -> dict:
    """Audit one file's bytes at one subdivision level; ``{"mesh", "rows", "error"}``, never raising for bad input.

    ``rows`` is columnar (:func:`row_columns`).  A ``part`` runs only its detectors under its lights (the
    reference always runs; the first lights are timed only in the part that starts at light 0), and
    :func:`silcount.study.parts.merge` joins the parts into the unit's result.

    ``label`` is the file's name in the sweep (its suffix picks the loader; it
    replaces the temporary path in error messages).
    """
    sha = hashlib.sha256(data).hexdigest()
    try:
        with tempfile.TemporaryDirectory(prefix="silcount-corpus-") as tmp:
            path = Path(tmp) / Path(label).name
            path.write_bytes(data)
            try:
                source = load_mesh(path)
            except SilcountError as exc:
                raise type(exc)(str(exc).replace(str(path), label)) from None
        lights = mesh_lights(source, settings, sha)
        if part is None:
            result = _audit(source, level, lights, settings)
        else:
            own = replace(settings, detectors=part.detectors)
            result = _audit(source, level, lights[part.lo : part.hi], own, part.lo, lights if part.lo == 0 else [])
        result["error"] = None
    except Exception as exc:  # recorded as this mesh's error row, never dropped: the sweep goes on
        text = " ".join(str(exc).split()) or type(exc).__name__
        error = text if isinstance(exc, SilcountError) else f"{type(exc).__name__}: {text}"
        result = {"mesh": {}, "rows": row_columns([]), "error": error}
    result["sha256"] = sha
    result["level"] = level
    return result
