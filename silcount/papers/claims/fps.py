"""The frame rates: against each other and against the papers' own cycle model at the stated clock.

EESD paper Sec. 6 (TA 69.93, VnV 65.51, EESD 73.16 FPS; no machine named);
HSD paper Sec. I and VIII (69.93 -> 75.53; "conventional method that is
maximum 67.54 FPS"; "P IV 2.8GH", bunny data, Table 1: 2207 edges).  The
cycle model is the papers' own: the papers'-convention sums with the paper's
weights, one cycle per clock tick, under every reading a comparison takes
(:func:`.comparisons.readings_of`); predicted detection time = cycles / clock.
A detection time longer than the reported frame time cannot be right (the
frame also renders).  The mesh's n follows from its edge count under two
readings: the papers' own ``e_n = 6n``, n = faces of a closed triangle
mesh (F = 2E/3), or n = its vertices (V = E/3 + 2 at genus 0), as HSD Sec. VII
and EESD Sec. 5 call n ("n vertices, f_n faces, e_n edges").
"""

from __future__ import annotations

import itertools

import sympy as sp

from silcount.papers import formulas as F
from silcount.papers.claims.base import Claim, Reading, algo, claim_from_data, judged_by_readings, paper_weights
from silcount.papers.claims.comparisons import cycles_under, readings_of
from silcount.papers.claims.context import Evidence


def _n_readings(edges: int) -> list[tuple[str, sp.Expr]]:
    return [
        (f"n = E/6 = {edges / 6:.1f} (the papers' e_n = 6n)", sp.Rational(edges, 6)),
        (f"n = F = 2E/3 = {2 * edges / 3:.1f} (faces of a closed triangle mesh)", sp.Rational(2 * edges, 3)),
        (
            f"n = V = E/3 + 2 = {edges / 3 + 2:.1f} (the papers' 'n vertices', of a closed genus-0 triangle mesh)",
            sp.Rational(edges, 3) + 2,
        ),
    ]


def frame_time(c: dict, source: str, ev: Evidence) -> list[Claim]:
    """Per reported figure: does the predicted detection time fit in the frame time?"""
    w, clock = paper_weights(), c["clock_ghz"] * 1e9
    out = []
    for model, fps in c["fps"].items():
        readings = []
        for (n_name, n_val), (r_name, (r,)) in itertools.product(_n_readings(c["edges"]), readings_of(model)):
            cyc = float(cycles_under(model, r, w).subs({F.n: n_val, F.m: c["m"]}))
            t_ms, frame_ms = 1e3 * cyc / clock, 1e3 / fps
            readings.append(
                Reading(
                    f"{n_name}" + (f", {r_name}" if r_name else ""),
                    t_ms < frame_ms,
                    f"{cyc:.4g} cycles = {t_ms:.3g} ms at {c['clock_ghz']} GHz vs a {frame_ms:.3g} ms frame; "
                    f"fits only at >= {cyc * fps / 1e9:.3g} GHz",
                )
            )
        if not c.get("machine_stated", True):
            readings.append(Reading("another machine (the paper names none)", True, "any clock fast enough fits"))
        claim = judged_by_readings(
            c,
            source,
            "fps",
            readings,
            f"m = {c['m']} ({c['m_note']}); {c['machine_note']}",
        )
        claim.key = f"{c['id']} {algo(model)}"
        claim.statement = f"{c['statement']}: {algo(model)} at {fps} FPS"
        out.append(claim)
    return out


def fps_order(c: dict, source: str, ev: Evidence) -> Claim:
    """The FPS ordering against the cycle ordering of the papers' own model, per reading of the scene."""
    fps = c["fps"]
    by_fps = sorted(fps, key=lambda mdl: -fps[mdl])
    w = paper_weights()
    readings = []
    for point, (r_name, combo) in itertools.product(c["points"], list(readings_of(*fps))):
        vals = {mdl: cycles_under(mdl, r, w).subs({F.n: point["n"], F.m: point["m"]}) for mdl, r in zip(fps, combo)}
        order = sorted(fps, key=lambda mdl: float(vals[mdl]))
        readings.append(
            Reading(
                point["name"] + (f", {r_name}" if r_name else ""),
                order == by_fps,
                "fewest cycles first: " + " < ".join(f"{algo(x)} {float(vals[x]):.4g}" for x in order),
            )
        )
    return judged_by_readings(
        c,
        source,
        "fps",
        readings,
        "FPS order (fastest first) " + " > ".join(f"{algo(x)} {fps[x]}" for x in by_fps) + "; the paper "
        "names no mesh or machine, so each scene reading is tried. " + c.get("note", ""),
    )


