"""Primitive costs, the mesh model (n, V/F/E, the tables' m), complexity, and small algebraic facts.

EESD paper Sec. 2, 5, 5.1-5.3, 6, 7; HSD paper Sec. V, VI, VIII (Table 1).
Every rule computes its verdict: kernels are executed on counting
arithmetic (:mod:`silcount.papers.primitives`), identities are decided by
sympy, complexity by the worst case (the annotations' tight worst case and measured witness families, beside the
typical growth: :class:`~silcount.papers.claims.context.Evidence`).
"""

from __future__ import annotations

import sympy as sp

from silcount.mesh.shapes import builtin_mesh
from silcount.papers import formulas as F
from silcount.papers import primitives
from silcount.papers.claims.base import (
    FAILS,
    HOLDS,
    Claim,
    Reading,
    algo,
    claim_from_data,
    from_readings,
    show_readings,
)
from silcount.papers.claims.context import Evidence

EULER_MESHES = ("icosahedron", "icosphere4", "torus")


def _judged(c, source, family, readings, rederived="", measured=None, reason="", verdict=None) -> Claim:
    return claim_from_data(
        c,
        source,
        family,
        rederived=rederived or show_readings(readings),
        measured=measured,
        verdict=verdict or from_readings(readings),
        reason=reason,
        readings=readings if len(readings) > 1 else [],
    )


def kernel_cost(c: dict, source: str, ev: Evidence) -> Claim:
    printed = {k: int(v) for k, v in c["cost"].items() if k in primitives.ARITHMETIC}
    readings = []
    for name in c["kernels"]:
        got = primitives.kernel_cost(name)
        shown = " + ".join(f"{v}{F.KIND_SYMBOLS[k]}" for k, v in sorted(got.items())) or "no arithmetic"
        readings.append(Reading(primitives.KERNELS[name][1], got == printed, f"executed: {shown}"))
    return _judged(
        c,
        source,
        "primitive",
        readings,
        reason="each reading of the operation executed on counting arithmetic (add, mul, cmp; reads and writes "
        "depend on a memory layout the paper does not give). Computations tried: "
        + "; ".join(primitives.KERNELS[name][1] for name in c["kernels"])
        + ".",
    )


def _euler_rows():
    return [(name, m.n_vertices, m.n_faces, m.n_edges) for name, m in ((n, builtin_mesh(n)) for n in EULER_MESHES)]


def mesh_ratio(c: dict, source: str, ev: Evidence) -> Claim:
    """The printed vertices (and edges) per face against Euler's formula and the built-in closed meshes."""
    vpf, epf = c["vertices_per_face"], c.get("edges_per_face")
    rows = _euler_rows()
    measured = "; ".join(f"{name}: V/F = {V / Fc:.3f}, E/F = {E / Fc:.3f}" for name, V, Fc, E in rows)
    g = sp.Symbol("g")
    parts, why = [], []
    if epf is not None:
        genus = sp.solve(sp.Eq(vpf - epf + 1, (2 - 2 * g) / F.n), g)[0]
        parts.append(
            f"V = {vpf}n, E = {epf}n, F = n in Euler's V - E + F = 2 - 2g needs genus {sp.sstr(genus)}, "
            f"and 2E = mF needs m = {2 * epf}-gons"
        )
    parts.append("closed triangle meshes have E/F = 3/2 and V/F -> 1/2 (2E = 3F and V - E + F = 2 - 2g)")
    ok = all(abs(V / Fc - vpf) < 0.1 * vpf for _, V, Fc, _ in rows)
    if not ok:
        why.append(f"V/F = {vpf} fits no closed triangle mesh" + (" (it is F/V inverted)" if vpf == 2 else ""))
    if epf is not None:
        evv = sp.Rational(epf) / sp.Rational(vpf)
        if evv == 3:
            why.append("E/V = 3 is right: closed triangle meshes approach it (E = 3V - 6 + 6g)")
        if not ok:
            why.append(f"with E = {epf}n only a polygon mesh of {2 * epf}-gons of genus {sp.sstr(genus)} has both")
    return claim_from_data(
        c,
        source,
        "mesh model",
        rederived="; ".join(parts),
        measured=measured,
        verdict=HOLDS if ok else FAILS,
        reason="Euler's formula: "
        + ("; ".join(why) if why else f"closed triangle meshes have V/F near {vpf}")
        + "; the built-in closed meshes agree.",
    )


