"""`silcount corpus`: subdivision, lights, fits, error rows, the cache, the JSON schema, the CLI (in-process).

Expected values come from hand counts (subdivision sizes, a doubled
silhouette), from a synthetic power law (fits) and from a second run of the
same sweep (cache, scheduler).  The real-cluster test is ``test_corpus_cluster.py``.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from silcount.detectors import DETECTORS
from silcount.detectors.adjacency import silhouette_edge_ids
from silcount.mesh.io import load_mesh
from silcount.mesh.lights import DirectionalLight, PointLight
from silcount.mesh.model import from_polygons
from silcount.mesh.shapes import icosphere, plane, quad_cube
from silcount.mesh.stats import mesh_statistics
from silcount.study import corpus, find_files
from silcount.study import schedule as schedule_mod
from silcount.study.fits import power_fit
from silcount.study.subdivide import faces_after, subdivide
from silcount.study.tables import rows_frame
from silcount.study.work import Settings, interleave, mesh_lights, mesh_record, row_columns, shape_kind

DATA = Path(__file__).resolve().parent.parent / "data"
SCHEMA = Path(__file__).resolve().parent.parent / "docs" / "schemas" / "corpus.schema.json"
SMALL = dict(lights=3, timing=False, quiet=True, scheduler="threads", workers=1)

LITERATURE = ("gaussmap", "cones")  # the literature's hierarchies (docs/literature.md)


@pytest.fixture
def folder(tmp_path) -> Path:
    d = tmp_path / "meshes"
    (d / "sub").mkdir(parents=True)
    for name in ("tetrahedron.obj", "quad_cube.obj", "icosphere1.obj"):
        shutil.copy(DATA / name, d / name)
    shutil.copy(DATA / "plane.obj", d / "sub" / "plane.obj")
    (d / "notes.txt").write_text("not a mesh, not swept")
    return d


def prism(n: int = 5):
    """A closed n-gonal prism: two n-gon caps and n quads, outward wound."""
    ang = 2 * np.pi * np.arange(n) / n
    verts = [(np.cos(a), np.sin(a), z) for z in (0.0, 1.0) for a in ang]
    bottom, top = list(range(n))[::-1], list(range(n, 2 * n))
    sides = [[i, (i + 1) % n, n + (i + 1) % n, n + i] for i in range(n)]
    return from_polygons(verts, [bottom, top, *sides])


# ---- subdivision -----------------------------------------------------------------------------
def test_triangle_subdivision_sizes_by_hand():
    m = icosphere(1)  # V 42, F 80, E 120
    s = subdivide(m, 1)
    assert (s.n_vertices, s.n_faces, s.n_edges) == (42 + 120, 4 * 80, 2 * 120 + 3 * 80)
    assert s.is_closed and s.is_consistently_wound and s.mean_sides == 3.0
    assert faces_after(m, 2) == subdivide(m, 2).n_faces == 16 * 80


def test_polygons_become_quads():
    cube = subdivide(quad_cube(), 1)  # each quad -> 4 quads around its centre
    assert (cube.n_faces, cube.n_vertices, cube.mean_sides) == (24, 8 + 12 + 6, 4.0)
    p = prism(5)  # 2 pentagons -> 5 quads each, 5 quads -> 4 each
    s = subdivide(p, 1)
    assert s.n_faces == faces_after(p, 1) == 2 * 5 + 5 * 4 and s.mean_sides == 4.0
    assert s.is_closed and s.is_consistently_wound and s.nonmanifold_edges.size == 0


def test_flat_subdivision_exactly_doubles_the_silhouette():
    """No point moves, so the new edges join coplanar faces: each silhouette edge splits in two."""
    for mesh in (icosphere(2), prism(7)):
        for light in (DirectionalLight((0.31, 0.52, 0.79)), PointLight((2.9, -3.3, 4.1))):
            n0 = silhouette_edge_ids(mesh, light).size
            assert silhouette_edge_ids(subdivide(mesh, 1), light).size == 2 * n0 > 0


def test_shape_kinds():
    assert shape_kind(icosphere(1)) == "closed"
    assert shape_kind(plane()) == "flat"
    bent = from_polygons([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 1)], [[0, 1, 2], [1, 3, 2]])
    assert shape_kind(bent) == "open"


@pytest.mark.parametrize(
    ("mesh", "polygons"), [(icosphere(1), 80), (plane(), 1), (quad_cube(), 6)], ids=["icosphere", "plane", "quad_cube"]
)
def test_mesh_records_keep_the_audits_statistics(mesh, polygons):
    stats = mesh_statistics(mesh)
    record = mesh_record(mesh)
    for key in ("vertices", "faces", "edges", "boundary_edges", "nonmanifold_edges", "mean_sides"):
        assert record[key] == stats[key] and type(record[key]) is type(stats[key]), key
    assert record["closed"] is bool(stats["closed"])
    assert record["coplanar_polygons"] == stats["coplanar"]["polygons"]
    assert record["merge_ratio"] == stats["faces"] / stats["coplanar"]["polygons"]
    # by hand: no two of the icosphere's 80 faces are coplanar; the flat plane is one polygon; the cube six
    assert record["coplanar_polygons"] == polygons


# ---- lights ----------------------------------------------------------------------------------
def test_lights_depend_on_seed_and_bytes_only():
    mesh = icosphere(1)
    sha_a, sha_b = hashlib.sha256(b"a").hexdigest(), hashlib.sha256(b"b").hexdigest()
    s = Settings(lights=5, light_kind="both")
    a1, a2 = mesh_lights(mesh, s, sha_a), mesh_lights(mesh, s, sha_a)
    assert a1 == a2 and len(a1) == 10
    assert a1 != mesh_lights(mesh, s, sha_b)
    assert a1 != mesh_lights(mesh, Settings(lights=5, light_kind="both", seed=1), sha_a)
    dirs = np.array([light.direction for light in a1[:5]])
    assert np.allclose(np.linalg.norm(dirs, axis=1), 1.0)
    pos = np.array([light.position for light in a1[5:]])
    assert np.allclose(np.linalg.norm(pos - mesh.centre, axis=1), 3.0 * mesh.bounding_radius)
    assert np.allclose((pos - mesh.centre) / (3.0 * mesh.bounding_radius), dirs)  # the same directions, paired


# ---- fits ------------------------------------------------------------------------------------
def test_fit_recovers_a_known_exponent_and_its_interval_covers_it():
    """Synthetic ``0.7 F^0.8``, log-normal scatter: estimates near 0.8, the 95% interval covers it ~95% of the time."""
    covered, estimates = 0, []
    for seed in range(100):
        rng = np.random.default_rng(seed)
        faces = np.exp(rng.uniform(np.log(50), np.log(2e6), 40))
        values = 0.7 * faces**0.8 * np.exp(rng.normal(0.0, 0.3, faces.size))
        fit = power_fit(faces, values)
        lo, hi = fit["alpha_ci"]
        covered += lo < 0.8 < hi
        estimates.append(fit["alpha"])
        assert fit["meshes"] == 40 and lo < fit["alpha"] < hi
    assert abs(np.mean(estimates) - 0.8) < 0.005 and 88 <= covered <= 99
    exact = power_fit([10, 100, 1000], [3 * 10**0.5, 3 * 100**0.5, 3 * 1000**0.5])
    assert exact["alpha"] == pytest.approx(0.5, abs=1e-12) and exact["c"] == pytest.approx(3.0, rel=1e-12)
    assert power_fit([10, 10], [1, 2])["alpha"] is None
    assert power_fit([10, 20, 30], [0, 5, 6])["meshes"] == 2  # a zero cannot be on a log scale


# ---- the sweep -------------------------------------------------------------------------------
def test_sweep_tables_and_schema(folder):
    import jsonschema

    result = corpus([folder], subdivide=(0, 1), cache=False, **SMALL)
    assert [label for label, _ in find_files([folder])] == [
        "icosphere1.obj",
        "quad_cube.obj",
        "sub/plane.obj",
        "tetrahedron.obj",
    ]
    m = result.meshes
    assert list(zip(m["file"], m["level"])) == [(f, lv) for f in sorted(set(m["file"])) for lv in (0, 1)]
    assert result.failed == 0 and len(result.rows) == 8 * 3 * len(DETECTORS) and len(DETECTORS) == 7
    cube = m[(m["file"] == "quad_cube.obj")].set_index("level")
    assert cube.loc[0, "faces"] == 6 and cube.loc[1, "faces"] == 24 and cube.loc[1, "coplanar_polygons"] == 6
    assert (cube["silhouette_edges_mean"].iloc[1] == 2 * cube["silhouette_edges_mean"].iloc[0]).all()
    assert (result.rows["missed_edges"] == 0).all() and (result.rows["extra_edges"] == 0).all()
    assert {"silhouette_edges", "silhouette_edges:closed", "silhouette_edges:level0", "ta:true"} <= set(result.fits)
    assert {"gaussmap:true", "cones:paper", "cones:directional:edge_test~s_log2F"} <= set(result.fits)
    jsonschema.validate(result.document, json.loads(SCHEMA.read_text()))


def test_broken_file_is_an_error_row_and_the_sweep_goes_on(folder):
    (folder / "broken.obj").write_text("v 0 0 0\nf 1 2 3\n")
    (folder / "empty.off").write_bytes(b"")
    result = corpus([folder], cache=False, **SMALL)
    errors = result.meshes.set_index("file")["error"]
    assert errors["broken.obj"].startswith("broken.obj: ") and "\n" not in errors["broken.obj"]
    assert "empty" in errors["empty.off"] and errors["quad_cube.obj"] == ""
    assert result.failed == 2 and set(result.rows["file"]) == {
        "icosphere1.obj",
        "quad_cube.obj",
        "sub/plane.obj",
        "tetrahedron.obj",
    }


class Interrupted(Exception):
    pass


def test_an_interrupted_sweep_resumes_from_the_cache(folder, tmp_path, monkeypatch):
    cache = tmp_path / "cache"
    reference = corpus([folder], cache=False, **SMALL).document
    real = schedule_mod.audit_task
    calls: list[str] = []

    def dies_on_the_third(label, *args):
        if len(calls) == 2:
            raise Interrupted(label)
        calls.append(label)
        return real(label, *args)

    monkeypatch.setattr(schedule_mod, "audit_task", dies_on_the_third)
    with pytest.raises(Interrupted):
        corpus([folder], cache=cache, **SMALL)
    assert len(list(cache.glob("*.json"))) == 2
    calls.clear()
    monkeypatch.setattr(schedule_mod, "audit_task", lambda label, *a: calls.append(label) or real(label, *a))
    resumed = corpus([folder], cache=cache, **SMALL).document
    assert len(calls) == 2 and resumed == reference  # only the unfinished meshes ran
    calls.clear()
    assert corpus([folder], cache=cache, **SMALL).document == reference and calls == []
    changed = corpus([folder], cache=cache, **{**SMALL, "lights": 4}).document
    assert len(calls) == 4 and changed["settings"]["lights"] == 4  # other settings, other entries


def test_the_largest_units_start_first_and_run_on_the_cores_per_worker(folder, monkeypatch):
    import numba

    real = schedule_mod.audit_task
    started: list[tuple[str, int, int]] = []

    def record(label, data, level, settings, *part):
        started.append((label, level, numba.get_num_threads()))
        return real(label, data, level, settings, *part)

    monkeypatch.setattr(schedule_mod, "audit_task", record)
    monkeypatch.setattr(schedule_mod.os, "cpu_count", lambda: 4)
    result = corpus([folder], cache=False, subdivide=(0, 1), **SMALL)
    faces = {p.name: load_mesh(p).n_faces for p in folder.rglob("*.obj")}  # the estimate grows with the faces
    cost = [faces[Path(label).name] * 4**level for label, level, _ in started]
    assert len(started) == 8 and cost == sorted(cost, reverse=True)  # one worker: strictly in cost order
    assert {t for *_, t in started} == {min(4, numba.config.NUMBA_NUM_THREADS)}  # 4 cores // 1 worker
    assert result.document == corpus([folder], cache=False, subdivide=(0, 1), **SMALL).document
    started.clear()
    corpus([folder], cache=False, **{**SMALL, "workers": 4})
    assert {t for *_, t in started} == {1}  # 4 cores // 4 workers


def test_process_workers_are_handed_one_unit_at_a_time(folder):
    # Dask's processes scheduler hands out batches of 6 ready tasks by default: with 4 units and 2 workers
    # all 4 would be dispatched at once, two to each worker, and the largest-first order would be lost
    # between them.  Handed out one at a time, no more units are in flight than there are workers.
    from dask.callbacks import Callback

    in_flight: list[int] = []
    with Callback(pretask=lambda key, dsk, state: in_flight.append(len(state["running"]))):
        result = corpus([folder], cache=False, **{**SMALL, "scheduler": "processes", "workers": 2})
    assert len(in_flight) >= 4 and max(in_flight) <= 2, in_flight  # a large unit may run as several tasks
    assert result.document == corpus([folder], cache=False, **SMALL).document


def test_a_process_sweep_leaves_no_executor_thread_for_the_interpreter_s_exit(folder):
    """The pool is shut down, and its workers' exit waited for, inside the sweep, where a Ctrl-C is reported as
    one line: left to the interpreter's exit (``concurrent.futures``' atexit join), a Ctrl-C there printed a
    ``KeyboardInterrupt`` traceback and exited 0 (6 of 16 Ctrl-Cs sent 1.55-1.85 s into a 2 s sweep)."""
    import threading

    corpus([folder], cache=False, **{**SMALL, "scheduler": "processes", "workers": 2})
    left = [t for t in threading.enumerate() if type(t).__name__ == "_ExecutorManagerThread" and t.is_alive()]
    assert not left, left


def test_the_process_pool_spawns_all_its_workers_at_once():
    # started on creation (before Dask's import), not on the first unit's submission; spawned, never forked
    import multiprocessing

    before = set(multiprocessing.active_children())
    pool = schedule_mod.process_pool(2)
    try:
        started = [p for p in multiprocessing.active_children() if p not in before]
        assert len(started) == 2 and {type(p).__name__ for p in started} == {"SpawnProcess"}
        pids = {pool.submit(os.getpid).result() for _ in range(8)}
        assert pids <= {p.pid for p in started} and os.getpid() not in pids
    finally:
        pool.shutdown()


def test_cli_outputs_and_exit_codes(folder, tmp_path, capsys):
    from silcount.cli.main import main

    out = tmp_path / "out"
    args = ["corpus", str(folder), "--lights", "2", "--no-time", "--no-cache", "--scheduler", "threads"]
    assert main([*args, "--out", str(out), "--format", "md", "--quiet"]) == 0
    assert "## Fits" in capsys.readouterr().out
    names = {p.name for p in out.iterdir()}
    assert {
        "corpus.parquet",
        "meshes.csv",
        "fits.json",
        "summary.md",
        "silhouette.png",
        "silhouette.svg",
        "operations.png",
        "hsd_merge.svg",
    } <= names
    import pandas as pd

    assert len(pd.read_parquet(out / "corpus.parquet")) == 4 * 2 * len(DETECTORS)
    assert {"literature.md", "literature.png", "literature.svg", "output_sensitivity.png"} <= names
    assert "(literature.md)" in (out / "summary.md").read_text()
    first = (out / "silhouette.svg").read_bytes()
    (folder / "broken.obj").write_text("f 1 2 3\n")
    assert main([*args, "--format", "json", "--quiet"]) == 1  # a mesh failed
    assert json.loads(capsys.readouterr().out)["meshes"][0]["file"] == "broken.obj"
    (folder / "broken.obj").unlink()
    assert main([*args, "--out", str(out), "--quiet"]) == 0
    assert (out / "silhouette.svg").read_bytes() == first  # byte-identical figures
    assert main(["corpus", str(tmp_path / "nothing"), "--no-cache"]) == 3
    assert main([*args, "--detectors", "ta,bogus"]) == 2


def test_report_skips_without_a_corpus(monkeypatch, tmp_path, capsys):
    from silcount.cli import corpus as cli

    monkeypatch.setattr(cli, "corpus_dir", lambda: None)
    assert cli.report(tmp_path) == [tmp_path / "corpus" / "scale.md"]  # from the committed measurements only
    assert "skipped" in capsys.readouterr().out


# ---- the literature's detectors beside the papers' -------------------------------------------
def test_hierarchies_are_one_run_each_with_steps_build_and_edges_visited(folder):
    from silcount.detectors import detect
    from silcount.mesh.io import load_mesh

    result = corpus([folder], cache=False, variant="both", **SMALL)
    runs = [key for key, _, _ in result.settings.runs()]
    assert [r for r in runs if r.split(":")[0] in LITERATURE] == list(LITERATURE)  # one variant, as reference
    assert {"ta:literal", "hsd:literal", "eesd:literal"} <= set(runs) and "reference:literal" not in runs
    rows = result.rows
    for det in LITERATURE:
        r = rows[rows["detector"] == det]
        assert len(r) == 4 * 3 and (r["variant"] == "intended").all()
        assert (r["silhouette_edges"] == r["reference_edges"]).all()  # exactly the reference's answer
        assert (r["missed_edges"] == 0).all() and (r["extra_edges"] == 0).all()
        assert (r["edges_visited"] == r["steps_edge_test"]).all() and (r["steps_add"] == r["silhouette_edges"]).all()
        assert ((r["edges_visited_fraction"] >= 0) & (r["edges_visited_fraction"] <= 1)).all()
        assert (r["edges_visited_fraction"] > 0).any()
    ref = rows[rows["detector"] == "reference"]
    assert (ref["edges_visited_fraction"] == 1.0).all() and ref["steps_node_test"].isna().all()
    ta = rows[rows["detector"] == "ta"]
    assert (ta["edges_visited"] == ta["steps_search_S"]).all()  # the sides of the lit faces it looks up in S
    m = result.meshes.set_index("file")
    mesh = load_mesh(folder / "icosphere1.obj")
    for det in LITERATURE:
        notes = detect(mesh, DirectionalLight((0.3, 0.5, 0.8)), det).notes
        assert m.loc["icosphere1.obj", f"{det}:build_total"] == sum(notes["build"].values()) > 0
        assert m.loc["icosphere1.obj", f"{det}:tree_bytes"] == notes["tree_bytes"]
    assert (m["hsd:build_total"] > 0).all()  # HSD's coplanar merge, its per-mesh preprocessing
    doc = {d["file"]: d for d in result.document["meshes"]}["icosphere1.obj"]["detectors"]
    assert doc["gaussmap"]["build"]["total"] == sum(v for k, v in doc["gaussmap"]["build"].items() if k != "total")
    assert doc["cones"]["steps"]["edge_test"] == doc["cones"]["edges_visited"] > 0
    assert "build" not in doc["ta"] and doc["ta"]["edges_visited_fraction"] > 0
    import jsonschema

    jsonschema.validate(result.document, json.loads(SCHEMA.read_text()))


def test_output_sensitivity_fits_are_power_fits_of_edges_tested(folder):
    result = corpus([folder], cache=False, **SMALL)
    m = result.meshes
    for det in LITERATURE:
        x = {
            "s": m["silhouette_edges_mean"],
            "F": m["faces"],
            "s_log2F": m["silhouette_edges_mean"] * np.log2(m["faces"]),
        }
        for key, against in (("s", "s"), ("F", "F"), ("s_log2F", "s log2 F")):
            fit = result.fits[f"{det}:directional:edge_test~{key}"]
            want = power_fit(x[key], m[f"{det}:steps_edge_test"])
            assert fit["against"] == against and fit["meshes"] == want["meshes"] == 4
            assert fit["alpha"] == pytest.approx(want["alpha"], rel=1e-12) and fit["alpha_ci"] == want["alpha_ci"]
    assert result.fits["ta:true"]["against"] == "F"


def test_the_literature_page_counts_what_the_tables_say(folder, tmp_path):
    from silcount.study.output import write_out

    result = corpus([folder], cache=False, **SMALL)
    write_out(result, tmp_path / "out", with_rows=False)
    text = (tmp_path / "out" / "literature.md").read_text()
    assert "| TA | VnV | HSD | EESD | reference | Gauss map | normal cones |" in text
    assert "| 1-9 | directional | 2 | true operations per light |" in text  # tetrahedron 4, quad_cube 6 faces
    m = result.meshes.set_index("file")
    wins = int((m["hsd:true_total"] < m["ta:true_total"]).sum())
    assert f"HSD below TA: in true operations per light on {wins} of 4 meshes" in text
    papers = m[[f"{d}:true_total" for d in ("ta", "vnv", "hsd", "eesd")]].min(axis=1)
    others = m[[f"{d}:true_total" for d in ("reference", "gaussmap", "cones")]].min(axis=1)
    assert f"below the lowest of reference, Gauss map and normal cones on {int((papers < others).sum())} of 4" in text
    assert "Times: not measured in this sweep" in text and "| time per light |" not in text


def test_findings_name_a_paper_detector_that_beats_the_others():
    import pandas as pd

    from silcount.study.literature import band_of, findings

    recs = []
    for file, faces, ops in (("a.obj", 1000, {"ta": 10.0, "reference": 20.0}), ("b.obj", 50, {"ta": 99.0})):
        for det in ("ta", "vnv", "hsd", "eesd", "reference", "gaussmap", "cones"):
            recs.append({"file": file, "level": 0, "light_kind": "directional", "detector": det, "faces": faces,
                         "true_ops": ops.get(det, 50.0), "time_s": None, "visited_fraction": 1.0, "s": 5.0,
                         "edge_test": 7.0, "build_total": None})  # fmt: skip
    lines = findings(pd.DataFrame(recs), {}, timed=False)
    best = next(line for line in lines if line.startswith("True operations per light"))
    assert "on 1 of 2 meshes: a.obj (TA, 1,000 faces)" in best
    tie = "a tie of VnV, HSD, EESD, reference, Gauss map and normal cones"  # b.obj: all but TA at 50
    assert f"Fewest true operations per light: TA on 1, {tie} on 1 of 2 meshes." in lines
    assert (band_of(1), band_of(999), band_of(1000), band_of(86482)) == ("1-9", "100-999", "1,000-9,999",
                                                                         "10,000-99,999")  # fmt: skip


def test_a_timed_sweep_times_the_hierarchies_per_light_kind_and_the_cache_blanks_it(tmp_path):
    import jsonschema

    from silcount.study.output import write_out

    one = tmp_path / "one"
    one.mkdir()
    shutil.copy(DATA / "icosphere1.obj", one / "icosphere1.obj")
    cache = tmp_path / "cache"
    args = dict(lights=2, light_kind="both", quiet=True, scheduler="threads", workers=1)
    timed = corpus([one], cache=cache, timing=True, **args)
    doc = timed.document["meshes"][0]
    by_kind = doc["time_by_light_kind"]
    assert set(by_kind) == {"directional", "point"} and doc["time_per_light_s"] == by_kind["directional"]
    assert all(by_kind[k][d] > 0 for k in by_kind for d in DETECTORS)
    jsonschema.validate(timed.document, json.loads(SCHEMA.read_text()))
    write_out(timed, tmp_path / "out", with_rows=False)
    text = (tmp_path / "out" / "literature.md").read_text()
    assert "| 10-99 | point | 1 | time per light |" in text and "Times: not measured" not in text
    untimed = corpus([one], cache=cache, timing=False, **args)  # read back from the cache, times blanked
    assert untimed.document == corpus([one], cache=False, timing=False, **args).document
    blank = untimed.document["meshes"][0]["time_by_light_kind"]
    assert set(blank) == {"directional", "point"} and all(v is None for k in blank for v in blank[k].values())


number = st.one_of(st.integers(-9, 9), st.floats(-1, 1))
unit_rows = st.lists(  # as run_record's rows: some keys in every row, maybe None; the steps per detector, never None
    st.fixed_dictionaries(
        {"light": st.integers(0, 3), "edges_visited": st.one_of(st.none(), number)},
        optional={key: number for key in ("steps_b", "steps_a", "steps_c")},
    ),
    max_size=6,
)


@settings(max_examples=80, deadline=None)
@given(units=st.lists(unit_rows, min_size=1, max_size=4))
def test_columnar_rows_give_the_frame_of_one_dict_per_row(units):
    """A unit's rows travel as columns (``row_columns``); the frame equals pandas' own one built from the rows."""
    import pandas as pd

    labels = [f"m{i}.off" for i in range(len(units))]
    results = [
        {"mesh": {"faces": 4 * i}, "rows": row_columns(rows), "level": 0, "sha256": f"{i:064x}"}
        for i, rows in enumerate(units)
    ]
    records = [
        {"file": label, "level": 0, "sha256": res["sha256"], "faces": res["mesh"]["faces"], **dict(sorted(row.items()))}
        for label, res, rows in zip(labels, results, units)
        for row in rows
    ]
    expected = pd.DataFrame.from_records(records)
    if not expected.empty:
        expected = expected.sort_values(["file", "level", "light"], kind="stable").reset_index(drop=True)
    pd.testing.assert_frame_equal(rows_frame(labels, results), expected, check_exact=True)


@settings(max_examples=80, deadline=None)
@given(data=st.data(), n_lights=st.integers(0, 4), n_runs=st.integers(1, 4))
def test_interleaved_run_columns_are_the_rows_one_dict_per_row(data, n_lights, n_runs):
    """A unit's runs kept as columns (:func:`interleave`) give what its rows, light by light and run by run,
    give through :func:`row_columns`: the same column order, values and ``None`` for a key a row lacks."""
    keys = ("light", "steps_b", "steps_a", "edges_visited", "steps_c", "total")
    runs, rows_by_run = [], []
    for _ in range(n_runs):
        rows = [
            {k: data.draw(number) for k in data.draw(st.lists(st.sampled_from(keys), unique=True, min_size=1))}
            for _ in range(n_lights)
        ]
        names = dict.fromkeys(k for row in rows for k in row)
        cols = {k: [row.get(k) for row in rows] for k in names}
        runs.append((cols, [tuple(sorted(row)) for row in rows]))
        rows_by_run.append(rows)
    rows = [run[i] for i in range(n_lights) for run in rows_by_run]
    assert interleave(runs, n_lights) == row_columns(rows)
