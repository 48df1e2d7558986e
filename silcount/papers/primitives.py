"""The papers' primitive operations, executed on counting arithmetic.

EESD paper Sec. 5 ("A dot product needs 3 Multiplies and 2 Adds. A vector or
ray addition requires 3 Adds"), Sec. 5.1 (face normal "3Adds and 3Muls", light
ray "4Muls and 3Adds", edge inverse "one Inverse or 1Muls": a vertex-pair swap or,
with signed edge ids, a multiply by -1; the paper does not say how edges are stored), Sec. 5.3 (ray
point "3Mults and 3Adds", the plane test ``aR_x+bR_y+cR_z+d=0`` or, as ``Intersection(R, f)`` names it, a
test of the face itself; "to extend each edge three addition": a given offset added, or the end moved along its
edge).  Each
kernel is the operation under one reading of the text; :func:`kernel_cost`
counts what executing it costs (arithmetic kinds only: reads and writes
depend on the memory layout, which the papers do not give).
"""

from __future__ import annotations

from silcount.counting.arithmetic import Num, OpCounter, plain


def _vec(counter: OpCounter, *vals: float) -> list[Num]:
    return [Num(x, counter) for x in vals]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _kernel_dot(c):
    _dot(_vec(c, 1, 2, 3), _vec(c, 4, 5, 6))


def _kernel_vector_add(c):
    a, b = _vec(c, 1, 2, 3), _vec(c, 4, 5, 6)
    [a[i] + b[i] for i in range(3)]


def _kernel_ray_point(c):
    x0, d, t = _vec(c, 1, 2, 3), _vec(c, 4, 5, 6), Num(0.5, c)
    [x0[i] + t * d[i] for i in range(3)]


def _kernel_light_vector(c):
    light, p0 = _vec(c, 0, 0, 5), _vec(c, 1, 0, 0)
    [light[i] - p0[i] for i in range(3)]


def _kernel_light_vector_homogeneous(c):
    light, w, p0 = _vec(c, 0, 0, 5), Num(1.0, c), _vec(c, 1, 0, 0)
    [light[i] - w * p0[i] for i in range(3)]


def _kernel_normal(c):
    p0, p1, p2 = _vec(c, 1, 0, 0), _vec(c, 0, 1, 0), _vec(c, 0, 0, 1)
    e1 = [p1[i] - p0[i] for i in range(3)]
    e2 = [p2[i] - p0[i] for i in range(3)]
    [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]


def _kernel_normal_precomputed(c):
    _vec(c, 0, 0, 1)  # the normal is read, not computed


def _kernel_edge_inverse(c):
    a, b = 3, 7
    a, b = b, a  # reversing an edge swaps its two vertex ids


def _kernel_edge_inverse_signed(c):
    _ = Num(5, c) * -1  # signed edge ids, twin = -e: the reverse is one multiply by -1


def _kernel_cross_product(c):
    e1, e2 = _vec(c, -1, 1, 0), _vec(c, -1, 0, 1)  # two stored edge vectors
    [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]


def _kernel_light_ray_parametric(c):
    light, p0, t = _vec(c, 0, 0, 5), _vec(c, 1, 0, 0), Num(0.5, c)
    [light[i] + t * (p0[i] - light[i]) for i in range(3)]  # a point L + t (p0 - L) of the ray


def _kernel_point_in_plane(c):
    plane, r = _vec(c, 0, 0, 1, -1), _vec(c, 1, 2, 1)
    _ = plane[0] * r[0] + plane[1] * r[1] + plane[2] * r[2] + plane[3] == 0


def _kernel_ray_plane(c):
    plane, x0, d = _vec(c, 0, 0, 1, -1), _vec(c, 1, 2, 5), _vec(c, 0, 0, -1)
    num = _dot(plane, x0) + plane[3]
    den = _dot(plane, d)
    _ = num * den < 0  # the ray x0 + t d (t > 0) crosses the plane