def two_meanings(c: dict, source: str, family: str, readings: list[Reading], what: str, quantity: str) -> Claim:
    """Rule 15 (docs/claims.md): two of the paper's statements give one quantity two meanings.

    Each reading takes one statement as meant and judges the other by it, so a reading holds only where the
    two agree: a claim that they agree FAILS when under each reading one of them is false (the meaning of n,
    EESD Sec. 5 and HSD Sec. VI; HSD's sides per polygon, Sec. VI 6.3).  The claims that depend on which one
    the authors meant are judged under both readings (rule 5), and are AMBIGUOUS where the readings disagree.
    """
    return _judged(
        c, source, family, readings, reason=f"{what} give {quantity} two meanings; under each, one of them is false."
    )


def n_meaning(c: dict, source: str, ev: Evidence) -> Claim:
    sub = F.substitutions(c.get("model", "eesd2012-ta"))
    # the paper's own ratios with n vertices: V/F = 2 (f_n = n/2) and E/V = 3 (e_n = 3n)
    agree = sp.simplify(sub[F.f_n] - F.n / 2) == 0 and sp.simplify(sub[F.e_n] - 3 * F.n) == 0
    readings = [
        Reading(
            "n = vertices (as the text says)",
            agree,
            c.get(
                "vertices_reading_note",
                f"the sums substitute f_n = {sp.sstr(sub[F.f_n])}, e_n = {sp.sstr(sub[F.e_n])}: with n vertices the "
                "paper's own ratios give f_n = n/2 and e_n = 3n",
            ),
        ),
        Reading(
            "n = faces (as the substitutions say)",
            agree,
            c.get(
                "faces_reading_note",
                "then the text's 'n vertices' and the tables' 'number of vertices on the corner of occluder is 10' "
                "are wrong",
            ),
        ),
    ]
    return two_meanings(c, source, "mesh model", readings, "the text and the substitutions", "n")


def table_point(c: dict, source: str, ev: Evidence) -> Claim:
    sub = F.substitutions(c.get("model", "eesd2012-ta"))
    m_needed = sp.simplify(2 * sub[F.e_n] / sub[F.f_n])
    parts = [f"(n={p['n']}, m={p['m']}): 2E = {2 * 6 * p['n']}, mF = {p['m'] * p['n']}" for p in c["points"]]
    ok = all(p["m"] == m_needed for p in c["points"])
    return claim_from_data(
        c,
        source,
        "mesh model",
        rederived=f"every edge has two sides, 2E = mF: f_n = n, e_n = 6n force m = {m_needed}; " + "; ".join(parts),
        measured=None,
        verdict=HOLDS if ok else FAILS,
        reason=f"no closed mesh has n faces, 6n edges and m = {', '.join(str(p['m']) for p in c['points'])}; and TA "
        f"itself needs triangles ('{c.get('triangles_quote', 'each edge should be shared by just two triangles')}'), "
        "m = 3.",
    )


def worst_degree(model: str) -> int:
    """Degree in n of the model's tight worst case (every conditional at its dearest arm, loops at their
    bounds, ``formulas.worst_case``), raw operation counts, the dearest of the model's readings."""
    unit = {k: 1.0 for k in F.KINDS}
    return max(F.degree(F.weighted(F.paper_forms(model, r)["worst"], unit)) for r in F.readings(model))


def _growth(e) -> str:
    """The exponent, its interval and (when fitted) the complexity class by AIC, then where it was measured."""
    return f"{e.text()} ({e.source})"


def _class(e) -> str:
    """``, class n^2 (w 1.00)`` after an exponent (the whole choice is in ``measured``), or nothing when the
    class was not fitted."""
    return "" if e.classes is None else f", class {e.classes.chosen} (w {e.classes.weight:.2f})"


