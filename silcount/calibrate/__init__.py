"""Do the counts predict time?  Cycle profiles from llvm-mca and from this machine, checked against measured time.

* :mod:`.mca`: llvm-mca latency and reciprocal throughput per operation kind (``scripts/make_cycle_profiles.py``);
* :mod:`.microbench`, :mod:`.measure`: the micro-benchmarked profile (``silcount calibrate --measure``);
* :mod:`.timing`: plain-loop times and tallies per mesh, algorithm and light;
* :mod:`.predict`: tally x profile, one scale per profile fitted in log space, R^2, ratios, rank agreement;
* :mod:`.fps`: the papers' frame rates against their own cost model (EESD Sec. 6, HSD Sec. VIII);
* :mod:`.calibration`, :mod:`.output`: the whole calibration and its md / csv / json / png outputs.

``silcount.calibrate.ranking_evidence()`` (for the claims) and ``fps_table()`` are loaded on first use (PEP 562),
so importing :mod:`.mca` does not load numba or pandas.
"""

from __future__ import annotations

from typing import Any


def __getattr__(name: str) -> Any:
    if name == "ranking_evidence":
        from silcount.calibrate.calibration import ranking_evidence

        return ranking_evidence
    if name == "fps_table":
        from silcount.calibrate.fps import fps_table

        return fps_table
    raise AttributeError(f"module 'silcount.calibrate' has no attribute {name!r}")
