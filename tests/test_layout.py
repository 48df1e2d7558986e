"""The package's architecture, checked: imports point down the layers, no cycles, a module per purpose, lazy imports.

Layers, lowest first (docs/architecture.md, "Layers"): a module may import its own
subpackage and any lower layer, never a higher one or a sibling of its layer,
so that the units of one layer are independent of each other (the
"layers" and "independence" contracts of import-linter, in one table).
"""

from __future__ import annotations

import ast
import importlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from silcount import options
from silcount.cli.main import COMMANDS

PKG = Path(__file__).resolve().parent.parent / "silcount"

LAYERS: list[tuple[str, ...]] = [
    ("silcount.errors", "silcount.version", "silcount.options"),
    ("silcount.atomic", "silcount.progress", "silcount.threads"),  # atomic raises silcount.errors' UnwritableOutput
    ("silcount.plots", "silcount.counting", "silcount.mesh"),  # independent of each other
    ("silcount.detectors",),
    ("silcount.render", "silcount.study", "silcount.calibrate"),  # the measurements, independent of each other
    ("silcount.worstcase",),  # the worst-case search: fits from study, its witnesses judged by papers
    ("silcount.papers",),
    ("silcount.audit",),
    ("silcount.cli",),
    ("silcount",),
]


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


def purpose(path: Path) -> str:
    """What a module says it is for: the first line of its docstring."""
    doc = ast.get_docstring(ast.parse(path.read_text(), filename=str(path))) or ""
    return doc.strip().splitlines()[0].strip() if doc.strip() else ""


@pytest.mark.parametrize("name", sorted(GRAPH))
def test_every_module_says_what_it_is_for(name):
    """A module is one concept, not a size: its docstring opens with the one thing it is for."""
    assert purpose(modules()[name]), f"{name} has no docstring saying what it is for"


def test_no_two_modules_are_for_the_same_thing():
    """Two modules claiming one purpose are one concept split by size (``part 2 of ...``): merge them or say
    what each is for."""
    seen: dict[str, str] = {}
    for name, path in modules().items():
        what = purpose(path).lower()
        assert what not in seen, f"{name} and {seen[what]} both say they are for {what!r}"
        seen[what] = name


MAPPED = ("silcount.detectors", "silcount.detectors.eesd", "silcount.detectors.hierarchy")
"""Packages whose ``__init__`` docstring names each of their modules: the map of their architecture."""


@pytest.mark.parametrize("package", MAPPED)
def test_a_mapped_package_names_each_of_its_modules(package):
    """Each module and subpackage of a mapped package is named by the package's docstring (``spec.py``,
    ``hierarchy/``), so that a new module says where it stands among the others."""
    root = PKG.parent.joinpath(*package.split("."))
    doc = ast.get_docstring(ast.parse((root / "__init__.py").read_text())) or ""
    parts = [p.name for p in sorted(root.glob("*.py")) if p.name != "__init__.py"]
    parts += [f"{p.name}/" for p in sorted(root.iterdir()) if (p / "__init__.py").is_file()]
    for part in parts:
        assert part in doc, f"{package}'s docstring does not name {part}"


def test_the_purpose_rules_can_fail(tmp_path):
    """A module without a docstring has no purpose; an empty docstring neither."""
    (tmp_path / "a.py").write_text("x = 1\n")
    (tmp_path / "b.py").write_text('"""  """\n')
    (tmp_path / "c.py").write_text('"""The thing.\n\nMore."""\n')
    assert [purpose(tmp_path / n) for n in ("a.py", "b.py", "c.py")] == ["", "", "The thing."]


SCRIPTS = PKG.parent / "scripts"
BENCHMARKS = PKG.parent / "benchmarks"
MUTATORS = {"insert", "append", "extend", "remove", "pop", "clear", "reverse", "sort", "__setitem__", "__iadd__"}
PATH_LOADERS = {  # (module, attribute) that import a file by its path, around sys.path
    ("importlib.util", "spec_from_file_location"),
    ("importlib.machinery", "SourceFileLoader"),
    ("importlib.machinery", "SourcelessFileLoader"),
    ("runpy", "run_path"),
    ("site", "addsitedir"),
    ("imp", "load_source"),
}


