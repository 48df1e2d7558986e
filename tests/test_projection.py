"""The planar shadow matrix and 'new pixel' formula (stencil paper Sec. 4-5; EESD paper Sec. 4).

The symbolic verdicts of silcount/projection.py are checked here numerically,
with plain numpy and random configurations: the ray from L through P meets
the plane N.(X - C) = 0 at L + N.(C-L)/N.(P-L) (P - L).
"""

from __future__ import annotations

import numpy as np
import pytest

from silcount.papers import projection


def _printed_new_pixel(L, N, P, E, D):
    return L + E * (P - L) / (N @ P - D)


def _printed_matrix(L, N, E, D):
    M = np.zeros((4, 4))
    M[:3, :3] = np.outer(L, N) + E * np.eye(3)
    M[:3, 3] = -E * L - D * L
    M[3, :3] = N
    M[3, 3] = -D
    return M


@pytest.mark.parametrize("seed", range(5))
def test_exact_only_with_D_equal_N_dot_L(seed):
    rng = np.random.default_rng(seed)
    L, N, C, P = (rng.normal(size=3) for _ in range(4))
    truth = L + (N @ (C - L)) / (N @ (P - L)) * (P - L)
    good = dict(E=N @ C - N @ L, D=N @ L)
    plane_offset = dict(E=N @ L - N @ C, D=N @ C)
    assert np.allclose(_printed_new_pixel(L, N, P, **good), truth)
    assert not np.allclose(_printed_new_pixel(L, N, P, **plane_offset), truth)
    h = _printed_matrix(L, N, **good) @ np.append(P, 1.0)
    assert np.allclose(h[:3] / h[3], truth)


def test_symbolic_analysis_agrees():
    a = projection.analyse()
    exact = {r.name for r in a.readings if r.new_pixel_exact}
    assert exact == {r.name for r in a.readings if r.matrix_exact}
    assert len(exact) == 1 and next(iter(exact)).startswith("D = N.L")
    assert a.matrix_equals_formula
    assert len(a.solutions) == 1
