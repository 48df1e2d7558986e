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
import re

import numpy as np
import sympy as sp

from silcount.detectors import detect
from silcount.mesh.shapes import builtin_mesh
from silcount.papers import growth, projection
from silcount.papers.claims.base import FAILS, HOLDS, Claim, Reading, claim_from_data, judged_by_readings, show_readings
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
    return judged_by_readings(
        c,
        source,
        family,
        readings,
        reason,
        rederived=rederived or show_readings(readings),
        measured=measured,
        keep_one=False,
    )


def agreement(name: str, got: set, want: set) -> str:
    """How the edges a run left compare with the silhouette's, on mesh ``name``."""
    return (
        f"{name}: {len(got)} edges vs {len(want)} silhouette edges, {len(got - want)} extra, {len(want - got)} missed"
    )


def detector_agreement(c: dict, source: str, ev: Evidence) -> Claim:
    parts, agree = [], True
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        light = growth.standard_light(mesh)
        got = set(detect(mesh, light, c["detector"], variant=c["variant"], engine="fast").edge_ids.tolist())
        want = set(detect(mesh, light, "reference").edge_ids.tolist())
        agree &= got == want
        parts.append(agreement(name, got, want))
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
    """The printed step against the standard algorithm's (docs/claims.md, rule 10); with ``evidence``, the render
    experiment that measures the printed step in pixels (:mod:`silcount.render.experiments`), when it ran."""
    same = c["value"] == c["standard"]
    stencil = (ev.stencil or {}).get(c["evidence"]) if "evidence" in c else None
    return claim_from_data(
        c,
        source,
        "stencil",
        rederived=f"standard: {c['standard']}",
        measured=stencil["summary"] if stencil else None,
        verdict=HOLDS if same else FAILS,
        reason=f"against {c['standard_source']}." + (f" {NOT_MEASURED}." if "evidence" in c and not stencil else ""),
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
            "receivers off the plane, all between the occluder and the clipping plane",
            True,
            "their shadowed points lie between the occluder and the plane, inside the truncated volume",
        ),
        Reading(
            "receivers reaching beyond the clipping plane (seen from the light)",
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
        for normal_y, side in ((1, "the plane's normal N facing the light"), (-1, "N facing away from the light")):
            w = projection.w_of_occluder_point(normal_y)
            readings.append(
                Reading(
                    f"as the OpenGL modelview matrix (MultMatrix, then a perspective projection), {side}",
                    bool(w > 0),
                    f"with the exact E, D, w = N.P - N.L = {sp.sstr(w)} for an occluder point between the light "
                    "and the plane: " + ("drawn" if w > 0 else "w < 0, clipped"),
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


def _ray_crossings(mesh, light: np.ndarray, delta: float) -> np.ndarray:
    """Per vertex v, the faces (triangles) crossed by the ray from ``light`` through v' = v (1 + delta), t > 0."""
    tri = mesh.faces
    a, b, c = (mesh.vertices[tri[:, i]] for i in range(3))
    e1, e2, s = b - a, c - a, light - a
    q = np.cross(s, e1)
    out = []
    for v in mesh.vertices:
        d = v * (1 + delta) - light
        p = np.cross(d, e2)
        det = np.einsum("ij,ij->i", e1, p)
        ok = np.abs(det) > 1e-14
        inv = np.where(ok, 1 / np.where(ok, det, 1), 0)
        u, w, t = np.einsum("ij,ij->i", s, p) * inv, (q @ d) * inv, np.einsum("ij,ij->i", e2, q) * inv
        out.append(int(np.sum(ok & (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 1e-9))))
    return np.array(out)


def hit_count(c: dict, source: str, ev: Evidence) -> Claim:
    """Two statements of one not-silhouette test ("one of the faces" / "two faces") give the same verdicts: the
    rays of the test cast on built-in closed meshes, under each reading of "two"."""
    tests = {"at least two": lambda k: k >= 2, "exactly two": lambda k: k == 2}
    counts = {name: _ray_crossings(builtin_mesh(name), np.array(c["light"], float), 1e-4) for name in c["meshes"]}
    readings = []
    for reading, two in tests.items():
        differ = {name: int(sum((k >= 1) != two(k) for k in ks)) for name, ks in counts.items()}
        readings.append(
            Reading(
                f"'two faces' as {reading}, each statement the whole test (not a silhouette if and only if)",
                not any(differ.values()),
                ", ".join(f"{name}: {d} of {len(counts[name])} rays judged differently" for name, d in differ.items()),
            )
        )
    hist = "; ".join(
        f"{name}: " + ", ".join(f"{k} faces x{x}" for k, x in enumerate(np.bincount(ks)) if x)
        for name, ks in counts.items()
    )
    return _judged(
        c,
        source,
        "algorithm",
        readings,
        measured=f"faces crossed per ray, light at {tuple(c['light'])}, v' = v (1 + 1e-4): {hist}",
        reason="on a closed mesh a ray that meets the occluder crosses it an even number of times, so 'one of the "
        "faces' and 'at least two' agree; 'exactly two' differs wherever a ray crosses four faces (the torus); "
        "the paper does not say which it means (read as a plain 'if', the second statement says nothing of a ray "
        "that crosses four faces).",
    )


SUM = re.compile(r"\\sum_\{(\w+)=1\}\^\{([^}]*)\}")


def nested_sums(c: dict, source: str, ev: Evidence) -> Claim:
    """A printed step of nested sums (its ``quote``: the outer sum over polygons, the inner over the pixels each
    ray covers): the inner sum needs its own index and a bound that counts pixels, not ``polygon_bounds``."""
    sums = SUM.findall(c["quote"])
    (outer, _), (inner, inner_bound) = sums[0], sums[1]
    problems = ([f"the inner sum reuses the outer index {inner}"] if inner == outer else []) + (
        [f"the inner sum runs to {inner_bound}, {c['polygon_note']}"] if inner_bound in c["polygon_bounds"] else []
    )
    return claim_from_data(
        c,
        source,
        "stencil",
        rederived="sums: " + ", ".join(f"{i} = 1..{b}" for i, b in sums),
        measured=None,
        verdict=FAILS if problems else HOLDS,
        reason=("; ".join(problems) if problems else "distinct indices, a pixel bound") + f". {c['pixel_note']}",
    )


RULES = {
    "nested_sums": nested_sums,
    "hit_count": hit_count,
    "detector_agreement": detector_agreement,
    "step_list": step_list,
    "stencil_ops": stencil_ops,
    "stencil_test": stencil_test,
    "standard": standard,
    "truncated_volume": truncated_volume,
    "projection": _projection,
}
