"""Primitive costs, the mesh model (n, V/F/E, the tables' m), complexity, and small algebraic facts.

EESD paper Sec. 2, 5, 5.1-5.3, 6, 7; HSD paper Sec. V, VI, VIII (Table 1).
Every rule computes its verdict: kernels are executed on counting
arithmetic (:mod:`silcount.papers.kernels`), identities are decided by
sympy, complexity by the measured exponents (:class:`~silcount.papers.claims.context.Evidence`).
"""

from __future__ import annotations

import itertools

import sympy as sp

from silcount.mesh.shapes import builtin_mesh
from silcount.papers import formulas as F
from silcount.papers import kernels
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
    printed = {k: int(v) for k, v in c["cost"].items() if k in kernels.ARITHMETIC}
    readings = []
    for name in c["kernels"]:
        got = kernels.kernel_cost(name)
        shown = " + ".join(f"{v}{F.KIND_SYMBOLS[k]}" for k, v in sorted(got.items())) or "no arithmetic"
        readings.append(Reading(kernels.KERNELS[name][1], got == printed, f"executed: {shown}"))
    return _judged(
        c,
        source,
        "primitive",
        readings,
        reason="each reading of the operation executed on counting arithmetic (add, mul, cmp; reads and writes "
        "depend on a memory layout the paper does not give).",
    )


def _euler_rows():
    return [(name, m.n_vertices, m.n_faces, m.n_edges) for name, m in ((n, builtin_mesh(n)) for n in EULER_MESHES)]


def mesh_ratio(c: dict, source: str, ev: Evidence) -> Claim:
    vpf, epf = c["vertices_per_face"], c.get("edges_per_face")
    rows = _euler_rows()
    measured = "; ".join(f"{name}: V/F = {V / Fc:.3f}, E/F = {E / Fc:.3f}" for name, V, Fc, E in rows)
    g = sp.Symbol("g")
    parts = []
    if epf is not None:
        genus = sp.solve(sp.Eq(vpf - epf + 1, (2 - 2 * g) / F.n), g)[0]
        parts.append(
            f"V = {vpf}n, E = {epf}n, F = n in Euler's V - E + F = 2 - 2g needs genus {sp.sstr(genus)}, "
            f"and 2E = mF needs m = {2 * epf}-gons"
        )
    parts.append("closed triangle meshes have E/F = 3/2 and V/F -> 1/2 (2E = 3F and V - E + F = 2 - 2g)")
    ok = all(abs(V / Fc - vpf) < 0.1 * vpf for _, V, Fc, _ in rows)
    return claim_from_data(
        c,
        source,
        "mesh model",
        rederived="; ".join(parts),
        measured=measured,
        verdict=HOLDS if ok else FAILS,
        reason="Euler's formula: the printed ratios fit no closed triangle mesh (V/F = 2 is F/V inverted) and, "
        "with E = 6n, only a polygon mesh of 12-gons of genus about 1.5n; the built-in closed meshes agree.",
    )


def n_meaning(c: dict, source: str, ev: Evidence) -> Claim:
    sub = F.substitutions("eesd2012-ta")
    readings = [
        Reading(
            "n = vertices (as the text says)",
            False,
            f"the sums substitute f_n = {sp.sstr(sub[F.f_n])}, e_n = {sp.sstr(sub[F.e_n])}: with n vertices the "
            "paper's own ratios give f_n = n/2 and e_n = 3n",
        ),
        Reading(
            "n = faces (as the substitutions say)",
            False,
            "then the text's 'n vertices' and the tables' "
            "'number of vertices on the corner of occluder is 10' are wrong",
        ),
    ]
    return _judged(
        c,
        source,
        "mesh model",
        readings,
        reason="the text and the substitutions give n two meanings; under each, one of them is false.",
    )


def table_point(c: dict, source: str, ev: Evidence) -> Claim:
    sub = F.substitutions("eesd2012-ta")
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
        "itself needs triangles ('each edge should be shared by just two triangles'), m = 3.",
    )


