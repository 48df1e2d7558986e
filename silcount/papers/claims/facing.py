"""The facing test's small facts: faces with one normal, the sign of the paper's D_i, the silhouette product,
culling by the light, the eye or the light as the test's origin; and EESD's ray-plane test as printed.

HSD paper Sec. V ("all same normal vectors have same status"), Sec. VI (the facing test's "ray from eyes point
of view") and Sec. VIII (culling the faces turned from the light); EESD paper Sec. 2 (D_i and ||v, f||, the
product of the two faces' signs, the "ridge edges") and Sec. 5.3 (its plane test).  Each verdict is decided by
sympy or by evaluating the test, never typed.
"""

from __future__ import annotations

import itertools

import numpy as np
import sympy as sp

from silcount.detectors.adjacency import facing_flags, silhouette_edge_ids
from silcount.detectors.result import differences
from silcount.mesh.lights import PointLight
from silcount.mesh.raytrace import moller_trumbore
from silcount.mesh.shapes import builtin_mesh
from silcount.papers import growth
from silcount.papers.claims.base import FAILS, HOLDS, Claim, Reading, claim_from_data, judged_by_readings
from silcount.papers.claims.context import Evidence


def coplanar(c: dict, source: str, ev: Evidence) -> Claim:
    """'All same normal vectors have same status' (HSD Sec. V), read three ways: the triangles of one flat face
    (the paper's example), and faces with the same normal in parallel planes under a directional light and under a
    point light (the paper's visibility test builds 'a ray from light source to the plan', Sec. VI 6.3)."""
    a, b = sp.symbols("a b", real=True)
    Lv, p0, u, w, d = (sp.Matrix(sp.symbols(f"{x}0:3", real=True)) for x in ("L", "p", "u", "w", "d"))
    normal = u.cross(w)
    moved = p0 + a * u + b * w
    in_plane = sp.expand((Lv - moved).dot(normal) - (Lv - p0).dot(normal)) == 0
    # a directional light: the facing value d . n does not involve the face's position at all
    directional = not (d.dot(normal)).free_symbols & set(p0)
    # a point light between two parallel planes: n = (0, 1, 0), planes y = 0 and y = 2, L = (0, 1, 0)
    n_, L_ = sp.Matrix([0, 1, 0]), sp.Matrix([0, 1, 0])
    lower, upper = ((L_ - sp.Matrix([0, y, 0])).dot(n_) for y in (0, 2))
    readings = [
        Reading("the triangles of one flat face (the example: 'a faces with n vertices ... n-2 triangles')", in_plane,
                "symbolic: moving p within the plane (p0 + a u + b w, n = u x w) leaves (L - p).n fixed"),
        Reading("faces with the same normal in parallel planes, directional light", directional,
                "d.n does not depend on the face's position"),
        Reading("faces with the same normal in parallel planes, point light (HSD's visibility builds a ray from "
                "the light source to the plane)", bool(sp.sign(lower) == sp.sign(upper)),
                f"n = (0, 1, 0) on the planes y = 0 and y = 2, L = (0, 1, 0): (L - p).n = {lower} and {upper}, "
                "one face lit and the other not"),
    ]  # fmt: skip
    return judged_by_readings(
        c,
        source,
        "algorithm",
        readings,
        "the sentence names 'same normal vectors'; its example and HSD's merge ('each face that is flat') are "
        "coplanar faces, for which it holds under any light, and faces that only share a normal keep one status "
        "only under a directional light.",
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


def signed_distance(c: dict, source: str, ev: Evidence) -> Claim:
    """'The distance between v and f is ||v, f|| = (v - f_v) . n_f', with 'n_f is normal vector of f' (EESD
    Sec. 2), against the point-plane distance, on a face by hand: (0, 0, 0), (2, 0, 0), (0, 2, 0) and v = (0, 0, 1),
    with n_f as the paper computes a normal (a cross product of two edges, Sec. 5.1's '3Adds and 3Muls': no
    square root or division, so not a unit vector) and as a unit normal."""
    corners = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    v = np.array([0.0, 0.0, 1.0])
    cross = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    unit = cross / np.linalg.norm(cross)
    printed = {"cross": float((v - corners[0]) @ cross), "unit": float((v - corners[0]) @ unit)}
    distance = abs(printed["unit"])  # the point-plane distance
    readings = [
        Reading(
            f"n_f as the paper computes it, the cross product {tuple(cross.tolist())}",
            bool(np.isclose(printed["cross"], distance)),
            f"(v - f_v) . n_f = {printed['cross']:g}, the distance {distance:g}",
        ),
        Reading(
            "n_f a unit normal", bool(np.isclose(printed["unit"], distance)), f"(v - f_v) . n_f = {printed['unit']:g}"
        ),
    ]
    return judged_by_readings(
        c,
        source,
        "algorithm",
        readings,
        "(v - f_v) . n_f is the signed distance only for a unit n_f; the paper's normal is a cross product it "
        "never normalises, so its value is the distance times |n_f| (twice the face's area here). Its sign, "
        "which is all the facing test uses, is right either way.",
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


def light_culling(c: dict, source: str, ev: Evidence) -> Claim:
    """'All faces that have normal vectors toward away of light source should be culled' (HSD Sec. VIII), as view
    culling: on convex built-in meshes (every face turned to the eye is seen), the faces turned from the light but
    to the eye, for an eye at silcount's standard light (the HSD paper's 'the light source is located in the viewer
    point of eyes', Sec. V, where no shadow can be seen) and for an eye opposite it."""
    parts, visible_culled = [], 0
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        light = growth.standard_light(mesh)
        lit = facing_flags(mesh, light)[0]
        offset = np.asarray(light.position) - mesh.centre
        for label, eye_offset in (("at the light", offset), ("opposite the light", -offset)):
            seen = facing_flags(mesh, PointLight(tuple(mesh.centre + eye_offset)))[0]
            culled = int(np.count_nonzero(seen & ~lit))
            if label != "at the light":
                visible_culled += culled
            parts.append(f"{name}, eye {label}: {culled} of {int(seen.sum())} faces turned to the eye are culled")
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="; ".join(parts),
        measured=None,
        verdict=FAILS if visible_culled else HOLDS,
        reason="a face turned from the light but to the eye is seen (its shadowed side), so culling it leaves a "
        "hole; the faces turned from the light are the faces hidden from the eye only when the eye is at the light, "
        "where no shadow can be seen. Convex meshes, so a face turned to the eye is visible.",
    )


def facing_viewpoint(c: dict, source: str, ev: Evidence) -> Claim:
    """'To determine a face p is visible or not a ray from eyes point of view is needed' (HSD Sec. VI 6.1, 6.2),
    for the silhouette a shadow volume is extruded from: on built-in meshes, the light's silhouette against the
    edges a facing test from the eye finds, for an eye at silcount's standard light (the HSD paper's Sec. V example:
    'the light source is located in the viewer point of eyes') and for an eye beside it (as far from the mesh's
    centre, a right angle away)."""
    parts, differ = [], 0
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        light = growth.standard_light(mesh)
        want = silhouette_edge_ids(mesh, light)
        offset = np.asarray(light.position, dtype=float) - mesh.centre
        axis = np.eye(3)[int(np.argmin(np.abs(offset)))]  # the axis least along the offset
        side = np.cross(offset, axis)
        side *= np.linalg.norm(offset) / np.linalg.norm(side)
        for label, eye_offset in (("at the light", offset), ("beside the light", side)):
            got = differences(silhouette_edge_ids(mesh, PointLight(tuple(mesh.centre + eye_offset))), want)
            if label != "at the light":
                differ += got["disagreement_with_reference"]
            parts.append(
                f"{name}, eye {label}: {got['missed_edges']} of the light's {want.size} silhouette edges missed, "
                f"{got['extra_edges']} others found"
            )
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="; ".join(parts),
        measured=None,
        verdict=FAILS if differ else HOLDS,
        reason="a shadow volume is extruded from the light's silhouette (the paper's own definition, Sec. III: one "
        "face 'toward the light', one away; and its own costing of the same test, lines 181 and 201: 'a ray from "
        "light source to the plan'). A facing test from the eye finds the view's silhouette: the same edges only "
        "when the eye is at the light, where no shadow can be seen.",
    )


