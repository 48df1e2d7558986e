"""A unit's time and memory from its faces (``silcount.study.units``), the split of units
(``silcount.study.parts``) and the model of a Thingi10K-shaped sweep (``silcount.study.scale``), by hand."""

from __future__ import annotations

import pytest

from silcount.study import parts as split
from silcount.study import scale
from silcount.study.units import MARGIN, default_budget, load_model, model_from, physical_memory
from silcount.study.work import Part, Settings

MIB = 2**20


def toy_units() -> dict:
    """Units whose time is 1e-6 F s and whose extra memory is 1000 F bytes (0.3 of both the reference's alone,
    0.4 gaussmap's), 8 lights
    costing half of 64's extra memory and 1/8 of its time: the fits must give those back."""
    units = []
    for faces in (20_000, 80_000, 320_000):
        for det, share in (("all", 1.0), ("reference", 0.3), ("gaussmap", 0.4)):
            units.append({"file": f"m{faces}", "detectors": det, "lights": 64, "faces": faces,
                          "seconds": 1e-6 * faces * share, "base_bytes": 100 * MIB,
                          "peak_bytes": 100 * MIB + 1000 * faces * share})  # fmt: skip
    units.append({"file": "m320000", "detectors": "all", "lights": 8, "faces": 320_000, "seconds": 0.32 / 8,
                  "base_bytes": 100 * MIB, "peak_bytes": 100 * MIB + 1000 * 320_000 / 2})  # fmt: skip
    return {"units": units}


def test_the_fits_give_a_known_law_back():
    m = model_from(toy_units())
    f = m.fit_of("all", "seconds")
    assert f["alpha"] == pytest.approx(1.0) and f["c"] == pytest.approx(1e-6)
    # 8 of 64 lights: time 1/8 of 64's, so all of it is per light; memory: half of it
    assert m.light_share["seconds"] == pytest.approx(1.0) and m.light_share["extra_bytes"] == pytest.approx(4 / 7)
    s = Settings(detectors=("reference", "gaussmap"), timing=False)
    # memory: the two peaks alone added (300 F + 400 F) at 1 M faces, times the margin; time: the reference's
    # 0.3 s plus what gaussmap adds to it (0.1 s); on half the lights, half the time
    assert m.peak_bytes(1e6, s, ("reference", "gaussmap")) == pytest.approx(100 * MIB + MARGIN * 700e6, rel=1e-9)
    assert m.seconds(1e6, s, ("reference", "gaussmap"), 32) == pytest.approx(0.4 * 0.5)
    assert m.peak_bytes(1e6, Settings(timing=False)) == pytest.approx(100 * MIB + MARGIN * 1000e6, rel=1e-9)


def test_the_margin_covers_every_measured_unit():
    m = load_model()
    for u in m.units:
        if u.get("error"):
            continue
        names = None if u["detectors"] == "all" else (u["detectors"],)
        settings = Settings(lights=u["lights"])
        assert u["peak_bytes"] <= m.peak_bytes(u["faces"], settings, names), u


def test_the_default_budget_shares_three_quarters_of_the_memory_among_the_workers():
    total = physical_memory()
    assert total is not None and default_budget(4) == int(0.75 * total / 4)


def test_memory_parts_pack_detectors_then_batch_lights_or_refuse():
    settings = Settings(lights=10, detectors=("a", "b", "c"), timing=False)

    def need(detectors, lights):  # a: 4 per light, b: 1, c: 1 (bytes), nothing fixed
        return sum({"a": 4, "b": 1, "c": 1}[d] for d in detectors) * lights

    assert split.by_memory(settings, 60, need) == [Part(("a", "b", "c"), 0, 10)]
    # 40 fits a alone on 10 lights, b and c together
    assert split.by_memory(settings, 40, need) == [Part(("a",), 0, 10), Part(("b", "c"), 0, 10)]
    # 12 fits a on 3 lights: 4 batches of the 10 lights (3, 3, 2, 2); b and c each alone on every light (10),
    # not together (20): detectors are packed on all the lights, and only one that does not fit alone is batched
    assert split.by_memory(settings, 12, need) == [
        Part(("a",), 0, 3), Part(("a",), 3, 6), Part(("a",), 6, 8), Part(("a",), 8, 10),
        Part(("b",), 0, 10), Part(("c",), 0, 10),
    ]  # fmt: skip
    refused = split.by_memory(settings, 3, need)
    assert isinstance(refused, str) and refused.startswith("refused: a needs") and "\n" not in refused


