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
through :func:`.registry.register_detector` like any plug-in.  Imported on the registry's first use only.
"""

from __future__ import annotations

from silcount.detectors import hsd, reference, ta, vnv
from silcount.detectors.eesd import detector as eesd
from silcount.detectors.hierarchy import cones, gaussmap
from silcount.detectors.spec import DetectorSpec

SPECS: tuple[DetectorSpec, ...] = tuple(m.SPEC for m in (reference, ta, vnv, hsd, eesd, gaussmap, cones))
