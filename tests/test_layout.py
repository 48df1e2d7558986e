"""The package's architecture, checked: imports point down the layers, no cycles, small modules, lazy imports.

Layers, lowest first (README, "Layout"): a module may import its own
subpackage and any lower layer, never a higher one or a sibling of its layer,
so that the units of one layer are independent of each other (the
"layers" and "independence" contracts of import-linter, in one table).
"""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parent.parent / "silcount"

LAYERS: list[tuple[str, ...]] = [
    ("silcount.errors", "silcount.version"),
    ("silcount.atomic", "silcount.progress"),  # atomic raises silcount.errors' UnwritableOutput
    ("silcount.plots", "silcount.counting", "silcount.mesh"),  # independent of each other
    ("silcount.detectors",),
    ("silcount.render", "silcount.study", "silcount.calibrate"),  # the measurements, independent of each other
    ("silcount.papers",),
    ("silcount.audit",),
    ("silcount.cli",),
    ("silcount",),
]
MAX_LINES = 400


def module_name(path: Path) -> str:
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted(PKG.rglob("*.py"))}


def unit_of(name: str) -> str:
    """The layer unit a module belongs to: its subpackage, or itself for a top-level module."""
    for layer in LAYERS:
        for unit in sorted(layer, key=len, reverse=True):
            if name == unit or name.startswith(unit + "."):
                return unit
    raise AssertionError(f"{name} is in no layer of tests/test_layout.py")


def rank(unit: str) -> int:
    return next(i for i, layer in enumerate(LAYERS) if unit in layer)


def imports_of(name: str, path: Path, known: set[str]) -> set[str]:
    """Every silcount module ``name`` imports, at the top or inside a function (``TYPE_CHECKING`` too)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            targets = [f"{mod}.{a.name}" if f"{mod}.{a.name}" in known else mod for a in node.names]
        else:
            continue
        out.update(t for t in targets if t == "silcount" or t.startswith("silcount."))
    out.discard(name)
    return out


GRAPH = {name: imports_of(name, path, set(modules())) for name, path in modules().items()}


def test_every_module_is_in_a_layer():
    for name in GRAPH:
        unit_of(name)


@pytest.mark.parametrize("name", sorted(GRAPH))
def test_imports_point_down_the_layers(name):
    here = unit_of(name)
    for target in GRAPH[name]:
        there = unit_of(target)
        if there == here:
            continue
        assert rank(there) < rank(here), (
            f"{name} imports {target}: {here} may not import {there} (same or higher layer)"
        )


def test_no_import_cycles():
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(n: str) -> None:
        state[n] = 1
        stack.append(n)
        for m in sorted(GRAPH.get(n, ())):
            if m not in GRAPH:
                continue
            if state.get(m) == 1:
                cycle = stack[stack.index(m) :] + [m]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if m not in state:
                visit(m)
        stack.pop()
        state[n] = 2

    for n in sorted(GRAPH):
        if n not in state:
            visit(n)


def test_the_checker_sees_a_cycle_and_an_upward_import(tmp_path):
    """The two checks above can fail: a planted upward import is a higher rank, a planted cycle is found."""
    assert rank(unit_of("silcount.cli.main")) > rank(unit_of("silcount.detectors.ta"))
    assert unit_of("silcount.detectors.ta") == "silcount.detectors"
    planted = tmp_path / "m.py"
    planted.write_text("from silcount.cli import main\nfrom . import base\n")
    got = imports_of("silcount.detectors.m", planted, set(GRAPH))
    assert got == {"silcount.cli.main", "silcount.detectors.base"}


@pytest.mark.parametrize("name", sorted(GRAPH))
def test_modules_are_small(name):
    lines = len(modules()[name].read_text().splitlines())
    assert lines <= MAX_LINES, f"{name} has {lines} lines (at most {MAX_LINES})"


SCRIPTS = PKG.parent / "scripts"


@pytest.mark.parametrize("path", sorted(SCRIPTS.glob("*.py")), ids=lambda p: p.name)
def test_scripts_are_small_and_import_the_installed_package(path):
    """The package's size rule holds for scripts/ too, and no script edits ``sys.path`` to find silcount."""
    text = path.read_text()
    lines = len(text.splitlines())
    assert lines <= MAX_LINES, f"scripts/{path.name} has {lines} lines (at most {MAX_LINES})"
    assert "sys.path.insert" not in text, f"scripts/{path.name} edits sys.path: import silcount as installed"


HEAVY = ("sympy", "trimesh", "matplotlib")


def _loaded_after(code: str) -> set[str]:
    env = dict(os.environ)
    probe = code + "\nimport sys\nprint(' '.join(sorted({m.split('.')[0] for m in sys.modules})))\n"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env, check=True)
    return set(out.stdout.split()) & set(HEAVY)


def test_import_silcount_loads_nothing_heavy():
    assert _loaded_after("import silcount") == set()


def test_cli_parser_loads_nothing_heavy():
    assert _loaded_after("from silcount.cli.main import build_parser; build_parser()") == set()


def test_render_and_compare_load_nothing_heavy(tmp_path):
    data = PKG.parent / "data"
    for name in ("triangle_cube.obj", "plane.obj"):
        (tmp_path / name).write_bytes((data / name).read_bytes())
    scene = tmp_path / "s.json"
    scene.write_text(
        json.dumps(
            {
                "spec": "silcount-scene/1",
                "resolution": [24, 16],
                "camera": {"eye": [4, 3, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50.0, "near": 0.1},
                "light": {"position": [-1, 6, 2]},
                "objects": [
                    {"name": "floor", "mesh": "plane.obj", "casts_shadow": False, "rotate_deg": [-90, 0, 0]},
                    {"name": "cube", "mesh": "triangle_cube.obj", "translate": [0, 1, 0]},
                ],
            }
        )
    )
    mask = str(tmp_path / "a.png")
    code = (
        f"from silcount.cli.main import main\n"
        f"assert main(['render', {str(scene)!r}, '--method', 'zfail', '--out', {mask!r}]) == 0\n"
        f"assert main(['compare', {mask!r}, {mask!r}]) == 0\n"
    )
    assert _loaded_after(code) == set()
