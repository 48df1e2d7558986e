"""The frame budget: the occluders over the floor, the committed measurements, the report and its FPS answers."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from common import shared_scenes

from silcount.mesh import shapes
from silcount.papers import budget as report_budget
from silcount.render import budget
from silcount.render.scene import load_scene
from silcount.render.stages import frame_stages


def template():
    return load_scene(shared_scenes() / "cube_on_floor.json")


def test_over_floor_places_the_mesh_on_the_floor_at_the_extent():
    """A unit cube at (10, 10, 10) becomes a 2-wide cube on the floor's origin: x, z in [-1, 1], y in [0, 2]."""
    cube = shapes.builtin_mesh("triangle_cube")
    moved = cube.vertices - cube.vertices.min(axis=0) + 10
    from silcount.mesh.model import from_polygons

    scene = budget.over_floor(from_polygons(moved, cube.faces), "box", template())
    caster = scene.casters[0]
    lo, hi = caster.mesh.vertices.min(axis=0), caster.mesh.vertices.max(axis=0)
    assert np.allclose(lo, [-1, 0, -1]) and np.allclose(hi, [1, 2, 1])
    assert [o.casts_shadow for o in scene.objects] == [False, True]  # the template's floor, then the mesh
    assert scene.name == "box" and budget.caster_faces(scene) == cube.n_faces
    assert (scene.light, scene.width) == (template().light, template().width)


def test_measure_gives_every_stage_on_both_renderers():
    """One tiny scene, one detector: 2 cases x 2 renderers x 6 stages; the software counts equal a fresh frame's."""
    pytest.importorskip("moderngl", reason="moderngl not installed (pip install -e '.[gl]')")
    from silcount.errors import NoOpenGL

    try:
        table = budget.measure([template()], ["reference"], repeat=1, sizes=[32])
    except NoOpenGL as err:
        pytest.skip(str(err))
    assert len(table) == 2 * 2 * 6
    sw = table[(table.renderer == "software") & (table.method == "zfail")].set_index("stage")
    fresh = frame_stages(template(), "zfail", "reference", resolution=(32, 32)).set_index("stage")
    assert sw["fragments"].tolist() == fresh["fragments"].tolist()
    assert sw["stencil_updates"].tolist() == fresh["stencil_updates"].tolist()
    gl = table[(table.renderer == "llvmpipe") & (table.method == "pertriangle")]
    assert gl["operations"].isna().all() and (gl["frame_seconds"] > 0).all()


def test_the_committed_counts_are_this_code_s():
    """The committed file's counts for cube_on_floor at 512^2 equal a frame rendered now (counts are exact), given
    the scene's clip coordinates as the measurement gives them (:func:`silcount.render.budget.software_rows`)."""
    from silcount.render.opengl import scene_clip

    table, meta = budget.read()
    rows = table[(table.scene == "cube_on_floor") & (table["size"] == 512) & (table.renderer == "software")]
    scene = template().with_resolution(512, 512)
    for method, detector in (("zfail", "ta"), ("pertriangle", "")):
        got = rows[(rows.method == method) & (rows.detector == detector)].set_index("stage")
        fresh = frame_stages(scene, method, detector or "reference", scene_clip=scene_clip(scene)).set_index("stage")
        ops = fresh[["add", "mul", "cmp", "read", "write", "div"]].sum(axis=1)
        assert got["operations"].astype(int).tolist() == ops.astype(int).tolist()
        assert got["fragments"].astype(int).tolist() == fresh["fragments"].tolist()
    assert meta["load_before"] and meta["command"].startswith("python -m benchmarks.frame_budget")


def test_the_committed_stage_times_add_up_to_the_frames():
    """The issue's target on the committed data: every frame's stage sum within 5 % of its wall time."""
    table, _ = budget.read()
    sums = report_budget.stage_sums(table)
    assert set(sums.renderer) == {"software", "llvmpipe"}
    assert (sums["within 5 %"] == "yes").all(), sums.to_string()


def test_crossing_finds_the_face_count_of_a_known_power_law():
    """share = 1e-3 F^0.5 is 10 % at F = 10^4 (by hand: 0.1 / 1e-3 = 100 = F^0.5)."""
    faces = np.array([100.0, 1000.0, 10000.0, 100000.0])
    b, at, note = report_budget.crossing(faces, 1e-3 * faces**0.5)
    assert b == pytest.approx(0.5) and at == pytest.approx(1e4)
    assert note == "below 10 % for F < F10; within the measured F"
    b, at, note = report_budget.crossing(faces, 0.05 * faces**-0.1)
    assert np.isnan(at) and note.startswith("below 10 % at every F")


def test_fps_answers_hsd_against_ta():
    """69.93 -> 75.53 FPS: the frame shortens by 1 - 69.93/75.53 = 7.41 % (by hand); the papers' model at
    n = E/6 times TA at 3.49 ms and HSD at 1.17 ms (calibrate.fps's table); EESD is slower than TA in that model,
    so no share produces EESD's gain."""
    sh = pd.DataFrame(
        {
            "scene": "s",
            "faces": 1,
            "size": 512,
            "method": "zfail",
            "detector": ["ta", "vnv"],
            "stage": "detection",
            "ops_share": 0.5,
            "software": [0.02, 0.3],
            "llvmpipe": [0.01, 0.2],
        }
    )
    answers = report_budget.fps_answers(sh).set_index(["change", "reading"])
    hsd = answers.loc[("TA 69.93 -> HSD 75.53", report_budget.N_READINGS[0][0])]
    assert hsd["printed shortening %"] == pytest.approx(7.41, abs=0.005)
    assert hsd["model detection ms"] == "3.49 -> 1.17"
    k = 3.4911 / 1.1697
    assert float(hsd["needed s %"]) == pytest.approx(100 * 0.074143 / (1 - 1 / k), abs=0.05)
    assert hsd["FPS at that s (software)"] == pytest.approx(69.93 / (0.98 + 0.02 / k), abs=0.01)
    eesd = answers.loc[("TA 69.93 -> EESD 73.16", report_budget.N_READINGS[0][0])]
    assert eesd["k"] < 1 and eesd["needed s %"] == "none (k <= 1)"