def complexity(c: dict, source: str, ev: Evidence) -> Claim:
    """ "X is O(n^d)", an upper bound: judged by the worst case (docs/claims.md, rule 7), typical growth shown."""
    model, deg = c["model"], c["degree"]
    unit = {k: 1.0 for k in F.KINDS}
    convention = F.degree(F.weighted(F.paper_forms(model)["convention"], unit))
    worst = worst_degree(model)
    det = F.models.load(model)["algorithm"]
    typical = [e for e in ev.exponents if e.detector == det and e.cost_model == "true"]
    if not typical:
        raise ValueError(f"no measured exponent for detector {det!r}: the complexity claim needs one")
    witnesses = ev.worst_for(det)
    tol = 0.05
    steepest = max(typical + witnesses, key=lambda e: e.exponent)
    above = [e for e in typical + witnesses if e.low > deg + tol]
    paper = [e for e in ev.exponents if e.detector == det and e.cost_model == "paper"]
    measured = "typical: " + "; ".join(f"{det} true: {_growth(e)}" for e in typical)
    measured += "".join(f"; paper cost model F^{e.exponent:.2f}{_class(e)}" for e in paper)
    if witnesses:
        measured += "; worst case: " + "; ".join(f"{det} true: {_growth(e)}" for e in witnesses)
    label = {id(e): e.source.split(" (")[0].split(":")[0] for e in typical + witnesses}
    if worst > deg:
        verdict, why = FAILS, f"the annotations' tight worst case is of degree {worst} in n, above n^{deg}"
    elif above:
        verdict, why = (
            FAILS,
            f"{label[id(above[0])]} grows faster than n^{deg}: F^{above[0].exponent:.2f}{_class(above[0])}",
        )
    else:
        verdict = HOLDS
        why = f"the annotations' tight worst case is of degree {worst} in n and no measured family grows faster; " + (
            f"the bound is reached by the {label[id(steepest)]} (F^{steepest.exponent:.2f} "
            f"[{steepest.low:.2f}, {steepest.high:.2f}]{_class(steepest)})"
            if steepest.high >= deg - tol
            else f"no measured family reaches it (steepest: F^{steepest.exponent:.2f}{_class(steepest)})"
        )
    typical_text = ", ".join(f"F^{e.exponent:.2f}{_class(e)} ({label[id(e)]})" for e in typical)
    lower = all(e.high < deg - tol for e in typical)
    why += f". Typical growth: {typical_text}" + (
        f", lower, which an upper bound allows (growth below n^{deg} does not contradict O(n^{deg}))" if lower else ""
    )
    return claim_from_data(
        c,
        source,
        "complexity",
        rederived=f"tight worst case of the annotations: degree {worst} in n; papers'-convention sum: degree "
        f"{convention} (e_n = 6n, f_n = n)",
        measured=measured,
        verdict=verdict,
        reason=f"O() is an upper bound, judged by the worst case that can happen: {why}.",
    )


def big_oh(c: dict, source: str, ev: Evidence) -> Claim:
    degs = {mdl: worst_degree(mdl) for mdl in [c["winner"], *c["others"]]}
    same = len(set(degs.values())) == 1
    return claim_from_data(
        c,
        source,
        "complexity",
        rederived="tight worst cases of the annotations: " + ", ".join(f"{algo(k)}: O(n^{d})" for k, d in degs.items()),
        measured=None,
        verdict=FAILS if same else HOLDS,
        reason="the paper's own annotations put all three in one O class (their worst cases and their sums); Big-Oh "
        "is an upper bound that drops constant factors and cannot order algorithms of one class"
        if same
        else "the classes differ",
    )


def loop_bound(c: dict, source: str, ev: Evidence) -> Claim:
    c = {**c, "table_reading": c.get("table_reading") or F.models.load(c["model"]).get("table_reading", "")}
    loop = F.models.load(c["model"])["loops"][c["loop"]]
    prose, printed = F.parse(loop["bound"]), F.parse(loop["bound_printed"])
    agree = sp.simplify(prose - printed) == 0
    readings = [
        Reading(
            "'decreased to 1' (the sum as meant)",
            agree,
            f"the sentence's 'decreased by 1' gives {prose}, not {printed}",
        ),
        Reading("'decreased by 1' (the sentence as meant: m - 1)", agree, f"the sum should use {prose}"),
    ]
    return two_meanings(
        c, source, "derivation", readings, "the sentence and the sum", "the sides HSD visits per polygon (m)"
    )


def edge_count(c: dict, source: str, ev: Evidence) -> Claim:
    readings = []
    for r in c["readings"]:
        if "faces" in r:
            faces = sp.nsimplify(F.parse(r["faces"]))
            readings.append(Reading(r["name"], faces.is_Integer, f"F = {sp.sstr(faces)}"))
        else:
            e = sp.nsimplify(F.parse(r["edges"]))
            readings.append(Reading(r["name"], e == c["edges"], f"E = {sp.sstr(e)}"))
    return _judged(
        c,
        source,
        "mesh model",
        readings,
        reason="the paper gives no geometry for its data; a mesh built to match the number is no evidence.",
    )


def fan_triangles(c: dict, source: str, ev: Evidence) -> Claim:
    counts = {n: len([(0, i, i + 1) for i in range(1, n - 1)]) for n in range(3, 13)}
    ok = all(t == n - 2 for n, t in counts.items())
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="fan triangulation: " + ", ".join(f"{n}-gon: {t}" for n, t in counts.items()),
        measured=None,
        verdict=HOLDS if ok else FAILS,
        reason="a simple n-gon splits into n - 2 triangles (interior angles (n - 2) pi), all in its plane.",
    )