def _dotted(node: ast.AST) -> str | None:
    """``a.b.c`` for a chain of names and attributes, else None."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    return ".".join([node.id, *reversed(parts)])


def path_edits(source: str) -> list[str]:
    """Every place ``source`` changes ``sys.path`` or loads a module by its file path, as ``line N: what``.

    Read from the syntax tree, not the text, so no spelling escapes it: ``sys.path`` under any alias
    (``import sys as s``, ``from sys import path``, ``p = sys.path``) assigned, augmented, sliced, deleted
    from or called with a mutating method; and the path loaders of importlib, runpy and site under any
    import form.  A string that is itself Python (code for ``python -c``) is read the same way.
    """
    tree = ast.parse(source)
    names: dict[str, str] = {}  # local name -> the dotted name it stands for
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                names[a.asname or a.name.partition(".")[0]] = a.name if a.asname else a.name.partition(".")[0]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            for a in node.names:
                names[a.asname or a.name] = f"{node.module}.{a.name}"

    def resolve(node: ast.AST) -> str | None:
        dotted = _dotted(node)
        if dotted is None:
            return None
        head, _, rest = dotted.partition(".")
        full = names.get(head, head)
        return f"{full}.{rest}" if rest else full

    for node in ast.walk(tree):  # aliases of sys.path itself: ``p = sys.path``
        if isinstance(node, ast.Assign) and resolve(node.value) == "sys.path":
            names.update({t.id: "sys.path" for t in node.targets if isinstance(t, ast.Name)})

    def is_path(node: ast.AST) -> bool:
        while isinstance(node, ast.Subscript):
            node = node.value
        return resolve(node) == "sys.path"

    found = []
    for node in ast.walk(tree):
        line = getattr(node, "lineno", 0)
        targets: list[ast.AST] = []
        if isinstance(node, ast.Assign):
            targets = [t for t in node.targets if not (isinstance(t, ast.Name) and resolve(node.value) == "sys.path")]
        elif isinstance(node, ast.AugAssign | ast.AnnAssign | ast.Delete):
            targets = node.targets if isinstance(node, ast.Delete) else [node.target]
        for t in targets:
            for sub in ast.walk(t):
                if is_path(sub) and not isinstance(sub, ast.Name | ast.Attribute) or resolve(sub) == "sys.path":
                    found.append(f"line {line}: assigns to sys.path")
                    break
        if isinstance(node, ast.Call):
            func = node.func
            if isinstance(func, ast.Attribute) and func.attr in MUTATORS and is_path(func.value):
                found.append(f"line {line}: sys.path.{func.attr}(...)")
            target = resolve(func)
            if target and any(target == f"{m}.{a}" for m, a in PATH_LOADERS):
                found.append(f"line {line}: {target}(...) loads a file by its path")
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and "\n" in node.value:
            try:
                inner = path_edits(node.value)
            except SyntaxError:  # prose, not code
                continue
            found += [f"line {line}, in the code of a string: {what}" for what in inner]
    return found


def script_files() -> list[Path]:
    """Every Python file of scripts/ and of the benchmarks package."""
    return sorted([*SCRIPTS.rglob("*.py"), *BENCHMARKS.rglob("*.py")])


@pytest.mark.parametrize("path", script_files(), ids=lambda p: p.relative_to(PKG.parent).as_posix())
def test_scripts_say_what_they_are_for_and_import_the_installed_package(path):
    """A script or benchmark says what it is for, as a module does, and none of them edits ``sys.path`` (or
    loads a file by its path) to find silcount or a sibling: they import silcount as installed (or as a child's
    ``PYTHONPATH`` gives it), and the benchmarks each other as a package."""
    text = path.read_text()
    name = path.relative_to(PKG.parent).as_posix()
    assert purpose(path) or path.name == "__init__.py", f"{name} has no docstring saying what it is for"
    assert not path_edits(text), f"{name} edits sys.path or loads by path: {'; '.join(path_edits(text))}"


@pytest.mark.parametrize(
    "source",
    [
        "import sys\nsys.path.insert(0, 'x')\n",
        "import sys\nsys.path[:0] = ['x', 'y']\n",
        "import sys\nsys.path[0] = 'x'\n",
        "import sys\nsys.path = ['x'] + sys.path\n",
        "import sys\nsys.path += ['x']\n",
        "import sys\nsys.path.append('x')\n",
        "import sys\nsys.path.extend(['x'])\n",
        "import sys as s\ns.path.insert(0, 'x')\n",
        "from sys import path\npath[:0] = ['x']\n",
        "from sys import path as p\np.append('x')\n",
        "import sys\np = sys.path\np.insert(0, 'x')\n",
        "import sys\ndel sys.path[0]\n",
        "import importlib.util\nimportlib.util.spec_from_file_location('m', 'x.py')\n",
        "from importlib.util import spec_from_file_location as f\nf('m', 'x.py')\n",
        "from importlib.machinery import SourceFileLoader\nSourceFileLoader('m', 'x.py')\n",
        "import runpy\nrunpy.run_path('x.py')\n",
        "import site\nsite.addsitedir('x')\n",
        'CHILD = """\nimport sys\nsys.path[:0] = [tree]\n"""\n',  # code for ``python -c``
    ],
)
def test_the_scripts_rule_sees_every_spelling_of_a_path_edit(source):
    assert path_edits(source), source


def test_the_scripts_rule_lets_reading_sys_path_pass():
    source = (
        "import sys\nimport os\nprint(sys.path[0], len(sys.path))\nfirst = sys.path[:1]\n"
        "env = dict(os.environ)\nenv['PYTHONPATH'] = 'x'\nfrom importlib import import_module\nimport_module('json')\n"
    )
    assert path_edits(source) == []


HEAVY = ("sympy", "trimesh", "matplotlib")
# what no --help may load (issue 43: each within 0.3 s, scripts/bench_front_door.py): numba alone costs 0.2-0.6 s
HELP_HEAVY = HEAVY + ("numba", "llvmlite", "scipy", "pandas", "dask", "numpy", "PIL")


def _loaded_after(code: str, heavy: tuple[str, ...] = HEAVY) -> set[str]:
    env = dict(os.environ)
    probe = code + "\nimport sys\nprint(' '.join(sorted({m.split('.')[0] for m in sys.modules})))\n"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env, check=True)
    return set(out.stdout.split()) & set(heavy)


def test_import_silcount_loads_nothing_heavy():
    assert _loaded_after("import silcount") == set()


def _help_probe(argv: list[str]) -> str:
    """Code printing ``silcount ARGV``'s help into a buffer (not stdout, which the probe reads) and checking it."""
    return (
        "import contextlib, io\n"
        "from silcount.cli.main import main\n"
        "buf = io.StringIO()\n"
        "with contextlib.redirect_stdout(buf):\n"
        "    try:\n"
        f"        main({argv!r})\n"
        "    except SystemExit as exc:\n"
        "        assert exc.code == 0, exc.code\n"
        "assert buf.getvalue().startswith('usage: silcount'), buf.getvalue()\n"
    )