def complexity(c: dict, source: str, ev: Evidence) -> Claim:
    model, deg = c["model"], c["degree"]
    unit = {k: 1.0 for k in F.KINDS}
    got = F.degree(F.weighted(F.paper_forms(model)["convention"], unit))
    det = F.models.load(model)["algorithm"]
    ours = [e for e in ev.exponents if e.detector == det and e.cost_model == "true"]
    if not ours:
        raise ValueError(f"no measured exponent for detector {det!r}: the complexity claim needs one")
    tol = 0.05
    bound = all(e.low <= deg + tol for e in ours)
    tight = all(e.low <= deg + tol and e.high >= deg - tol for e in ours)
    shown = "; ".join(
        f"{e.detector} {e.cost_model}: F^{e.exponent:.2f} [{e.low:.2f}, {e.high:.2f}] ({e.source})" for e in ours
    )
    readings = [
        Reading(
            "O as an upper bound (grows no faster than n^2)",
            got <= deg and bound,
            f"sum of degree {got}; every measured interval reaches down to {deg} + {tol}"
            if bound
            else "a measured interval lies above n^2",
        ),
        Reading(
            "tight, as the sums' leading n^2 terms say",
            got == deg and tight,
            "every measured interval meets n^2 (within 0.05)" if tight else "a measured interval excludes n^2",
        ),
    ]
    paper = [e for e in ev.exponents if e.detector == det and e.cost_model == "paper"]
    return _judged(
        c,
        source,
        "complexity",
        readings,
        rederived=f"papers'-convention sum: degree {got} in n (e_n = 6n, f_n = n)",
        measured=shown + "".join(f"; paper cost model F^{e.exponent:.2f}" for e in paper),
        reason="measured evidence decides: fitted exponents of total operations (true cost) vs faces, 95% intervals.",
    )


def big_oh(c: dict, source: str, ev: Evidence) -> Claim:
    unit = {k: 1.0 for k in F.KINDS}
    degs = {mdl: F.degree(F.weighted(F.paper_forms(mdl)["convention"], unit)) for mdl in [c["winner"], *c["others"]]}
    same = len(set(degs.values())) == 1
    return claim_from_data(
        c,
        source,
        "complexity",
        rederived=", ".join(f"{algo(k)}: O(n^{d})" for k, d in degs.items()),
        measured=None,
        verdict=FAILS if same else HOLDS,
        reason="the paper's own sums put all three in one O class; Big-Oh drops constant factors and cannot order "
        "algorithms of one class"
        if same
        else "the classes differ",
    )


def loop_bound(c: dict, source: str, ev: Evidence) -> Claim:
    loop = F.models.load(c["model"])["loops"][c["loop"]]
    prose, printed = F.parse(loop["bound"]), F.parse(loop["bound_printed"])
    readings = [
        Reading("'decreased to 1'", True, f"the printed sum's {printed} follows"),
        Reading("'decreased by 1' (m - 1)", sp.simplify(prose - printed) == 0, f"the sum should use {prose}"),
    ]
    return _judged(
        c,
        source,
        "derivation",
        readings,
        reason="the sentence and the sum disagree and the paper does not say which is meant; every HSD "
        "claim is judged under both.",
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


def coplanar(c: dict, source: str, ev: Evidence) -> Claim:
    a, b = sp.symbols("a b", real=True)
    Lv, p0, u, w = (sp.Matrix(sp.symbols(f"{x}0:3", real=True)) for x in ("L", "p", "u", "w"))
    normal = u.cross(w)
    moved = p0 + a * u + b * w
    same = sp.expand((Lv - moved).dot(normal) - (Lv - p0).dot(normal)) == 0
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="(L - p).n is the same for every p of the plane",
        measured=None,
        verdict=HOLDS if same else FAILS,
        reason="symbolic: moving p within the plane (p0 + a u + b w, n = u x w) leaves (L - p).n fixed.",
    )


def facing_sign(c: dict, source: str, ev: Evidence) -> Claim:
    vv, fv, nf = (sp.Matrix(sp.symbols(f"{x}0:3", real=True)) for x in ("v", "f", "n"))
    dist = (vv - fv).dot(nf)
    D = (fv - vv).dot(nf) / (nf.norm() * (fv - vv).norm())
    opposite = sp.simplify(D * nf.norm() * (fv - vv).norm() + dist) == 0
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="D_i = -||v, f|| / (|n| |f_v - v|)" if opposite else "same sign",
        measured=None,
        verdict=FAILS if opposite else HOLDS,
        reason="D_i has the opposite sign of ||v, f||, so 'D_i > 0 then front face' calls back faces front "
        "under the paper's own first test ('||v, f|| > 0 then f is a front face')."
        if opposite
        else "",
    )


def silhouette_product(c: dict, source: str, ev: Evidence) -> Claim:
    ok = all(
        ((s1 * s2) < 0) == ((s1 > 0) != (s2 > 0)) for s1, s2 in itertools.product((-2.0, -0.5, 0.5, 3.0), repeat=2)
    )
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="product < 0 iff exactly one face is front-facing",
        measured=None,
        verdict=HOLDS if ok else FAILS,
        reason="the paper's own definition (Sec. 2: one neighbour towards the light, one away).",
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


RULES = {
    "kernel_cost": kernel_cost,
    "mesh_ratio": mesh_ratio,
    "n_meaning": n_meaning,
    "table_point": table_point,
    "complexity": complexity,
    "big_oh": big_oh,
    "loop_bound": loop_bound,
    "edge_count": edge_count,
    "fan_triangles": fan_triangles,
    "coplanar": coplanar,
    "facing_sign": facing_sign,
    "silhouette_product": silhouette_product,
    "phong": phong,
}