def fps_consistency(c: dict, source: str, ev: Evidence) -> Claim:
    """A figure reported for a conventional method against the stated maximum of the conventional methods."""
    over = [x for x in c["conventional"] if x > c["conventional_max"]]
    readings = [
        Reading(
            "the baseline is a conventional method on the same setup",
            not over,
            f"{', '.join(map(str, over)) or 'no figure'} above the stated maximum {c['conventional_max']}",
        ),
        Reading(
            "the baseline was measured in another setup ('with different quality')",
            True,
            "the figures are not comparable, and neither is the claimed increase",
        ),
    ]
    return judged_by_readings(
        c,
        source,
        "fps",
        readings,
        "the paper's only hedge is 'in the same PC and with different quality'.",
    )


def fps_gain(c: dict, source: str, ev: Evidence) -> Claim:
    """A frame-rate gain credited to a faster detector, by Amdahl's law on the papers' own cycle model.

    The frame shortens from 1/FPS_before to 1/FPS_after; replacing the ``before`` detector by the ``after``
    one saves at most the predicted detection time difference (cycles / clock).  Under a reading the gain can
    come from detection when the baseline's predicted detection fits in its frame (a share above 100 % is
    impossible on any machine) and the saving reaches the frame's printed shortening; the share the gain
    needs is ``r / (1 - 1/k)``, r the frame's relative shortening, k the detection speed-up."""
    w, clock = paper_weights(), c["clock_ghz"] * 1e9
    frame_b, frame_a = 1e3 / c["fps_before"], 1e3 / c["fps_after"]
    r = 1 - frame_a / frame_b
    readings = []
    for (n_name, n_val), (r_name, (rb, ra)) in itertools.product(
        _n_readings(c["edges"]), readings_of(c["before"], c["after"])
    ):
        t_b, t_a = (
            1e3 * float(cycles_under(mdl, rd, w).subs({F.n: n_val, F.m: c["m"]})) / clock
            for mdl, rd in ((c["before"], rb), (c["after"], ra))
        )
        k = t_b / t_a
        need = f"needs a share >= {100 * r / (1 - 1 / k):.3g} %" if k > 1 else "no share gives a gain (k <= 1)"
        readings.append(
            Reading(
                f"{n_name}" + (f", {r_name}" if r_name else ""),
                t_b < frame_b and t_b - t_a >= frame_b - frame_a,
                f"{algo(c['before'])} {t_b:.3g} ms ({100 * t_b / frame_b:.3g} % of its {frame_b:.3g} ms frame) -> "
                f"{algo(c['after'])} {t_a:.3g} ms: saves {t_b - t_a:.3g} ms of the {frame_b - frame_a:.3g} ms "
                f"the frame lost (k = {k:.3g}; the gain {need})",
            )
        )
    return judged_by_readings(
        c,
        source,
        "fps",
        readings,
        f"Amdahl: the frame {frame_b:.4g} -> {frame_a:.4g} ms is {100 * r:.3g} % shorter; the papers' own cycle "
        f"model at {c['clock_ghz']} GHz gives each detector's time per frame. {c['machine_note']}",
    )


def same_number(c: dict, source: str, ev: Evidence) -> Claim:
    """A number reported in two places is the same number."""
    same = len(set(c["values"])) == 1
    return claim_from_data(
        c,
        source,
        "fps",
        rederived="",
        measured=None,
        verdict="HOLDS" if same else "FAILS",
        reason=f"{' and '.join(map(str, c['values']))}: {c['where_note']}.",
    )


RULES = {
    "frame_time": frame_time,
    "fps_order": fps_order,
    "fps_consistency": fps_consistency,
    "fps_gain": fps_gain,
    "same_number": same_number,
}
