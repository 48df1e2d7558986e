"""``check_choice``: the one "unknown ...; choose from ..." check, and the messages its callers give."""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout

import pytest

from silcount.errors import BadArgument, check_choice


def test_a_choice_passes_and_returns_none():
    assert check_choice("colour", "red", ("red", "green")) is None
    assert check_choice("colour", "green", {"red": 1, "green": 2}) is None


def test_an_unknown_value_is_a_bad_argument_naming_every_choice_in_order():
    with pytest.raises(BadArgument) as e:
        check_choice("colour", "blue", ("red", "green"))
    assert str(e.value) == "unknown colour 'blue'; choose from red, green"
    assert e.value.exit_code == 2


def test_a_dict_offers_its_keys():
    with pytest.raises(BadArgument, match=r"^unknown shape 'disc'; choose from cube, ball$"):
        check_choice("shape", "disc", {"cube": 1, "ball": 2})


def test_prefix_and_error_type():
    with pytest.raises(ValueError, match=r"^--colours: unknown colour 7; choose from red$"):
        check_choice("colour", 7, ["red"], prefix="--colours: ", error=ValueError)


def test_the_callers_messages():
    from silcount.detectors import DETECTORS, ENGINES, VARIANTS, detect
    from silcount.mesh.lights import PointLight
    from silcount.mesh.shapes import BUILTIN, builtin_mesh

    mesh = builtin_mesh("tetrahedron")
    light = PointLight((3.0, 4.0, 5.0))
    cases = [
        (lambda: detect(mesh, light, "magic"), f"unknown detector 'magic'; choose from {', '.join(DETECTORS)}"),
        (lambda: detect(mesh, light, variant="x"), f"unknown variant 'x'; choose from {', '.join(VARIANTS)}"),
        (lambda: detect(mesh, light, engine="x"), f"unknown engine 'x'; choose from {', '.join(ENGINES)}"),
        (lambda: builtin_mesh("blob"), f"unknown built-in mesh 'blob'; choose from {', '.join(BUILTIN)}"),
    ]
    for call, message in cases:
        with pytest.raises(BadArgument) as e:
            call()
        assert str(e.value) == message


def test_the_cli_line_for_an_unknown_detector(tmp_path):
    from meshfiles import tetra_bytes, write

    from silcount.cli.main import main
    from silcount.detectors import DETECTORS

    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        rc = main(["audit", str(write(tmp_path, "t.obj", tetra_bytes("obj"))), "--detectors", "reference,magic"])
    assert rc == 2 and out.getvalue() == ""
    assert f"--detectors: unknown detector 'magic'; choose from {', '.join(DETECTORS)}" in err.getvalue()