def plane_test(c: dict, source: str, ev: Evidence) -> Claim:
    """'If the equation of plane is ax+by+cz+d=0 then if aR_x+bR_y+cR_z+d=0 then the ray intersected the plane'
    (EESD Sec. 5.3, the pseudo-code's Intersection(R, f)), against the ray's own crossing of the plane and its
    meeting the face (silcount's tracer, Moller-Trumbore, ``t > 0``), on two rays by hand towards -z and the face
    (0, 0, 0), (1, 0, 0), (0, 1, 0) in the plane z = 0 (a = b = d = 0, c = 1): one from a point above the face,
    one from a point of the plane outside it."""
    tri = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    a, b, cz, d = 0.0, 0.0, 1.0, 0.0
    down = (0.0, 0.0, -1.0)
    parts, wrong = [], 0
    for label, R in (("above the face", (0.25, 0.25, 1.0)), ("on the plane, outside the face", (2.0, 2.0, 0.0))):
        value = a * R[0] + b * R[1] + cz * R[2] + d
        t = -value / (a * down[0] + b * down[1] + cz * down[2])  # where the ray's line meets the plane
        face = bool(moller_trumbore(*R, *down, *tri.ravel(), 0.0, np.inf)[0])  # type: ignore[call-arg]  # numba
        printed = value == 0.0
        wrong += printed != face  # the pseudo-code asks Intersection(R, f): the face
        crossing = f"crosses the plane at t = {t:g}" if t > 0.0 else "starts on the plane (t = 0)"
        if t < 0.0:
            crossing = "points away from the plane"
        parts.append(
            f"R = {R} {label}: aR_x+bR_y+cR_z+d = {value:g}, so the printed test says "
            f"{'intersected' if printed else 'no intersection'}; the ray {crossing}; "
            f"it meets the face: {'yes' if face else 'no'}"
        )
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="; ".join(parts),
        measured=None,
        verdict=FAILS if wrong else HOLDS,
        reason="the printed test puts one point of the ray in the plane equation: it asks whether R lies on the "
        "plane, not whether the ray meets the plane or the face. A ray from a point off the plane that crosses "
        "it, and the face, is answered 'no'; a point of the plane outside the face is answered 'yes'. Putting "
        "the ray itself in the equation gives t = -(n.R + d) / (n.dir), a division and a test of t (the "
        "'ray crossing' reading of the test's cost), and the face needs more (Moller-Trumbore)."
        if wrong
        else "",
    )