def phong(c: dict, source: str, ev: Evidence) -> Claim:
    Ia, Ka, Kd, Il, NL, Ks, NH, nn = sp.symbols("I_a K_a K_d I_l NL K_s NH n", positive=True)
    terms = Ka * Ia + Kd * Il * NL + Il * Ks * NH**nn
    combined = Ia * Ka + Kd * Il * NL + Il * Ks * NH**nn
    same = sp.simplify(terms - combined) == 0
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="I_a K_a + K_d I_l (N.L) + I_l K_s (N.H)^n",
        measured=None,
        verdict=HOLDS if same else FAILS,
        reason="the three printed terms sum to the printed total (the ambient 'I_a = K_a I_a' reuses "
        "the symbol I_a for the ambient light).",
    )


def phong_specular(c: dict, source: str, ev: Evidence) -> Claim:
    """'illumination models that Phong proposed ... I_s = I_l K_s (N.H)^n', H 'between lighting vector and the
    viewing vector' (Stencil paper Sec. 5): Phong's own specular term (1975) is (R.V)^n, R = 2 (N.L) N - L the
    light's mirror direction; (N.H)^n with the halfway vector is Blinn's (1977).  Both evaluated with the eye at the
    mirror direction, and with the eye along the normal and the light ``angle`` degrees off it, at ``exponent``."""
    N = sp.Matrix([0, 0, 1])
    t = sp.rad(c["angle"])
    L = sp.Matrix([sp.sin(t), 0, sp.cos(t)])
    R = 2 * N.dot(L) * N - L
    k = int(c["exponent"])

    def terms(V: sp.Matrix) -> tuple[float, float]:
        H = (L + V) / (L + V).norm()
        return float(R.dot(V) ** k), float(N.dot(H) ** k)

    mirror, along = terms(R), terms(N)
    differ = abs(along[0] - along[1]) > 1e-9
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived=f"N = (0, 0, 1), the light {c['angle']} degrees off N, n = {k}: eye at the mirror direction R: "
        f"(R.V)^n = {mirror[0]:.4f}, (N.H)^n = {mirror[1]:.4f}; eye along N: (R.V)^n = {along[0]:.4f}, "
        f"(N.H)^n = {along[1]:.4f}",
        measured=None,
        verdict=FAILS if differ else HOLDS,
        reason="Phong (1975) wrote the specular term with the light's mirror direction R: (R.V)^n. The printed "
        "(N.H)^n, with the halfway vector the paper itself defines ('between lighting vector and the viewing "
        "vector'), is Blinn's 1977 form, now called Blinn-Phong: the two agree at the mirror direction and differ "
        "around it (Blinn's exponent is about 4n for the same highlight)."
        if differ
        else "",
    )


def definition_scope(c: dict, source: str, ev: Evidence) -> Claim:
    """A count defined per face ("e_n is number of all edges in face f": ``per_face``, the paper's m) against
    what the model's sums substitute for it."""
    symbol = F.LOCALS[c["symbol"]]
    used, per_face = F.substitutions(c["model"])[symbol], F.parse(c["per_face"])
    same = sp.simplify(used - per_face) == 0
    return claim_from_data(
        c,
        source,
        "mesh model",
        rederived=f"the sums substitute {c['symbol']} = {sp.sstr(used)}; the edges of one face are {per_face}",
        measured=None,
        verdict=HOLDS if same else FAILS,
        reason=f"{c['use_note']} As defined, {c['symbol']} would be {per_face}; as used, the definition's "
        "'in face f' is wrong."
        if not same
        else "the definition matches the sums.",
    )


def self_definition(c: dict, source: str, ev: Evidence) -> Claim:
    """A printed definition ``lhs = rhs`` (``equation``, sympy syntax) whose defined symbol occurs on its right:
    solved for the other symbols, what the equation forces."""
    lhs, rhs = (sp.sympify(x) for x in c["equation"].split("="))
    circular = lhs.free_symbols & rhs.free_symbols
    forced = sp.solve(sp.Eq(lhs, rhs), dict=True)
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived=f"{lhs} = {rhs} holds only for "
        + " or ".join(", ".join(f"{k} = {v}" for k, v in f.items()) for f in forced),
        measured=None,
        verdict=FAILS if circular else HOLDS,
        reason=(
            f"{', '.join(map(str, circular))} is defined by itself; {c['use_note']}" if circular else "no circularity."
        ),
    )


RULES = {
    "phong_specular": phong_specular,
    "self_definition": self_definition,
    "definition_scope": definition_scope,
    "kernel_cost": kernel_cost,
    "mesh_ratio": mesh_ratio,
    "n_meaning": n_meaning,
    "table_point": table_point,
    "complexity": complexity,
    "big_oh": big_oh,
    "loop_bound": loop_bound,
    "edge_count": edge_count,
    "fan_triangles": fan_triangles,
    "phong": phong,
}
