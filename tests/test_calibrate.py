"""silcount calibrate: the fit, the rank statistics, the FPS table, the outputs (structure, never timing values)."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import numpy as np
import pandas as pd
import pytest

from silcount.calibrate import fps, measure, output, predict, timing
from silcount.calibrate.calibration import calibrate, from_committed, ranking_evidence
from silcount.cli.main import main
from silcount.counting.cycles import TRUE_KINDS, Profile, measured_file_profiles
from silcount.errors import UnreadableInput
from silcount.mesh.shapes import builtin_mesh

SCHEMA = json.loads((Path(__file__).resolve().parent.parent / "docs/schemas/calibrate.schema.json").read_text())


def _samples(seconds_of) -> pd.DataFrame:
    """Two meshes x two detectors x one light; tallies chosen by hand, seconds from ``seconds_of(row)``."""
    rows = []
    for mesh, faces, k in (("m1", 20, 1), ("m2", 80, 4)):
        for det, adds in (("ta", 10 * k), ("vnv", 30 * k)):
            row = {"group": "icosphere", "mesh": mesh, "faces": faces, "edges": 30, "detector": det, "light": 0}
            for model in timing.MODELS:
                row |= {f"{model}_{kind}": 0 for kind in TRUE_KINDS}
                row[f"{model}_add"] = adds
                row[f"{model}_div"] = 1
            rows.append(row)
    frame = pd.DataFrame(rows)
    frame["seconds"] = [seconds_of(r) for r in frame.to_dict("records")]
    return frame


UNIT = {"unit": Profile("unit", {k: 1.0 for k in TRUE_KINDS}, "test")}


def test_exact_proportional_times_fit_perfectly():
    # weighted = adds + 1 (div) with unit weights; seconds = 3e-9 x weighted exactly
    s = _samples(lambda r: 3e-9 * (r["true_add"] + 1))
    pred = predict.weighted(s, UNIT)
    meshes = predict.per_mesh(pred)
    summ = predict.summary(pred, meshes)
    row = summ[summ["model"] == "true"].iloc[0]
    assert row["scale"] == pytest.approx(3e-9)
    assert row["r2"] == pytest.approx(1.0)
    assert row["median_ratio"] == pytest.approx(1.0) and row["worst_ratio"] == pytest.approx(1.0)
    assert row["fastest_agree"] == 2 and row["meshes"] == 2 and row["rank_rho"] == pytest.approx(1.0)


def test_reversed_order_is_caught():
    # vnv measured faster than ta although it counts 3x the operations
    s = _samples(lambda r: 1e-6 / (r["true_add"] + 1))
    pred = predict.weighted(s, UNIT)
    meshes = predict.per_mesh(pred)
    summ = predict.summary(pred, meshes)
    row = summ[summ["model"] == "true"].iloc[0]
    assert row["fastest_agree"] == 0 and row["rank_rho"] == pytest.approx(-1.0)
    assert row["r2"] < 0  # worse than the mean: the weighted count anti-predicts
    m1 = meshes[(meshes["model"] == "true") & (meshes["mesh"] == "m1")].iloc[0]
    assert m1["measured_order"] == "vnv < ta" and m1["predicted_order"] == "ta < vnv"
    # worst ratio by hand: log s = mean(log t - log w); t = 1e-6 / w
    w = np.array([11, 31, 41, 121], float)
    scale = np.exp(np.mean(np.log(1e-6 / w) - np.log(w)))
    ratios = scale * w / (1e-6 / w)
    assert row["worst_ratio"] == pytest.approx(ratios[np.argmax(np.abs(np.log(ratios)))])


def test_fps_table_by_hand():
    t = fps.fps_table()
    assert len(t) == 8 and set(t["algorithm"]) == {"ta", "vnv", "eesd", "hsd"}
    row = t[(t["algorithm"] == "eesd") & (t["reading"] == "e_n = 6n")].iloc[0]
    # EESD's printed form (18n^2+18n)M+(18n^2+36n)A+6n^2C+12nR+12nW with M4 A2 C3 R1 W2 = 126 n^2 + 180 n
    n = 2207 / 6
    assert row["paper_cycles"] == pytest.approx(126 * n**2 + 180 * n)
    assert row["detect_ms"] == pytest.approx(1e3 * (126 * n**2 + 180 * n) / 2.8e9)
    assert row["frame_ms"] == pytest.approx(1000 / 73.16)
    assert bool(row["fits"]) == (row["detect_ms"] < row["frame_ms"])


def test_measure_smoke_structure(tmp_path):
    raw = measure.raw_timings(n=200, repeats=1, dram_bytes=1 << 16)
    assert all(v > 0 for v in raw.values())
    values = measure.profile_values(raw)
    assert set(values["latency"]) == set(TRUE_KINDS) | {"read_dram"}
    path = tmp_path / "measured-x.toml"
    path.write_text(measure.render_toml("Test CPU 1", raw, 200, 1, 1 << 16))
    profs = measured_file_profiles(path)
    assert set(profs) == {f"test-cpu-1-measured-{s}" for s in ("latency", "throughput", "latency-dram")}
    assert measure.slug("AMD EPYC 7B13 64-Core Processor") == "amd-epyc-7b13-64-core-processor"


def test_tiny_live_calibration_writes_valid_outputs(tmp_path):
    meshes = [("icosphere", builtin_mesh("icosphere0")), ("icosphere", builtin_mesh("icosphere1"))]
    times = timing.timings(meshes, n_lights=1, repeats=1)
    assert list(times.columns) == ["mesh", "detector", "light", "seconds"] and len(times) == 2 * len(timing.timed())
    cal = calibrate(meshes, times, "test", "test", n_lights=1)
    paths = output.write(cal, tmp_path, with_timings=True, figures=False)
    names = {p.name for p in paths}
    assert {"calibrate.md", "calibrate.csv", "calibrate.json", "calibrate_large.csv", "timings.csv"} <= names
    doc = json.loads((tmp_path / "calibrate.json").read_text())
    jsonschema.validate(doc, SCHEMA)
    csv = pd.read_csv(tmp_path / "calibrate.csv")
    assert list(csv.columns) == list(cal.summary.columns) and len(csv) == len(cal.summary)
    assert doc["summary_large"] == []  # icosphere0 and 1 are below LARGE_FACES
    # the papers' four are fitted; gaussmap and cones are predicted with that fit, reported apart
    assert doc["samples"] == 2 * len(timing.algorithms()) and set(cal.samples["detector"]) == set(timing.algorithms())
    lit = doc["literature"]
    assert lit["detectors"] == list(timing.literature()) and lit["samples"] == 2 * len(timing.literature())
    assert {(r["model"], r["detector"]) for r in lit["summary"]} == {
        (m, d) for m in timing.MODELS for d in timing.literature()
    }
    assert [r["mesh"] for r in lit["per_mesh"]] == ["icosphere0", "icosphere1"]
    assert len(pd.read_csv(tmp_path / "timings.csv")) == len(times)  # every timed sample, to reuse with --timings
    assert "## The literature's hierarchies" in (tmp_path / "calibrate.md").read_text()


def test_the_literature_does_not_move_the_four():
    # timings with and without gaussmap and cones: the same fit, rank statistics and per-mesh orders
    s = _samples(lambda r: 3e-9 * (r["true_add"] + 1))
    base = predict.weighted(s, UNIT)
    lit = s.assign(detector="cones", seconds=s["seconds"] * 2.0)
    pred = predict.weighted(lit, UNIT, predict.scales_of(base))
    assert pred["scale"].tolist() == base["scale"].tolist()  # the four's scale, not refitted
    assert pred["ratio"].to_numpy() == pytest.approx(0.5)  # twice as slow as the fit predicts
    summ = predict.per_detector(pred)
    assert set(summ["detector"]) == {"cones"} and summ["median_ratio"].to_numpy() == pytest.approx(0.5)


def test_committed_like_timings_with_the_literature_keep_the_fours_numbers():
    meshes = [("icosphere", builtin_mesh("icosphere0")), ("icosphere", builtin_mesh("icosphere1"))]
    times = timing.timings(meshes, n_lights=1, repeats=1)
    four = times[times["detector"].isin(timing.algorithms())]
    with_lit, without = calibrate(meshes, times, "t", "t", n_lights=1), calibrate(meshes, four, "t", "t", n_lights=1)
    for table in ("samples", "predictions", "per_mesh", "summary", "summary_large"):
        pd.testing.assert_frame_equal(getattr(with_lit, table), getattr(without, table))
    assert len(without.literature_samples) == 0 and json.loads(output.to_json(without))["literature"]["summary"] == []


def test_cli_reuses_a_timings_file(tmp_path):
    meshes = timing.series_meshes()[:1]
    times = timing.timings(meshes, n_lights=2, repeats=1)
    with pytest.raises(UnreadableInput, match="no timing for icosphere1"):
        calibrate(timing.series_meshes()[:2], times, "test", "t", n_lights=2)
    times.insert(0, "cpu_model", "test")
    (tmp_path / "t.csv").write_text(times.to_csv(index=False))
    assert main(["calibrate", "--timings", str(tmp_path / "t.csv"), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    doc = json.loads((tmp_path / "o" / "calibrate.json").read_text())
    jsonschema.validate(doc, SCHEMA)
    assert doc["samples"] == 8 and doc["timings"] == str(tmp_path / "t.csv") and doc["cpu_model"] == "test"
    assert (tmp_path / "o" / "calibrate_true.png").stat().st_size > 0
    assert not (tmp_path / "o" / "timings.csv").exists()
    (tmp_path / "bad.csv").write_text("mesh,seconds\nicosphere0,1\n")
    assert main(["calibrate", "--timings", str(tmp_path / "bad.csv"), "--out", str(tmp_path / "p")]) == 3


@pytest.fixture(scope="module")
def committed():
    return from_committed()


def test_committed_report_validates_and_is_deterministic(committed, tmp_path):
    again = from_committed()
    assert output.to_json(again) == output.to_json(committed)
    assert output.to_markdown(again) == output.to_markdown(committed)
    a = output.figure(committed, "true", tmp_path / "a.png").read_bytes()
    assert output.figure(again, "true", tmp_path / "b.png").read_bytes() == a
    doc = json.loads(output.to_json(committed))
    jsonschema.validate(doc, SCHEMA)
    assert doc["samples"] == len(timing.SERIES) * len(timing.algorithms()) * timing.LIGHTS
    assert {r["profile"] for r in doc["summary"]} >= {"paper", "unit", "skylake-latency", "znver3-throughput"}
    assert {r["model"] for r in doc["summary_large"]} == {"paper", "true"}


def test_ranking_evidence(committed):
    ev = ranking_evidence(committed)
    assert set(ev["meshes"]) == set(timing.SERIES)
    for entry in ev["meshes"].values():
        assert sorted(entry["measured_order"]) == sorted(timing.algorithms())
        assert entry["measured_fastest"] == min(entry["measured_seconds"], key=entry["measured_seconds"].get)
        for model in ("paper", "true"):
            for verdict in entry["predicted"][model].values():
                assert verdict["fastest_agrees"] == (verdict["fastest"] == entry["measured_fastest"])
    assert ev["summary"]["true"]["paper"]["meshes"] == len(timing.SERIES)


def test_a_timed_mesh_that_loads_today_with_another_face_count_is_left_out_and_named():
    """Old times paired with today's tallies of another mesh would be a wrong sample (suzanne.ply: 968 -> 500)."""
    import pandas as pd

    from silcount.calibrate.calibration import _as_timed
    from silcount.mesh.shapes import builtin_mesh

    same, other = builtin_mesh("icosphere1"), builtin_mesh("icosphere2")
    same.name, other.name = "a.obj", "b.obj"
    times = pd.DataFrame({"mesh": ["a.obj", "b.obj"], "faces": [same.n_faces, 968], "seconds": [1.0, 1.0]})
    kept, left_out = _as_timed([("corpus", same), ("corpus", other)], times)
    assert [m.name for _, m in kept] == ["a.obj"]
    assert left_out == (f"b.obj: timed with 968 faces, loads today with {other.n_faces}",)
    assert _as_timed([("corpus", other)], times.drop(columns=["faces"])) == ([("corpus", other)], ())


