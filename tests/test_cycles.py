"""Cycle profiles: every profile weighs every kind the `true` model counts, each with its source (issue 11, 14)."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from silcount.calibrate import mca
from silcount.cli.main import main
from silcount.counting import cycles
from silcount.counting import models as paper_models
from silcount.errors import BadArgument

ALL = ("add", "mul", "cmp", "read", "write", "div", "sqrt")


def _toml(path):
    with open(path, "rb") as fh:
        return tomllib.load(fh)


def test_true_kinds_are_the_papers_five_and_div_sqrt():
    assert set(cycles.TRUE_KINDS) == set(ALL)


def test_every_builtin_profile_weighs_every_kind_with_a_source():
    profiles = cycles.builtin_profiles()
    assert {"paper", "unit", "skylake-latency", "skylake-throughput", "znver3-latency", "znver3-throughput"} <= set(
        profiles
    )
    for name, prof in profiles.items():
        assert set(ALL) <= set(prof.weights), name
        assert all(prof.sources.get(k) for k in ALL), name
        assert all(prof.weights[k] >= 0 for k in ("add", "mul", "div", "sqrt", "read")), name


def test_paper_profile_is_the_printed_weights_plus_a_labelled_extension():
    # EESD 2012 Sec. 6: "Mults 4 cycles, Adds 2 cycles, Compares 3 cycles, Reads 1 cycle and Writes 2 cycles"
    p = cycles.builtin_profiles()["paper"]
    assert {k: p.weights[k] for k in ("mul", "add", "cmp", "read", "write")} == {
        "mul": 4,
        "add": 2,
        "cmp": 3,
        "read": 1,
        "write": 2,
    }
    for k in ("div", "sqrt"):
        assert p.sources[k].startswith("extension, not in the paper")
    for k in ("mul", "add", "cmp", "read", "write"):
        assert "extension" not in p.sources[k]


def test_paper_extension_is_mul_times_the_smallest_llvm_mca_latency_ratio():
    """The documented rule, recomputed from the committed llvm-mca files (not from the extension file)."""
    files = sorted(cycles.cycles_dir().glob("*-llvm-mca.toml"))
    assert files
    ext = cycles.builtin_profiles()["paper"]
    for kind in ("div", "sqrt"):
        ratio = min(_toml(f)["latency"][kind]["value"] / _toml(f)["latency"]["mul"]["value"] for f in files)
        assert ext.weights[kind] == pytest.approx(4 * ratio)


def test_llvm_mca_files_have_the_issue_keys():
    files = sorted(cycles.cycles_dir().glob("*-llvm-mca.toml"))
    assert {f.name for f in files} >= {"skylake-llvm-mca.toml", "znver3-llvm-mca.toml"}
    for f in files:
        data = _toml(f)
        assert data["llvm_mcpu"] and data["llvm_version"]
        for table in ("latency", "rthroughput"):
            assert set(data[table]) == set(ALL)
            for kind, entry in data[table].items():
                assert set(entry) == {"value", "instruction"}
                assert entry["instruction"] == mca.INSTRUCTIONS[kind]
                assert entry["value"] > 0


def test_hand_cited_skylake_profile_is_gone():
    assert not (cycles.cycles_dir() / "skylake.toml").exists()
    assert cycles.builtin_profiles()["skylake-latency"].source.startswith("llvm-mca")


def test_a_profile_lacking_a_kind_is_refused_naming_it():
    with pytest.raises(BadArgument, match="sqrt"):
        cycles.Profile("mine", {k: 1.0 for k in ALL if k != "sqrt"}, "test")


def test_a_tally_with_an_unweighed_kind_fails_naming_it():
    p = cycles.builtin_profiles()["unit"]
    assert p.cycles({"add": 2, "div": 3, "sqrt": 1}) == 6
    with pytest.raises(BadArgument, match="fma"):
        p.cycles({"add": 1, "fma": 2})


count = st.one_of(st.just(0), st.integers(1, 10), st.integers(0, 2**52))
tally = st.permutations(ALL).flatmap(
    lambda kinds: st.tuples(*[count for _ in kinds]).map(lambda cs: dict(zip(kinds, cs, strict=True)))
)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(tally, st.builds(lambda t: dict(list(t.items())[:3]), tally)), max_size=12))
def test_cycles_many_is_cycles_bit_for_bit(tallies):
    # Kinds in any order (the sum's order follows the tally's), zero counts, counts up to 2**52, on every
    # built-in profile (weights such as 0.25 and 1.3333, whose sums round): the same doubles as cycles().
    profiles = list(cycles.builtin_profiles().values())
    for profile, got in zip(profiles, cycles.cycles_many(profiles, tallies), strict=True):
        expected = np.array([float(profile.cycles(t)) for t in tallies])
        assert got.tobytes() == expected.tobytes(), profile.name


@settings(max_examples=40, deadline=None)
@given(st.lists(st.lists(st.one_of(st.none(), count), min_size=len(ALL), max_size=len(ALL)), max_size=12))
def test_cycles_of_counts_is_cycles_bit_for_bit(rows):
    # Columns (a batch of lights): each row's tally holds the kinds whose count is not None, in ALL's order;
    # an absent kind is a negative count.  The same doubles as cycles() of each row's dict.
    profiles = list(cycles.builtin_profiles().values())
    tallies = [{k: c for k, c in zip(ALL, row, strict=True) if c is not None} for row in rows]
    counts = np.array([[-1 if c is None else c for c in row] for row in rows], dtype=np.int64)
    for profile, got in zip(profiles, cycles.cycles_of_counts(profiles, ALL, counts), strict=True):
        expected = np.array([float(profile.cycles(t)) for t in tallies])
        assert got.tobytes() == expected.tobytes(), profile.name


def test_cycles_of_counts_fails_on_an_unweighed_kind_naming_it():
    profiles = [cycles.builtin_profiles()["unit"]]
    assert cycles.cycles_of_counts(profiles, ("add", "fma"), np.array([[1, 0], [2, -1]]))[0].tolist() == [1.0, 2.0]
    with pytest.raises(BadArgument, match="fma"):
        cycles.cycles_of_counts(profiles, ("add", "fma"), np.array([[1, -1], [1, 2]]))


def test_cycles_many_fails_on_an_unweighed_kind_naming_it():
    profiles = [cycles.builtin_profiles()["unit"]]
    assert cycles.cycles_many(profiles, [{"add": 1, "fma": 0}])[0].tolist() == [1.0]
    with pytest.raises(BadArgument, match="fma"):
        cycles.cycles_many(profiles, [{"add": 1}, {"add": 1, "fma": 2}])


def test_user_profile_file(tmp_path):
    good = tmp_path / "mine.toml"
    good.write_text(
        'name = "mine"\n[weights]\nadd = 1\nmul = 2\ncmp = 3\nread = 4\nwrite = 5\ndiv = 6\n'
        'sqrt = { value = 7, source = "my notes" }\n'
    )
    p = cycles.load_profile(str(good))
    named = tmp_path / "file-stem.toml"
    named.write_text(good.read_text())
    assert cycles.load_profile(str(named)).name == "mine"  # the file's own name, not its stem
    assert p.name == "mine" and p.weights["sqrt"] == 7 and p.sources["sqrt"] == "my notes"
    assert p.cycles({"add": 1, "div": 1, "sqrt": 2}) == 1 + 6 + 14
    bad = tmp_path / "five.toml"
    bad.write_text("[weights]\nadd = 1\nmul = 1\ncmp = 1\nread = 1\nwrite = 1\n")
    with pytest.raises(BadArgument, match="div, sqrt"):
        cycles.load_profile(str(bad))


def test_cli_fails_naming_the_missing_kind(tmp_path, capsys):
    bad = tmp_path / "five.toml"
    bad.write_text("[weights]\nadd = 1\nmul = 1\ncmp = 1\nread = 1\nwrite = 1\ndiv = 1\n")
    assert main(["calibrate", "--profile", str(bad), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "sqrt" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_measured_profiles_are_in_nanoseconds_with_methods():
    measured = cycles.measured_profiles()
    assert measured, "no committed silcount/models/cycles/measured-*.toml"
    for name, prof in measured.items():
        assert prof.unit == "ns" and name.split("-measured-")[1] in ("latency", "throughput", "latency-dram")
        assert all(prof.sources[k] for k in ALL)
    lat = next(p for n, p in measured.items() if n.endswith("-latency"))
    dram = next(p for n, p in measured.items() if n.endswith("-latency-dram"))
    assert dram.weights["read"] > lat.weights["read"]


def test_labels_and_sources_are_the_files_own():
    # What calibrate prints beside every weight (its name, unit, description and per-kind source),
    # read here straight from the committed TOML files and the paper's section.
    profiles = cycles.builtin_profiles()
    unit = profiles["unit"]
    assert (unit.source, set(unit.sources.values())) == ("every operation 1", {"1 by definition"})
    paper = profiles["paper"]
    section = paper_models.load("eesd2012-paper")["cycle_weights"]["section"]
    assert (paper.name, paper.unit) == ("paper", "cycles")
    assert paper.source == f"EESD paper Sec. {section} (div, sqrt: extension)"
    assert all(paper.sources[k] == f"EESD paper Sec. {section}" for k in ("mul", "add", "cmp", "read", "write"))
    for path in sorted(cycles.cycles_dir().glob("*-llvm-mca.toml")):
        data = _toml(path)
        for table, suffix in (("latency", "latency"), ("rthroughput", "throughput")):
            prof = profiles[f"{data['llvm_mcpu']}-{suffix}"]
            assert prof.unit == "cycles"
            assert prof.source == f"llvm-mca {data['llvm_version']} -mcpu={data['llvm_mcpu']} {table}"
            assert prof.sources == {k: data[table][k]["instruction"] for k in ALL}
    for path in sorted(cycles.cycles_dir().glob("measured-*.toml")):
        data = _toml(path)
        prof = profiles[f"{data['name']}-measured-latency"]
        assert prof.source == f"{path.name} [latency]"
        assert prof.sources == {k: str(data["latency"][k]["method"]) for k in ALL}


def test_refusals_list_the_kinds_plainly():
    with pytest.raises(BadArgument, match=r"^cycle profile mine lacks a weight for div, sqrt$"):
        cycles.Profile("mine", {k: 1.0 for k in ALL if k not in ("div", "sqrt")}, "test")
    with pytest.raises(BadArgument, match=r"^cycle profile unit has no weight for fma, fms$"):
        cycles.builtin_profiles()["unit"].cycles({"fma": 1, "fms": 2})