def test_balance_cuts_each_part_into_batches_of_its_lights():
    assert split.by_time([Part(("a",), 4, 10)], 4) == [
        Part(("a",), 4, 6), Part(("a",), 6, 8), Part(("a",), 8, 9), Part(("a",), 9, 10)
    ]  # fmt: skip
    assert split.by_time([Part(("a",), 0, 2)], 5) == [Part(("a",), 0, 1), Part(("a",), 1, 2)]


def test_list_scheduling_of_tasks_in_order_and_its_tail():
    # 4 | 3 + 1, then the 2 s task to the worker free at 4: ends 6 on one, 4 on the other
    assert scale.schedule_tasks([4.0, 3.0, 1.0, 2.0], 2) == (6.0, 4.0)
    assert scale.schedule_tasks([5.0, 1.0], 1) == (6.0, 6.0)


def test_a_collection_with_one_huge_mesh_is_split_so_that_no_worker_waits_long():
    from silcount.study.units import load_model

    profile, model = scale.load_profile(), load_model()
    faces = [5_000_000] + [20_000] * 50
    two = scale.plan_collection(profile, faces, 2, Settings(), None)
    assert two.tasks > 51  # the 5 M-face unit runs as batches of its lights
    # unsplit, the big unit runs alone on one worker while the other takes the 50 small ones and waits
    unsplit, idle = scale.schedule_tasks([model.seconds(f, Settings()) + profile.task_overhead_s for f in faces], 2)
    assert unsplit - idle > 0.5 * unsplit  # the tail unsplit: over half the sweep
    # split, no worker waits long, and the sweep is shorter, though each batch loads the mesh again
    assert two.tail_s < 0.1 * two.makespan_s and two.makespan_s < unsplit


def test_a_detector_with_no_measured_units_costs_the_dearest_measured_one_alone(monkeypatch):
    """A plug-in's name has no fit (the corpus once failed with KeyError on it): the reference's 0.3 F s
    plus what the dearer measured detector (gaussmap, 0.4 F) adds to it, 0.1 F; in memory its 0.4 F."""
    from silcount.detectors import DetectorSpec, registry

    registry.names()  # the built-ins and plug-ins first, then this test's detector, removed afterwards
    monkeypatch.setitem(registry._SPECS, "mine", DetectorSpec(name="mine", label="mine", detect=print))
    monkeypatch.setitem(registry._SOURCES, "mine", "registered")
    m = model_from(toy_units())
    s = Settings(detectors=("reference", "mine"), timing=False)
    assert m.seconds(1e6, s) == pytest.approx(0.3 + 0.1)
    assert m.peak_bytes(1e6, s) == pytest.approx(100 * MIB + MARGIN * 700e6, rel=1e-9)


@pytest.mark.parametrize("load", [0.7, 1.0, 1.5, 1.6, 6.0, 10.8])
def test_the_scale_page_reads_the_profiles_load_as_quiet_or_busy(load):
    """The profile runs one unit at a time on one thread: its own process puts about 1 on the load, so a
    highest 1-minute load of 1.5 or less is a quiet machine's; above it the page warns of a busy one."""
    from silcount.study.scale import _load_reading

    text = _load_reading(load)
    assert ("busy machine's" in text) == (load > 1.5) and ("quiet machine's" in text) == (load <= 1.5)
