"""The papers' frame rates against their own cost model: does the predicted detection fit in the frame?

The papers report frame rates on "a PC with NVIDIA Graphic Hardware and P IV
2.8GH" (HSD paper Sec. VIII; the EESD paper, Sec. 6, says only "same
computer"): TA 69.93, VnV 65.51, EESD 73.16 FPS (EESD Sec. 6) and HSD 75.53
FPS on the bunny, whose Table 1 counts 2207 edges (HSD Sec. VIII).  Here the
paper model's own printed closed form (the last line of each model's
``[closed_form]`` in ``silcount/models/``) is weighted by the paper's cycles (EESD
Sec. 6: Mult 4, Add 2, Compare 3, Read 1, Write 2; the closed forms have no
division or root) and divided by 2.8e9 cycles/s: a detection time per frame,
set beside the frame time 1/FPS.

Two readings of n for a 2207-edge mesh, both shown:

* ``e_n = 6n``: the papers' own substitution (EESD Sec. 5: "the number of
  edges will be 6n"), n = 2207 / 6;
* ``closed triangle mesh``: E = 3F / 2, n = 2 * 2207 / 3 faces (the bunny is
  a triangle mesh).

m = 3 (triangles) in both; HSD's closed form has no m.
"""

from __future__ import annotations

import pandas as pd

from silcount.counting import models

CLOCK_HZ = 2.8e9
BUNNY_EDGES = 2207
SYMBOL = {"A": "add", "M": "mul", "C": "cmp", "R": "read", "W": "write"}


def _reported() -> list[tuple[str, str, float]]:
    """``(source, model, FPS)`` as printed, read from the papers' claims in ``silcount/models/``."""
    out = []
    for claim in models.load("eesd2012-claims")["claims"]:
        if claim["id"] == "eesd-fps-frame":
            out += [("EESD 2012 Sec. 6", mdl, float(v)) for mdl, v in claim["fps"].items()]
    for claim in models.load("hsd2011-claims")["claims"]:
        if claim["id"] == "hsd-fps-frame":
            out += [("HSD 2011 Sec. VIII (bunny)", mdl, float(v)) for mdl, v in claim["fps"].items()]
    return out


def paper_cycles(model: str, n: float, m: float) -> float:
    """The paper's printed final closed form of ``model``, weighted by the paper's cycles, at (n, m)."""
    weights = models.load("eesd2012-paper")["cycle_weights"]
    form = models.expr(models.load(model)["closed_form"]["lines"][-1]["expr"])
    sym = models.symbols()
    subs = {s: weights[SYMBOL[s.name]] for s in form.free_symbols if s.name in SYMBOL}
    subs |= {sym["n"]: n, sym["m"]: m}
    return float(form.subs(subs))


def fps_table(edges: int = BUNNY_EDGES, clock_hz: float = CLOCK_HZ) -> pd.DataFrame:
    """One row per (reported FPS, reading of n): predicted detection ms per frame vs the frame's ms."""
    readings = (("e_n = 6n", edges / 6), ("closed triangle mesh", 2 * edges / 3))
    rows = []
    for source, model, fps in _reported():
        for reading, n in readings:
            cycles = paper_cycles(model, n, 3)
            detect_ms = 1e3 * cycles / clock_hz
            frame_ms = 1e3 / fps
            rows.append(
                {
                    "source": source,
                    "algorithm": models.load(model)["algorithm"],
                    "model": model,
                    "fps": fps,
                    "frame_ms": frame_ms,
                    "reading": reading,
                    "n": n,
                    "m": 3,
                    "paper_cycles": cycles,
                    "detect_ms": detect_ms,
                    "share_of_frame": detect_ms / frame_ms,
                    "fits": detect_ms < frame_ms,
                }
            )
    return pd.DataFrame(rows)
