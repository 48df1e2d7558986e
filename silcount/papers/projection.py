"""Symbolic analysis of the planar shadow matrix and the 'new pixel' formula.

Stencil paper (stencil-zbuffer-2011-real-time-shadow.txt) Sec. 4 prints a
4x4 shadow matrix and ``P = L + E/(NP-D) (P-L)``; Sec. 5 (and the EESD
paper, Sec. 4) the clipped-volume "new pixel" ``L + E(F-L)/(NF-D)``.  Neither
paper defines E or D.  The correct projection of a point P from a point light
L onto the plane through C with normal N is

    X = L + alpha (P - L),   alpha = N.(C - L) / N.(P - L).

:func:`analyse` decides, for each reading of E and D in
``silcount/models/papers/stencil2011/stencil2011-planar.toml``, whether the formula (and the matrix,
applied to (P, 1) and dehomogenised) equals X for every P; and solves for the
E and D that make them exact.  Everything is symbolic (sympy), no sampling.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import sympy as sp

from silcount.counting import models

NAMES = ("Lx Ly Lz Nx Ny Nz Cx Cy Cz Px Py Pz E D").split()
SYM = {name: sp.Symbol(name, real=True) for name in NAMES}
L = sp.Matrix([SYM["Lx"], SYM["Ly"], SYM["Lz"]])
N = sp.Matrix([SYM["Nx"], SYM["Ny"], SYM["Nz"]])
C = sp.Matrix([SYM["Cx"], SYM["Cy"], SYM["Cz"]])
P = sp.Matrix([SYM["Px"], SYM["Py"], SYM["Pz"]])
E, D = SYM["E"], SYM["D"]
MODEL = "stencil2011-planar"


def _parse(text: str) -> sp.Expr:
    return sp.sympify(text, locals=SYM)


def correct_projection() -> sp.Matrix:
    """Where the ray from L through P meets the plane N.(X - C) = 0."""
    alpha = N.dot(C - L) / N.dot(P - L)
    return L + alpha * (P - L)


def new_pixel() -> sp.Matrix:
    """The printed 'new pixel' formula (components from silcount/models/)."""
    return sp.Matrix([_parse(c) for c in models.load(MODEL)["new_pixel"]["components"]])


def shadow_matrix() -> sp.Matrix:
    """The printed 4x4 shadow matrix (rows from silcount/models/)."""
    return sp.Matrix([[_parse(x) for x in row] for row in models.load(MODEL)["shadow_matrix"]["rows"]])


def matrix_image() -> sp.Matrix:
    """The shadow matrix applied to (P, 1), dehomogenised."""
    h = shadow_matrix() * sp.Matrix([*P, 1])
    return sp.Matrix([h[i] / h[3] for i in range(3)])


def _equal(a: sp.Matrix, b: sp.Matrix) -> bool:
    return all(sp.expand(sp.numer(sp.together(x - y))) == 0 for x, y in zip(a, b))


def solve_E_D(expr: sp.Matrix) -> list[dict[sp.Symbol, sp.Expr]]:
    """The (E, D) for which ``expr`` lies on the plane for every P.

    The formulas keep X on the line L-P by construction; N.X = N.C for every P
    gives polynomial identities in P whose coefficients must vanish.
    """
    on_plane = sp.numer(sp.together(N.dot(expr) - N.dot(C)))
    coeffs = sp.Poly(sp.expand(on_plane), *P).coeffs()
    return [sol for sol in sp.solve(coeffs, [E, D], dict=True) if sol.get(E, E) != 0]


@dataclass(frozen=True)
class Reading:
    name: str
    new_pixel_exact: bool
    matrix_exact: bool


@dataclass(frozen=True)
class Analysis:
    readings: tuple[Reading, ...]
    solutions: tuple[str, ...]  # E, D making the new pixel exact
    matrix_equals_formula: bool  # matrix image == formula, for symbolic E, D


@cache
def analyse() -> Analysis:
    """Every reading of E and D: does the formula / the matrix project onto the plane exactly?"""
    target = correct_projection()
    formula, image = new_pixel(), matrix_image()
    readings = []
    for r in models.load(MODEL)["readings"]:
        subs = {E: _parse(r["E"]), D: _parse(r["D"])}
        readings.append(Reading(r["name"], _equal(formula.subs(subs), target), _equal(image.subs(subs), target)))
    sols = tuple(
        ", ".join(f"{k} = {sp.sstr(sp.factor(v))}" for k, v in sorted(sol.items(), key=lambda kv: str(kv[0])))
        for sol in solve_E_D(formula)
    )
    return Analysis(tuple(readings), sols, _equal(formula, image))


def _exact_subs() -> dict:
    """The E, D that make the formula exact: E = N.C - N.L, D = N.L."""
    return {E: N.dot(C) - N.dot(L), D: N.dot(L)}


def standard_matrix() -> sp.Matrix:
    """The standard planar shadow matrix for the plane N.X + d = 0 (d = -N.C) and a point light L
    (Blinn 1988; Moller & Haines, Real-Time Rendering: ``(N.L + d) I - L N^T`` in homogeneous form)."""
    d = -N.dot(C)
    m = sp.zeros(4, 4)
    for i in range(3):
        for j in range(3):
            m[i, j] = (N.dot(L) + d if i == j else 0) - L[i] * N[j]
        m[i, 3] = -L[i] * d
        m[3, i] = -N[i]
    m[3, 3] = N.dot(L)
    return m


def printed_is_minus_standard() -> bool:
    """With the exact E, D, is the printed matrix the standard one times -1?"""
    diff = shadow_matrix().subs(_exact_subs()) + standard_matrix()
    return all(sp.expand(x) == 0 for x in diff)


def w_of_occluder_point(normal_y: int = 1) -> sp.Expr:
    """The printed matrix's w for a sample occluder point between the light and the plane (exact E, D):
    light (0, 5, 0), plane y = 0 (N = (0, ``normal_y``, 0): 1 faces the light, -1 faces away; C = 0),
    P = (0.3, 2, 0.1).  Negating N negates the whole matrix (E and D are linear in N), the same projective
    map with the opposite w."""
    h = shadow_matrix().subs(_exact_subs()) * sp.Matrix([*P, 1])
    sample = {SYM["Lx"]: 0, SYM["Ly"]: 5, SYM["Lz"]: 0, SYM["Nx"]: 0, SYM["Ny"]: normal_y, SYM["Nz"]: 0}
    sample |= {SYM["Cx"]: 0, SYM["Cy"]: 0, SYM["Cz"]: 0, SYM["Px"]: sp.Rational(3, 10), SYM["Py"]: 2}
    sample |= {SYM["Pz"]: sp.Rational(1, 10)}
    return sp.nsimplify(h[3].subs(sample))
