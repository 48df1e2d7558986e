"""A worker's memory budget and the split of large units: parts joined give the unsplit unit's result.

Expected values come from a second, unsplit run of the same sweep or unit (cache-free), never from the
split code itself; the budgets are scaled down to the small meshes here from the committed fits.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from silcount.study import corpus
from silcount.study import parts as split
from silcount.study.units import load_model
from silcount.study.work import Part, Settings, audit_task

DATA = Path(__file__).resolve().parent.parent / "data"
SMALL = dict(lights=4, timing=False, quiet=True, scheduler="threads", workers=1, cache=False)


@pytest.fixture
def folder(tmp_path) -> Path:
    d = tmp_path / "meshes"
    d.mkdir()
    for name in ("tetrahedron.obj", "quad_cube.obj", "icosphere1.obj", "plane.obj"):
        shutil.copy(DATA / name, d / name)
    return d


def test_parts_joined_are_the_unit_both_light_kinds_and_every_detector():
    data = (DATA / "icosphere1.obj").read_bytes()
    settings = Settings(lights=3, light_kind="both", timing=False)
    whole = audit_task("icosphere1.obj", data, 1, settings)
    det = tuple(settings.detectors)
    parts = [Part(det[:3], 0, 2), Part(det[:3], 2, 6), Part(det[3:], 0, 1), Part(det[3:], 1, 6)]
    got = [audit_task("icosphere1.obj", data, 1, settings, p) for p in parts]
    assert all(len(g["rows"]["values"][0]) < len(whole["rows"]["values"][0]) for g in got)  # each a share
    assert split.merge(got, parts, settings) == whole


def test_a_timed_unit_keeps_its_timings_when_split():
    data = (DATA / "quad_cube.obj").read_bytes()
    settings = Settings(lights=4, light_kind="both", timing=True)
    whole = audit_task("quad_cube.obj", data, 0, settings)
    det = tuple(settings.detectors)
    parts = [Part(det[:2], 0, 8), Part(det[2:], 0, 3), Part(det[2:], 3, 8)]
    merged = split.merge([audit_task("quad_cube.obj", data, 0, settings, p) for p in parts], parts, settings)
    for kind in ("directional", "point"):  # the same detectors timed, each a number (wall times differ)
        times = merged["mesh"]["time_by_light_kind"][kind]
        assert list(times) == list(whole["mesh"]["time_by_light_kind"][kind]) == list(det)
        assert all((t is None) == (whole["mesh"]["time_by_light_kind"][kind][d] is None) for d, t in times.items())
    strip = ("time_by_light_kind", "time_per_light_s")
    assert {k: v for k, v in merged["mesh"].items() if k not in strip} == {
        k: v for k, v in whole["mesh"].items() if k not in strip
    }
    assert merged["rows"] == whole["rows"]


def test_a_budget_below_a_units_need_splits_it_and_the_results_are_identical(tmp_path):
    folder = tmp_path / "same"
    folder.mkdir()
    text = (DATA / "icosphere1.obj").read_text()
    for k in range(3):  # the same 80 faces, other bytes (other lights): one budget is below each unit's need
        (folder / f"ico{k}.obj").write_text(f"# copy {k}\n{text}")
    settings = Settings(lights=SMALL["lights"], timing=False)
    budget = load_model().peak_bytes(80, settings) - 1
    unbudgeted = corpus([folder], **SMALL)
    timeline: list[float] = []
    budgeted = corpus([folder], memory_budget=budget, timeline=timeline, **SMALL)
    assert len(timeline) > len(unbudgeted.meshes)  # the units ran in parts
    assert budgeted.failed == 0 and budgeted.document == unbudgeted.document
    assert budgeted.rows.equals(unbudgeted.rows) and budgeted.meshes.equals(unbudgeted.meshes)


def test_a_unit_that_cannot_fit_one_light_is_refused_in_one_line(folder, capsys):
    from silcount.cli.main import main

    result = corpus([folder], memory_budget=load_model().base_bytes, **SMALL)
    errors = result.meshes["error"].tolist()
    assert result.failed == 4 and all(e.startswith("refused: ") and "\n" not in e for e in errors), errors
    code = main(["corpus", str(folder), "--lights", "2", "--no-cache", "--no-time", "--quiet",
                 "--memory-budget", "1K", "--scheduler", "threads"])  # fmt: skip
    assert code == 1


def test_a_memory_budget_that_is_not_a_size_is_a_bad_argument(folder):
    from silcount.cli.main import main

    assert main(["corpus", str(folder), "--memory-budget", "lots", "--no-cache", "--quiet"]) == 2


def test_a_large_unit_is_spread_over_the_workers_and_the_results_are_identical(folder, tmp_path):
    from silcount.mesh.shapes import icosphere

    big = icosphere(4)  # 5,120 faces: most of the sweep's work
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in big.vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in big.faces.tolist()]
    (folder / "big.obj").write_text("\n".join(lines) + "\n")
    one = corpus([folder], **SMALL)
    timeline: list[float] = []
    two = corpus([folder], timeline=timeline, **{**SMALL, "workers": 2})
    assert len(timeline) > len(one.meshes)  # the big unit ran as batches of its lights
    assert two.document == one.document and two.rows.equals(one.rows)
