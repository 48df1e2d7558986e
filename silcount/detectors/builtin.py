"""The seven built-in detectors' specs, in the order every table lists them.

| name        | paper, section                          | module        |
|-------------|-----------------------------------------|---------------|
| reference   | edge adjacency (silcount)               | reference.py  |
| ta          | HSD 2011 Sec. 4.1; EESD 2012 Sec. 3.1   | ta.py         |
| vnv         | HSD 2011 Sec. 4.2; EESD 2012 Sec. 3.2   | vnv.py        |
| hsd         | HSD 2011 Sec. V, 6.3                    | hsd.py        |
| eesd        | EESD 2012 Sec. 3.3, 5.3                 | eesd.py       |
| gaussmap    | Gooch et al., I3D 1999, Sec. 4.1        | hierarchy/gaussmap.py |
| cones       | Johnson & Cohen, I3D 2001, Sec. 3;      | hierarchy/cones.py |
|             | Sander et al., SIGGRAPH 2000, Sec. 3    |               |

Each module declares its own :class:`.spec.DetectorSpec` (``SPEC``); the registry registers these first,
through :func:`.registry.register_detector` like any plug-in.  A module is imported when its detector is first
asked for by name (:func:`spec`), or when the registry fills (:func:`specs`): a ``silcount render`` with the
reference detector imports the reference alone (19 ms less of a 0.52 s process, ``benchmarks.front_door``).
"""

from __future__ import annotations

from importlib import import_module

from silcount.detectors.spec import DetectorSpec

MODULES: dict[str, str] = {
    "reference": "silcount.detectors.reference",
    "ta": "silcount.detectors.ta",
    "vnv": "silcount.detectors.vnv",
    "hsd": "silcount.detectors.hsd",
    "eesd": "silcount.detectors.eesd.detector",
    "gaussmap": "silcount.detectors.hierarchy.gaussmap",
    "cones": "silcount.detectors.hierarchy.cones",
}
"""Each built-in's name and the module that declares its ``SPEC``, in the order every table lists them."""


def spec(name: str) -> DetectorSpec:
    """Built-in ``name``'s spec (its module imported now if it was not)."""
    got = import_module(MODULES[name]).SPEC
    assert got.name == name, f"{MODULES[name]} declares {got.name!r}, not {name!r}"
    return got


def specs() -> tuple[DetectorSpec, ...]:
    """Every built-in's spec, in :data:`MODULES`' order."""
    return tuple(spec(name) for name in MODULES)
