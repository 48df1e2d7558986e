"""``$SILCOUNT_MODELS_DIR`` really replaces the cost models (found by mutation testing: nothing checked it)."""

from __future__ import annotations

import shutil

from silcount.counting import models as paper


def _clear() -> None:
    paper.load.cache_clear()
    paper.step_costs.cache_clear()


def test_models_dir_override_is_used(tmp_path, monkeypatch):
    shutil.copytree(paper.models_dir(), tmp_path / "models")
    toml = tmp_path / "models" / "papers" / "eesd2012" / "eesd2012-vnv.toml"
    text = toml.read_text()
    # EESD 2012 Sec. 5.2 charges the counter increment 1 A; a user's own model charges 5 A
    assert text.count('cost = { add = "1" }') == 1
    toml.write_text(text.replace('cost = { add = "1" }', 'cost = { add = "5" }'))
    params = {"e_n": 6, "f_n": 4, "m": 3.0}
    _clear()
    assert paper.paper_tally("eesd2012-vnv", {"counter": 3}, params)["add"] == 3
    monkeypatch.setenv("SILCOUNT_MODELS_DIR", str(tmp_path / "models"))
    _clear()
    try:
        assert paper.models_dir() == tmp_path / "models"
        assert paper.paper_tally("eesd2012-vnv", {"counter": 3}, params)["add"] == 15
    finally:
        monkeypatch.delenv("SILCOUNT_MODELS_DIR")
        _clear()
    assert paper.paper_tally("eesd2012-vnv", {"counter": 3}, params)["add"] == 3


def test_each_detector_is_priced_by_its_own_paper_model():
    # The closed forms each result's `paper` tally comes from: TA, VnV and EESD as the EESD paper
    # (2012) prints them, HSD as the HSD paper (2011) does, the reference by silcount's own model.
    import silcount

    expected = {
        "reference": "silcount-reference",
        "ta": "eesd2012-ta",
        "vnv": "eesd2012-vnv",
        "hsd": "hsd2011-hsd",
        "eesd": "eesd2012-eesd",
    }
    mesh, light = silcount.builtin_mesh("tetrahedron"), silcount.PointLight((5.0, 5.0, 5.0))
    for name, model in expected.items():
        assert silcount.detect(mesh, light, name).paper_model == model
        assert paper.model_path(model).is_file()