def test_report_without_a_corpus_folder_skips_the_corpus_section_saying_so(tmp_path, monkeypatch, capsys):
    # The Makefile names ../shared/corpus whether or not it exists: a clone without it writes the series
    # section and leaves the corpus one alone (one line on stderr), rather than failing the whole report.
    from silcount.calibrate.calibration import committed_timings, read_timings
    from silcount.cli import calibrate as calibrate_cli

    monkeypatch.setenv("SILCOUNT_CORPUS_DIR", str(tmp_path / "no-such-folder"))
    written = calibrate_cli.report(tmp_path)
    assert written and all("corpus" not in p.relative_to(tmp_path).parts for p in written)
    if set(read_timings(committed_timings())["mesh"]) - set(timing.SERIES):  # the committed timings time corpus files
        assert "calibrate: corpus skipped" in capsys.readouterr().err


def test_a_fit_across_the_algorithms_can_miss_one_algorithm():
    """TA's time falling across its two meshes (2 us, then 1 us) while its tally grows 4x, VnV's proportional: the
    shared fit predicts VnV exactly within its samples (R^2 = 1) and TA worse than TA's own mean (R^2 < 0),
    while the R^2 over all four samples stays high (the gap between the algorithms)."""
    ta = {"m1": 2e-6, "m2": 1e-6}
    s = _samples(lambda r: ta[r["mesh"]] if r["detector"] == "ta" else 1e-9 * (r["true_add"] + 1))
    pred = predict.weighted(s, UNIT)
    within = predict.per_detector(pred).set_index(["model", "detector"])
    assert within.loc[("true", "ta"), "r2"] < 0
    summ = predict.summary(pred, predict.per_mesh(pred)).set_index("model")
    assert summ.loc["true", "r2"] > within.loc[("true", "ta"), "r2"]
    exact = predict.per_detector(predict.weighted(_samples(lambda r: 3e-9 * (r["true_add"] + 1)), UNIT))
    assert exact["r2"].to_numpy() == pytest.approx(1.0)