def _kernel_ray_triangle(c):
    from silcount.detectors.eesd.counted import counted_triangle_hit

    o, d = _vec(c, 0.2, 0.2, 5), _vec(c, 0, 0, -1)
    counted_triangle_hit(o, d, _vec(c, 0, 0, 0), _vec(c, 1, 0, 0), _vec(c, 0, 1, 0), 0.0, float("inf"))


def _kernel_extend_along_edge(c):
    v1, v2, s = _vec(c, 1, 0, 0), _vec(c, 0, 0, 0), Num(1e-6, c)
    [v1[i] + s * (v1[i] - v2[i]) for i in range(3)]  # the end moved a little further along its own edge


def _kernel_append(c):
    s, size, e = [0, 0], 1, 7
    s[size] = e  # S[k] = edge: a write, no arithmetic


def _kernel_append_counted(c):
    s, size, e = [0, 0], Num(1, c), 7
    s[int(plain(size))] = e
    size = size + 1  # the array's length kept as a counter: one add


def _kernel_sign_test(c):
    _ = Num(0.25, c) > 0


def _kernel_visibility(c):
    from silcount.detectors.base import visibility_true_cost
    from silcount.mesh.lights import PointLight

    c.update(visibility_true_cost(PointLight((0.0, 0.0, 5.0))))


def _kernel_visibility_precomputed(c):
    light, p0, normal = _vec(c, 0, 0, 5), _vec(c, 1, 0, 0), _vec(c, 0, 0, 1)
    _ = _dot([light[i] - p0[i] for i in range(3)], normal) > 0


KERNELS = {
    "dot": (_kernel_dot, "a.b"),
    "vector_add": (_kernel_vector_add, "a+b, three components"),
    "ray_point": (_kernel_ray_point, "x0 + t d"),
    "light_vector": (_kernel_light_vector, "L - p0"),
    "light_vector_homogeneous": (_kernel_light_vector_homogeneous, "L - w p0 (homogeneous light)"),
    "normal_from_corners": (_kernel_normal, "(p1-p0) x (p2-p0)"),
    "normal_precomputed": (_kernel_normal_precomputed, "a stored normal, read"),
    "edge_inverse": (_kernel_edge_inverse, "(a, b) -> (b, a): an edge as its two vertex ids, swapped"),
    "edge_inverse_signed": (_kernel_edge_inverse_signed, "e -> -e: signed edge ids (twin = -e), one multiply by -1"),
    "cross_product": (_kernel_cross_product, "e1 x e2 of two stored edge vectors"),
    "light_ray_parametric": (_kernel_light_ray_parametric, "a point L + t (p0 - L) of the ray"),
    "point_in_plane": (
        _kernel_point_in_plane,
        "aR_x+bR_y+cR_z+d = 0 for a point R (the paper's own test, line 353: whether R lies on the plane, not "
        "whether the ray meets it: eesd-plane-test-logic)",
    ),
    "ray_plane": (_kernel_ray_plane, "does the ray x0 + t d, t > 0, cross the plane"),
    "ray_triangle": (
        _kernel_ray_triangle,
        "does the ray meet the face itself (a triangle, Moller-Trumbore, the test silcount's working EESD runs; "
        "its one division is not among the papers' kinds)",
    ),
    "extend_along_edge": (_kernel_extend_along_edge, "v1 + s (v1 - v2): the end moved along its own edge"),
    "append": (_kernel_append, "S[k] = e: an append as a write"),
    "append_counted": (_kernel_append_counted, "S[size] = e; size = size + 1: an append with its length counted"),
    "sign_test": (_kernel_sign_test, "x > 0"),
    "visibility": (_kernel_visibility, "silcount's counted visibility (normal from corners, L - p0, dot, sign)"),
    "visibility_precomputed": (_kernel_visibility_precomputed, "(L - p0) . n > 0 with a stored normal"),
}
ARITHMETIC = ("add", "mul", "cmp")


def kernel_cost(name: str) -> dict[str, int]:
    """What kernel ``name`` costs in add, mul and cmp, measured by executing it on counting arithmetic."""
    counter = OpCounter()
    KERNELS[name][0](counter)
    return {k: int(x) for k, x in counter.items() if x and k in ARITHMETIC}