def test_the_report_is_the_same_twice(tmp_path):
    """Rendered from committed data: two runs write the same bytes."""
    first = report_budget.report(tmp_path / "a")
    second = report_budget.report(tmp_path / "b")
    assert [p.name for p in first] == ["budget.md", "budget-shares.csv", "budget-stages.png", "budget-stages.svg"]
    for a, b in zip(first, second, strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name
    text = first[0].read_text()
    assert "# The frame budget" in text and "## The papers' frame rates, answered" in text


def test_hsd_fps_gain_claim_is_judged_by_amdahl_under_each_reading():
    """'We could increase the FPS from 69.93 to 75.53 using the proposed algorithm' (HSD paper Sec. II):
    under e_n = 6n the papers' model puts TA at 3.49 ms of a 14.30 ms frame (calibrate.fps's printed closed
    form, a second path to the same model) and the gain is possible; read as faces TA alone takes 55.7 ms,
    more than the frame, so no share can produce it: the readings disagree."""
    from silcount.calibrate.fps import paper_cycles
    from silcount.counting import models
    from silcount.papers.claims.base import AMBIGUOUS
    from silcount.papers.claims.fps import RULES

    data = next(c for c in models.load("hsd2011-claims")["claims"] if c["id"] == "hsd-fps-gain")
    claim = RULES[data["check"]](data, "hsd2011", None)
    assert claim.verdict == AMBIGUOUS
    ta_ms = 1e3 * paper_cycles("hsd2011-ta", 2207 / 6, 3) / 2.8e9
    by_n = {r.reading.split(" (")[0]: r for r in claim.readings}
    assert f"TA {ta_ms:.3g} ms" in by_n["n = E/6 = 367.8"].outcome and by_n["n = E/6 = 367.8"].holds
    assert (
        not by_n["n = F = 2E/3 = 1471.3"].holds
        and "390 % of its 14.3 ms frame" in by_n["n = F = 2E/3 = 1471.3"].outcome
    )
    assert "7.41 % shorter" in claim.reason


def test_leads_counts_each_frames_largest_stage():
    """Three frames by hand: b leads the first and third, a the second, c none."""
    got = budget.leads(["a", "b", "c"], [[1.0, 3.0, 2.0], [4.0, 1.0, 0.0], [0.0, 5.0, 1.0]])
    assert got == {"a": 1, "b": 2, "c": 0}


def _frame(
    sw: dict[str, tuple[float, int]], gl: dict[str, tuple[float, int]], ms: tuple[float, float] = (1.0, 1.0)
) -> pd.DataFrame:
    """A shares table of one frame: stage -> (time share, frames led) per renderer; ``ms``: each renderer's frame
    time in milliseconds (a stage's is its share of it)."""
    return pd.DataFrame(
        [
            {
                "scene": "s",
                "faces": 1,
                "size": 8,
                "method": "zfail",
                "detector": "reference",
                "stage": st,
                "ops_share": 0.5,
                "software": sw[st][0],
                "llvmpipe": gl[st][0],
                "software_ms": sw[st][0] * ms[0],
                "llvmpipe_ms": gl[st][0] * ms[1],
                "software_leads": sw[st][1],
                "llvmpipe_leads": gl[st][1],
            }
            for st in sw
        ]
    )


@pytest.mark.parametrize(
    ("gl_depth", "gl_stencil", "verdict"),
    [((0.6, 3), (0.4, 0), "yes"), ((0.4, 0), (0.6, 3), "NO"), ((0.45, 1), (0.55, 2), "unsettled")],
)
def test_dominance_says_yes_no_or_unsettled(gl_depth, gl_stencil, verdict):
    """The software's depth pass led all 3 of its frames; llvmpipe's leader: the same, another in all 3 frames
    (a disagreement), another in 2 of 3 (its lead within its own spread)."""
    none = (0.0, 0)
    sh = _frame(
        {"detection": none, "depth": (0.6, 3), "stencil": (0.4, 0)},
        {"detection": none, "depth": gl_depth, "stencil": gl_stencil},
    )
    row = report_budget.dominance(sh).iloc[0]
    assert row["agree"] == verdict and row["sw led"] == "3/3"


def test_a_detection_lead_is_compared_in_milliseconds():
    """By hand: a 2 ms software frame (detection 1.0 ms, depth 0.6, stencil 0.4) against a 4 ms llvmpipe frame
    (detection 1.0 ms, depth 1.2, stencil 1.8): detection took 1.00 times as long, the other stages 3.0/1.0."""
    sh = _frame(
        {"detection": (0.5, 3), "depth": (0.3, 0), "stencil": (0.2, 0)},
        {"detection": (0.25, 0), "depth": (0.3, 0), "stencil": (0.45, 3)},
        ms=(2.0, 4.0),
    )
    dom = report_budget.dominance(sh)
    row = dom.iloc[0]
    assert (row["software"], row["llvmpipe"], row["agree"]) == ("detection", "stencil", "NO")
    assert (row["detection sw/gl"], row["rest gl/sw"], row["detection sw/gl ms"]) == (1.0, 3.0, "1.00/1.00")
    text = report_budget.detection_led_alone(dom)
    assert "In the 1 of them" in text and "took 1.00-1.00 times" in text and "3.00-3.00 times" in text
    assert report_budget.detection_led_alone(dom.assign(agree="yes")) == ""
