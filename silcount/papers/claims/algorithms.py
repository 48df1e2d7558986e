"""The algorithms as written: detector outputs, the stencil steps and tests, the projection algebra.

EESD paper Sec. 2-4, HSD paper Sec. IV and VIII, stencil paper Sec. 3-5.
Detector claims run silcount's detectors (the variant that executes the
printed pseudo-code) against the reference on built-in closed meshes; the
stencil steps are compared with the standard algorithm (Heidmann 1991 z-pass,
Carmack 2000 z-fail, as in Everitt & Kilgard 2002, the stencil paper's [22]);
the final test is evaluated under each reading of ``~`` with C's semantics;
the projection is decided symbolically (:mod:`silcount.papers.projection`).
Measured mismatches of the literal stencil steps come from the render
experiments (:class:`~silcount.papers.claims.context.Evidence` ``stencil``).
"""

from __future__ import annotations

import math

import sympy as sp

from silcount.detectors import detect
from silcount.mesh.shapes import builtin_mesh
from silcount.papers import growth, projection
from silcount.papers.claims.base import FAILS, HOLDS, Claim, Reading, claim_from_data, from_readings, show_readings
from silcount.papers.claims.context import Evidence

STANDARD_ZPASS: dict[str, list] = {
    "required": [
        "ambient_pass",
        "stencil_on",
        "depth_write_off",
        "color_write_off",
        "volume_front_incr",
        "volume_back_decr",
        "color_write_on",
        "lit_pass",
        "stencil_test",
    ],
    "before": [
        ("color_write_on", "lit_pass"),
        ("volume_back_decr", "lit_pass"),
        ("depth_write_off", "volume_front_incr"),
    ],
}
STANDARD_OPS = {
    "zpass": {("front", "pass", "incr"), ("back", "pass", "decr")},
    "zfail": {("back", "fail", "incr"), ("front", "fail", "decr")},
}
VARIANT_NOTE = {"literal": "the loops as printed", "intended": "the text's intended reading"}
NOT_MEASURED = "not measured (no stencil evidence given)"


def _judged(c, source, family, readings, rederived="", measured=None, reason="") -> Claim:
    return claim_from_data(
        c,
        source,
        family,
        rederived=rederived or show_readings(readings),
        measured=measured,
        verdict=from_readings(readings),
        reason=reason,
        readings=readings if len(readings) > 1 else [],
    )


def detector_agreement(c: dict, source: str, ev: Evidence) -> Claim:
    parts, agree = [], True
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        light = growth.standard_light(mesh)
        got = set(detect(mesh, light, c["detector"], variant=c["variant"], engine="fast").edge_ids.tolist())
        want = set(detect(mesh, light, "reference").edge_ids.tolist())
        agree &= got == want
        parts.append(
            f"{name}: {len(got)} edges vs {len(want)} silhouette edges, {len(got - want)} extra, "
            f"{len(want - got)} missed"
        )
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="",
        measured="; ".join(parts),
        verdict=HOLDS if agree else FAILS,
        reason=f"silcount's {c['detector']} detector, {c['variant']} variant ({VARIANT_NOTE[c['variant']]}), against "
        "the reference (an edge whose two faces differ in facing the light, the papers' Sec. 2 definition) for one "
        "point light per mesh.",
    )


def toggle_all(c: dict, source: str, ev: Evidence) -> Claim:
    parts, empty = [], True
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        S: set[tuple[int, int]] = set()
        for p in range(mesh.n_faces):
            corners = mesh.corners[mesh.face_start[p] : mesh.face_start[p + 1]].tolist()
            for a, b in zip(corners, corners[1:] + corners[:1]):
                S.symmetric_difference_update({(b, a)} if (b, a) in S else {(a, b)})
        empty &= not S
        parts.append(f"{name}: {len(S)} edges left of {mesh.n_edges}")
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="",
        measured="; ".join(parts),
        verdict=FAILS if empty else HOLDS,
        reason="run over all NP polygons with no visibility test, the toggle adds each edge of a closed mesh from "
        "one face and deletes it from the other: nothing is left, whatever the light.",
    )


def step_list(c: dict, source: str, ev: Evidence) -> Claim:
    order = {op: i for i, ops in enumerate(c["steps"]) for op in ops}
    missing = [op for op in STANDARD_ZPASS["required"] if op not in order]
    late = [(a, b) for a, b in STANDARD_ZPASS["before"] if a in order and b in order and order[a] > order[b]]
    readings = [
        Reading(
            "the steps run in the order listed",
            not missing and not late,
            ", ".join([f"missing: {', '.join(missing)}"] * bool(missing) + [f"{a} comes after {b}" for a, b in late])
            or "the standard sequence",
        ),
        Reading(
            "the listed order is loose (steps may be one pass)",
            not missing,
            f"missing: {', '.join(missing)}" if missing else "every standard step is present",
        ),
    ]
    return _judged(
        c,
        source,
        "stencil",
        readings,
        reason="against the standard z-pass sequence (Heidmann 1991; "
        "Everitt & Kilgard 2002): " + ", ".join(STANDARD_ZPASS["required"]) + ".",
    )


