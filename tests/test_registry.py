"""The detector registry: specs checked, plug-ins found through their entry points on first use, broken ones
left out with one line naming them while the built-ins keep working, and a detector lacking parts running
everywhere with its empty columns said so.  Each plug-in case runs in a fresh process (the registry fills
once per process), from a site folder of :mod:`tests.plugins`."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from plugins import BARE, REPO, env_with, scene, silcount, site

from silcount.detectors.spec import DetectorSpec

BUILT_INS = ("reference", "ta", "vnv", "hsd", "eesd", "gaussmap", "cones")


def _detect(*args, **kw):
    raise AssertionError("not called")


@pytest.mark.parametrize(
    "change, message",
    [
        ({"name": "a:b"}, "letters, digits"),
        ({"label": ""}, "label"),
        ({"detect": 3}, "detect must be callable"),
        ({"role": "paper-ish"}, "role"),
        ({"variants": ("literal",)}, "'intended'"),
        ({"engines": ("naive",)}, "engines 'fast'"),
        ({"engines": ("fast", "gpu")}, "engines"),
        ({"growth_variant": "literal"}, "growth_variant"),
        ({"style": ("#000000",)}, "style"),
        ({"plain_setup": print}, "plain_setup without plain_edge_ids"),
    ],
)
def test_a_spec_with_a_malformed_field_is_refused(change, message):
    fields = {"name": "x", "label": "x", "detect": _detect} | change
    with pytest.raises(ValueError, match=message):
        DetectorSpec(**fields)


def test_a_spec_lacking_a_required_field_cannot_be_made():
    with pytest.raises(TypeError, match="label"):
        DetectorSpec(name="x", detect=_detect)  # type: ignore[call-arg]


def test_what_a_spec_lacks_is_named():
    bare = DetectorSpec(name="x", label="x", detect=_detect)
    assert bare.missing == ("naive engine", "paper model", "plain loops")
    full = DetectorSpec(
        name="x", label="x", detect=_detect, engines=("fast", "naive"), paper_model="m", plain_edge_ids=_detect
    )
    assert full.missing == ()


def _python(code: str, env: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)


def test_import_silcount_discovers_nothing_and_register_detector_adds_after_the_built_ins(tmp_path):
    """Discovery is on first use: ``import silcount`` loads no registry and warns of no broken plug-in."""
    env = env_with(site(tmp_path, "gone", {"gone": "no_such_module_here:SPEC"}, {}))
    code = (
        "import sys, silcount\n"
        "assert 'silcount.detectors.registry' not in sys.modules, 'discovered at import'\n"
        "from silcount.errors import BadArgument\n"
        "spec = silcount.DetectorSpec(name='mine', label='mine', detect=print)\n"
        "silcount.register_detector(spec)\n"
        "print(','.join(silcount.DETECTORS))\n"
        "for bad in (spec, 'not a spec'):\n"
        "    try:\n"
        "        silcount.register_detector(bad)\n"
        "    except BadArgument as exc:\n"
        "        print(exc)\n"
    )
    got = _python("import silcount\nimport sys\nprint(sorted(m for m in sys.modules if 'registry' in m))", env)
    assert got.returncode == 0 and got.stdout.strip() == "[]" and got.stderr == "", got.stderr
    got = _python(code, env)
    assert got.returncode == 0, got.stderr
    assert got.stdout.splitlines() == [
        "reference,ta,vnv,hsd,eesd,gaussmap,cones,mine",
        "register_detector: the name 'mine' is taken by the registered detector",
        "register_detector: expected a silcount DetectorSpec, got str",
    ]
    assert got.stderr.count("\n") == 1 and "plug-in 'gone'" in got.stderr  # the broken plug-in, at first use


BROKEN = {
    "import": ({"gone": "no_such_module_here:SPEC"}, {}, "plug-in 'gone' (no_such_module_here:SPEC) left out: "
               "ModuleNotFoundError: No module named 'no_such_module_here'"),
    "field": ({"lack": "lackplug:SPEC"}, {"lackplug": "from silcount import DetectorSpec\n"
               "SPEC = DetectorSpec(name='lack', detect=print)\n"},
              "plug-in 'lack' (lackplug:SPEC) left out: TypeError: DetectorSpec.__init__() missing 1 required "
              "keyword-only argument: 'label'"),
    "not a spec": ({"loose": "looseplug:SPEC"}, {"looseplug": "SPEC = {'name': 'loose', 'detect': print}\n"},
                   "plug-in 'loose' (looseplug:SPEC) left out: expected a silcount DetectorSpec, got dict"),
    "collision": ({"ta": "taplug:SPEC"}, {"taplug": "from silcount import DetectorSpec\n"
                  "SPEC = DetectorSpec(name='ta', label='impostor', detect=print)\n"},
                  "plug-in 'ta' (taplug:SPEC) left out: the name 'ta' is taken by the built-in detector"),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(BROKEN))
def test_a_broken_plugin_is_one_line_naming_it_and_the_built_ins_keep_working(tmp_path, case):
    entry_points, modules, line = BROKEN[case]
    env = env_with(site(tmp_path, case.replace(" ", "_"), entry_points, modules))
    args = ["audit", "data/tetrahedron.obj", "--random-lights", "2", "--format", "json", "--quiet"]
    got = silcount(args, env, cwd=REPO)  # every registered detector: the registry fills, the plug-ins are read
    assert got.returncode == 0, got.stderr
    assert got.stderr.splitlines() == [f"silcount:0: PluginWarning: detector {line}"]
    audit = json.loads(got.stdout)
    assert list(audit["detectors"]) == list(BUILT_INS) and audit["detectors"]["ta"]["agrees_with_reference"]
    got = silcount([*args, "--detectors", "reference,ta"], env, cwd=REPO)  # built-ins by name: no plug-in read
    assert got.returncode == 0 and got.stderr == "", got.stderr
    assert list(json.loads(got.stdout)["detectors"]) == ["reference", "ta"]
    name = next(iter(entry_points))
    if case != "collision":  # asked for by name, the left-out plug-in is an unknown detector that says why
        got = silcount([*args, "--detectors", name], env, cwd=REPO)
        assert got.returncode == 2
        assert got.stderr.splitlines()[-1].startswith(
            f"silcount audit: error: --detectors: detector {name!r}: its plug-in was left out: "
        )


def test_a_detector_lacking_parts_runs_everywhere_and_says_what_is_empty(tmp_path):
    """No naive engine, no paper model, no plain loops: audit, corpus and render run it; the empty columns
    are empty and the outputs say so."""
    env = env_with(site(tmp_path / "site", "bare", {"bare": "bareplug:SPEC"}, {"bareplug": BARE}))
    args = ["audit", "data/tetrahedron.obj", "--detectors", "reference,bare", "--random-lights", "2", "--quiet"]
    got = silcount([*args, "--format", "json"], env, cwd=REPO)
    assert got.returncode == 0, got.stderr
    audit = json.loads(got.stdout)
    assert "detector bare: no paper cost model, its paper columns are empty" in audit["warnings"]
    bare = audit["detectors"]["bare"]
    assert list(bare["tallies"]) == ["true"] and bare["agrees_with_reference"] and bare["formula_printed"] is None
    got = silcount([*args, "--format", "md"], env, cwd=REPO)
    assert got.returncode == 0, got.stderr
    paper = got.stdout.split("## Detectors, paper cost model")[1].split("##")[0]
    lines = [line for line in paper.splitlines() if line.startswith("|")]
    rows = {line.split("|")[1].strip(): [c.strip() for c in line.strip("|").split("|")] for line in lines}
    bare, ref = rows["bare"], rows["reference"]  # the same rule: the same edges; its tallies and cycles empty
    assert bare[1:3] == ref[1:3] and ref[3] != "" and bare[3:-3] == [""] * (len(bare) - 6)
    got = silcount([*args, "--engine", "naive", "--format", "json"], env, cwd=REPO)
    assert got.returncode == 0, got.stderr
    audit = json.loads(got.stdout)
    assert list(audit["detectors"]) == ["reference"]
    assert "detector bare: no naive engine, left out of this audit" in audit["warnings"]

    got = silcount(["corpus", "data/tetrahedron.obj", "--detectors", "reference,bare", "--lights", "2",
                    "--scheduler", "threads", "--workers", "1", "--no-cache", "--quiet"], env, cwd=REPO)  # fmt: skip
    assert got.returncode == 0, got.stderr
    assert "detector bare: no paper model, its paper_ columns are empty" in got.stdout
    assert "detector bare: no plain loops, its time column is empty" in got.stdout

    out = tmp_path / "bare.png"
    got = silcount(["render", str(scene(tmp_path)), "--method", "zfail", "--detector", "bare", "--out", str(out)],
                   env)  # fmt: skip
    assert got.returncode == 0 and out.exists(), got.stderr
    assert "bare intended" in got.stdout


def test_a_built_in_asked_for_by_name_imports_no_other_detector():
    """``get('reference')`` in a fresh process: the reference's module is imported, no other detector's, and
    no plug-in is looked for (the registry has not filled)."""
    code = (
        "import sys; from silcount.detectors import get, registry; spec = get('reference'); "
        "print(spec.name, registry._state['discovered'], "
        "sorted(m for m in sys.modules if m.split('.')[-1] in ('ta', 'vnv', 'hsd', 'gaussmap', 'cones', 'eesd')))"
    )
    got = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    assert got.stdout.split(None, 2) == ["reference", "False", "[]\n"]