@pytest.mark.parametrize("command", [None, *COMMANDS])
def test_help_loads_nothing_heavy(command):
    """``silcount --help`` and ``silcount CMD --help`` build their parsers from argparse-level modules alone."""
    argv = ["--help"] if command is None else [command, "--help"]
    assert _loaded_after(_help_probe(argv), HELP_HEAVY) == set()


def test_the_help_probe_sees_a_heavy_import():
    """The check above can fail: a probe that imports numba while building the parser is caught."""
    assert {"numba", "numpy"} <= _loaded_after("import numba\n" + _help_probe(["--help"]), HELP_HEAVY)


def test_every_subcommand_module_is_registered():
    """``silcount/cli/<name>.py`` is a subcommand exactly when COMMANDS names it; each has its two functions."""
    modules = {p.stem for p in (PKG / "cli").glob("*.py")} - {"__init__", "main"}
    assert modules == {name.replace("-", "_") for name in COMMANDS}
    for name in COMMANDS:
        module = importlib.import_module(f"silcount.cli.{name.replace('-', '_')}")
        assert callable(module.add_arguments) and callable(module.run), name


def test_the_parsers_leave_detector_names_to_the_registry():
    """No parser fixes the detector list: a plug-in's name parses, and the registry checks it when the command
    runs (``tests/test_registry.py``)."""
    from silcount.cli.main import build_parser

    argv = ["render", "s.json", "--method", "zfail", "--detector", "someone-elses", "--out", "m.png"]
    args = build_parser().parse_args(argv)
    assert args.detector == "someone-elses"
    assert not hasattr(options, "DETECTORS")


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


def test_an_audit_of_the_reference_detector_loads_no_sympy(tmp_path):
    """sympy evaluates the papers' printed formulas; the reference detector has none (issue 43)."""
    mesh, out = PKG.parent / "data" / "triangle_cube.obj", tmp_path / "a.json"
    code = (
        "from silcount.cli.main import main\n"
        f"assert main(['audit', {str(mesh)!r}, '--detectors', 'reference', '--random-lights', '1', '--quiet', "
        f"'--format', 'json', '--out', {str(out)!r}]) == 0\n"
    )
    assert _loaded_after(code) == set()
    assert _loaded_after(code.replace("'reference'", "'ta'")) == {"sympy"}  # TA's printed formula: it can fail