def stencil_ops(c: dict, source: str, ev: Evidence) -> Claim:
    got = {tuple(op) for op in c["ops"]}
    same = got == STANDARD_OPS[c["method"]]
    return claim_from_data(
        c,
        source,
        "stencil",
        rederived=f"standard {c['method']}: " + "; ".join("/".join(op) for op in sorted(STANDARD_OPS[c["method"]])),
        measured=None,
        verdict=HOLDS if same else FAILS,
        reason="reading P_i as 'P_i is front-facing' (the text defines P_i only as 'polygon'); the "
        f"(face, depth test, stencil op) pairs {'equal' if same else 'differ from'} the standard ones.",
    )


def _c_mod(a: int, b: int) -> int:
    return int(math.fmod(a, b))


TEST_READINGS = {
    "~ as C's bitwise NOT: (~s) % 2": lambda s: _c_mod(~s, 2) != 0,
    "~ as logical NOT, C precedence: (!s) % 2": lambda s: _c_mod(int(not s), 2) != 0,
    "~ applied to the remainder: !(s % 2)": lambda s: not (s % 2),
}


def stencil_test(c: dict, source: str, ev: Evidence) -> Claim:
    values = range(0, 4)
    readings = []
    for name, lit in TEST_READINGS.items():
        wrong = [s for s in values if lit(s) != (s == 0)]
        readings.append(
            Reading(
                name,
                not wrong,
                "lit iff stencil == 0"
                if not wrong
                else "wrong at stencil " + ", ".join(map(str, wrong)) + " (overlapping volumes)",
            )
        )
    stencil = (ev.stencil or {}).get(c["evidence"])
    return _judged(
        c,
        source,
        "stencil",
        readings,
        measured=stencil["summary"] if stencil else None,
        reason="the text: 'if the number of stencil buffer is not zero it is in shadow'; the test keeps a "
        "pixel lit when true, for stencil counts 0-3. " + ("" if stencil else NOT_MEASURED + "."),
    )


def standard(c: dict, source: str, ev: Evidence) -> Claim:
    same = c["value"] == c["standard"]
    return claim_from_data(
        c,
        source,
        "stencil",
        rederived=f"standard: {c['standard']}",
        measured=None,
        verdict=HOLDS if same else FAILS,
        reason=f"against {c['standard_source']}.",
    )


def truncated_volume(c: dict, source: str, ev: Evidence) -> Claim:
    stencil = (ev.stencil or {}).get(c["evidence"])
    readings = [
        Reading(
            "every receiver lies on the clipping plane (a floor)",
            True,
            "a point in shadow lies between the occluder and the plane, inside the truncated volume",
        ),
        Reading(
            "receivers off the clipping plane (the paper's torus and sphere, stencil paper Sec. 6)",
            False,
            "shadow on a receiver beyond the clipping plane is lost",
        ),
    ]
    return _judged(
        c,
        source,
        "stencil",
        readings,
        measured=stencil["summary"] if stencil else None,
        reason="no speed-up figure is given. " + ("" if stencil else NOT_MEASURED + "."),
    )


def _projection_readings(obj: str) -> list[Reading]:
    a = projection.analyse()
    exact = {r.name: (r.new_pixel_exact if obj == "new_pixel" else r.matrix_exact) for r in a.readings}
    return [Reading(name, ok, "exact for every P" if ok else "off the plane for some P") for name, ok in exact.items()]


def _projection(c: dict, source: str, ev: Evidence) -> Claim:
    a = projection.analyse()
    obj = c["object"]
    if obj == "new_pixel":
        readings = _projection_readings(obj)
        reason = "E and D are never defined; exact iff " + " or ".join(a.solutions) + "."
        measured = None
    elif obj == "shadow_matrix":
        readings = [Reading(f"{r.reading}, as a projective map", r.holds, r.outcome) for r in _projection_readings(obj)]
        w_sign = projection.w_of_occluder_point()
        readings.append(
            Reading(
                "as the OpenGL modelview matrix (MultMatrix, then a perspective projection)",
                False,
                f"with the exact E, D, w = N.P - N.L = {sp.sstr(w_sign)} < 0 for an occluder point "
                "between the light and the plane: clipped",
            )
        )
        reason = (
            "the printed matrix is the standard planar shadow matrix (Real-Time Rendering, its [28]) times -1"
            if projection.printed_is_minus_standard()
            else "the printed matrix is not the standard one up to sign"
        )
        reason += "; applied to (P, 1) it equals the new-pixel formula." if a.matrix_equals_formula else "."
        stencil = (ev.stencil or {}).get(c.get("evidence", ""))
        measured = stencil["summary"] if stencil else None
        reason += "" if stencil else " " + NOT_MEASURED + "."
    else:
        readings = [
            Reading(
                "as printed: (P-C)N = 0, and P on both sides",
                False,
                "says the occluder point lies on the plane; P = L + a(P - L) forces a = 1 or P = L",
            ),
            Reading(
                "P on the left read as S (the conversion may have garbled S)",
                bool(a.solutions),
                "S = L + E/(NP - D)(P - L) is exact iff " + " or ".join(a.solutions),
            ),
        ]
        reason, measured = "E and D are never defined (see the new-pixel claim).", None
    return _judged(c, source, "projection", readings, measured=measured, reason=reason)


RULES = {
    "detector_agreement": detector_agreement,
    "toggle_all": toggle_all,
    "step_list": step_list,
    "stencil_ops": stencil_ops,
    "stencil_test": stencil_test,
    "standard": standard,
    "truncated_volume": truncated_volume,
    "projection": _projection,
}