def ridge_definition(c: dict, source: str, ev: Evidence) -> Claim:
    """The EESD paper's categories (Sec. 2): 'ridge edges ... one visible plane face and one invisible plane face',
    against the silhouette's 'visible edges which connect the back faces to the front faces' and against the
    ridges of Isenberg et al. 2003 (the paper's [7]): creases whose faces' normals meet at more than
    ``crease_degrees``, whatever the view.  On closed built-in meshes, viewed from silcount's standard light
    (visible = turned to the eye; closed two-faced meshes, so every edge has one face on each side or none)."""
    parts, same_as_silhouette, differs_from_creases = [], True, False
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        if not (mesh.edge_valence == 2).all():
            raise ValueError(f"{c['id']}: {name} is not a closed two-manifold mesh")
        seen = facing_flags(mesh, growth.standard_light(mesh))[0]
        start, order = mesh.edge_sides
        faces = mesh.side_face[order].reshape(-1, 2)  # closed two-manifold: two sides per edge, in edge order
        paper = seen[faces[:, 0]] != seen[faces[:, 1]]
        silhouette = np.zeros(mesh.n_edges, dtype=bool)
        silhouette[silhouette_edge_ids(mesh, growth.standard_light(mesh))] = True
        cos = np.einsum("ij,ij->i", *(mesh.face_normals[faces[:, k]] for k in (0, 1)))
        lengths = [np.linalg.norm(mesh.face_normals[faces[:, k]], axis=1) for k in (0, 1)]
        cos /= lengths[0] * lengths[1]
        crease = cos < np.cos(np.radians(c["crease_degrees"]))
        same_as_silhouette &= bool(np.array_equal(paper, silhouette))
        differs_from_creases |= not np.array_equal(paper, crease)
        parts.append(
            f"{name}: {int(paper.sum())} edges by the printed definition, {int(silhouette.sum())} silhouette edges, "
            f"{int(crease.sum())} creases over {c['crease_degrees']} degrees, of {mesh.n_edges}"
        )
    return claim_from_data(
        c,
        source,
        "algorithm",
        rederived="; ".join(parts),
        measured=None,
        verdict=FAILS if same_as_silhouette and differs_from_creases else HOLDS,
        reason="the printed 'ridge' is the silhouette again (the same edges on every mesh, and view-dependent), not "
        "the crease of Isenberg et al. 2003 (the paper's [7]), which depends on the angle between the faces alone."
        if same_as_silhouette and differs_from_creases
        else "",
    )


RULES = {
    "signed_distance": signed_distance,
    "facing_viewpoint": facing_viewpoint,
    "plane_test": plane_test,
    "ridge_definition": ridge_definition,
    "light_culling": light_culling,
    "coplanar": coplanar,
    "facing_sign": facing_sign,
    "silhouette_product": silhouette_product,
}
