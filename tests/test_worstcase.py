"""The worst-case search (silcount/worstcase, ``silcount worst-case``): witnesses that re-run from their files,
shrinking that keeps the property, determinism, and "not found" where nothing can exceed the bound."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import jsonschema
import pytest
import sympy as sp

from silcount.counting import models
from silcount.detectors import detect
from silcount.errors import BadArgument
from silcount.worstcase import worst_case
from silcount.worstcase.files import load_witness
from silcount.worstcase.search import SIMPLER
from silcount.worstcase.space import CLOSED_SHAPES, ORDERS, Genome, build
from tests.common import run_cli

BUDGET = 60


def printed_line_1(model: str, params: dict) -> dict[str, float]:
    """The model's first printed line at a run's ``f_n, e_n, m``, read by the claims' parser
    (:mod:`silcount.papers.formulas`), not the search's."""
    from silcount.papers import formulas as F

    subs = {F.LOCALS[k]: sp.nsimplify(v) for k, v in params.items()}
    return {k: float(x.subs(subs)) for k, x in F.printed_lines(model)[0].form.items()}


@pytest.fixture(scope="module")
def hsd_witness(tmp_path_factory):
    out = tmp_path_factory.mktemp("hsd")
    return worst_case("hsd", model="paper", kind="any", bound="hsd2011-hsd", budget=BUDGET, out=out), out


def test_a_found_witness_exceeds_the_bound_when_rerun_from_its_files(hsd_witness):
    result, out = hsd_witness
    assert result.found
    mesh, light, record = load_witness(out / "witness.light.json")
    assert mesh.is_watertight
    run = detect(mesh, light, "hsd", variant=result.outcome.numbers["variant"], engine="naive")
    cost = models.paper_tally("hsd2011-hsd", run.steps, run.paper_params)
    bound = printed_line_1("hsd2011-hsd", run.paper_params)
    over = [k for k in cost if cost[k] > bound[k]]
    assert over and over == result.outcome.numbers["over"]
    assert record["genome"]["shape"] == result.outcome.genome.shape


def test_shrinking_keeps_the_property_and_no_simpler_genome_keeps_it_smaller(hsd_witness):
    result, _ = hsd_witness
    g = result.outcome.genome
    faces = result.outcome.numbers["faces"]

    def exceeds(genome: Genome) -> tuple[bool, int]:
        mesh, light = build(genome)
        best = False
        for variant in ("intended", "literal"):
            run = detect(mesh, light, "hsd", variant=variant, engine="fast")
            cost = models.paper_tally("hsd2011-hsd", run.steps, run.paper_params)
            bound = printed_line_1("hsd2011-hsd", run.paper_params)
            best |= any(cost[k] > bound[k] for k in cost)
        return best and mesh.is_watertight, mesh.n_faces

    assert exceeds(g) == (True, faces)
    neighbours = [replace(g, level=lv) for lv in range(1, g.level)]
    neighbours += [replace(g, **{k: v}) for k, v in SIMPLER if getattr(g, k) != v]
    for n in neighbours:
        met, n_faces = exceeds(n)
        assert not (met and n_faces < faces), n


def test_the_same_seed_gives_the_same_witness_byte_for_byte(tmp_path):
    texts = []
    for i in range(2):
        worst_case("hsd", model="paper", kind="any", bound="hsd2011-hsd", budget=BUDGET, seed=3, out=tmp_path / str(i))
        texts.append(
            [(tmp_path / str(i) / n).read_bytes() for n in ("summary.json", "witness.obj", "witness.light.json")]
        )
    assert texts[0] == texts[1]


def test_a_bound_nothing_can_exceed_is_not_found():
    """The reference scan's true cost is a fixed cost per face (its facing test, under 60 operations) and per
    edge (under 20): 1000 (f_n + e_n) is far above it, so no execution may be reported as exceeding it."""
    result = worst_case("reference", bound="1000*(f_n + e_n)", budget=25, closed_only=False)
    assert not result.found and result.outcome.genome is None
    assert result.outcome.evaluations == 25
    assert 0 < result.outcome.numbers["ratio"] < 0.1


def test_the_hypothesis_method_finds_a_witness_too():
    result = worst_case("hsd", model="paper", kind="any", bound="hsd2011-hsd", budget=BUDGET, method="hypothesis")
    assert result.found and result.outcome.evaluations <= BUDGET + 100  # shrinking's own evaluations


def test_every_face_order_keeps_the_faces_and_the_light():
    """A face order renumbers the faces and nothing else: the same polygons, the same light."""
    base_mesh, base_light = build(Genome(shape="icosphere", level=2))
    polys = sorted(tuple(sorted(f)) for f in base_mesh.faces.tolist())
    for order in ORDERS:
        mesh, light = build(Genome(shape="icosphere", level=2, order=order))
        assert light == base_light and sorted(tuple(sorted(f)) for f in mesh.faces.tolist()) == polys, order


@pytest.mark.parametrize("shape", CLOSED_SHAPES)
def test_the_closed_shapes_are_closed_and_consistently_wound(shape):
    for level in (1, 3):
        mesh, _ = build(Genome(shape=shape, level=level, subdiv=1))
        assert mesh.is_watertight, (shape, level)


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"bound": None}, "needs a bound"),
        ({"bound": "x*f_n"}, "unknown symbols"),
        ({"bound": "hsd2011-ta:9"}, "no printed line 9"),
        ({"bound": "f_n", "kind": "bytes"}, "operation kind"),
        ({"bound": "f_n", "detector": "nosuch"}, "unknown detector"),
        ({"bound": "f_n", "variant": "other"}, "no variant"),
        ({"bound": "f_n", "budget": 0}, "budget"),
        ({"goal": "family", "bound": "f_n"}, "goal 'exceed' only"),
    ],
)
def test_bad_arguments_fail_with_one_line(kwargs, needle):
    kwargs = {"detector": "ta", **kwargs}
    with pytest.raises(BadArgument, match=needle) as info:
        worst_case(kwargs.pop("detector"), **kwargs)
    assert "\n" not in str(info.value)


def test_the_command_line_reports_a_bad_bound_in_one_line_with_exit_2():
    rc, _, err = run_cli("worst-case", "--detector", "ta", "--bound", "f_n**(")
    assert rc == 2
    assert err.count("\n") == 1 and "not a closed form" in err


def test_the_api_returns_a_frame_and_the_summary_names_the_files(hsd_witness):
    result, out = hsd_witness
    df = result.frame()
    assert len(df) == 1 and bool(df["found"].iloc[0]) and df["evaluations"].iloc[0] == result.outcome.evaluations
    summary = json.loads((out / "summary.json").read_text())
    assert summary["files"] == {"mesh": "witness.obj", "light": "witness.light.json"} and summary["found"]
    schema = json.loads((Path(__file__).resolve().parent.parent / "docs/schemas/worst-case.schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    jsonschema.validate(summary, schema)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({**summary, "goal": "fastest"}, schema)


def test_cycles_under_a_profile_are_a_measure():
    """Cycles under a built-in profile are the tally weighed kind by kind (weights read from the profile)."""
    from silcount.counting.cycles import builtin_profiles
    from silcount.worstcase.objective import Measure

    name = next(iter(builtin_profiles()))
    weights = builtin_profiles()[name].weights
    tally = {"add": 2, "mul": 3, "cmp": 5, "read": 7, "write": 11}
    expected = sum(weights[k] * v for k, v in tally.items())
    assert Measure("ta", profile=name).value(tally) == pytest.approx(expected)
