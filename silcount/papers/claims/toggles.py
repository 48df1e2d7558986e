"""TA's array S as the papers print it: the pseudo-code's two readings of ``Delete v_p v_q``, the HSD prose's one
pass over every triangle's sides, and the stencil paper's toggle over all NP polygons.

HSD paper Sec. 4.1 (the pseudo-code, S started empty; the prose, S holding "all of the triangles edges"); EESD
paper Sec. 3.1 ("S is a list of silhouette"); stencil paper Sec. 3.2 (the formula ``s = sum_p sum_q iff(V1 in
S[V2], Delete V1, Add V2)``).  Each is run on built-in meshes and its S compared with the reference silhouette.
"""

from __future__ import annotations

import numpy as np

from silcount.detectors import detect
from silcount.detectors.adjacency import facing_flags
from silcount.mesh.shapes import builtin_mesh
from silcount.papers import growth
from silcount.papers.claims.algorithms import _judged, agreement
from silcount.papers.claims.base import FAILS, HOLDS, Claim, Reading, claim_from_data
from silcount.papers.claims.context import Evidence


def _sides(mesh, faces) -> list[tuple[int, int]]:
    """The directed sides (a, b) of ``faces``, face by face, each face's corners in order."""
    out = []
    for p in faces:
        corners = mesh.corners[mesh.face_start[p] : mesh.face_start[p + 1]].tolist()
        out += list(zip(corners, corners[1:] + corners[:1]))
    return out


def _lit_sides(mesh) -> list[tuple[int, int]]:
    """The directed sides of the faces turned to silcount's standard light, by the detectors' own facing test."""
    return _sides(mesh, np.flatnonzero(facing_flags(mesh, growth.standard_light(mesh))[0]).tolist())


def _run_s(sides, initial: list[tuple[int, int]], delete: str) -> tuple[list[tuple[int, int]], int]:
    """TA's loop over ``sides`` on the array S (``initial``, a linear list): a side whose inverse S holds deletes
    the inverse (``delete="found"``) or itself as written (``"written"``: S does not hold it, nothing goes);
    any other side is appended.  S at the end, and the most entries one search examined (the found entry's
    position plus one, all of S when nothing is found)."""
    S, most = list(initial), 0
    for a, b in sides:
        if (b, a) in S:
            pos = S.index((b, a))
            most = max(most, pos + 1)
            if delete == "found":
                del S[pos]
            elif (a, b) in S:
                S.remove((a, b))
        else:
            most = max(most, len(S))
            S.append((a, b))
    return S, most


def ta_pseudocode(c: dict, source: str, ev: Evidence) -> Claim:
    """TA's pseudo-code with S started empty, its ``Delete v_p v_q`` read two ways: as the edge found (its stored
    inverse ``v_p v_q^{-1}``, silcount's ``ta`` detector, ``intended``) and as written, the directed side
    ``v_p v_q``, which S does not hold when the test has just found its inverse (simulated here with a set of
    directed sides over the detectors' own facing flags); each against the reference, one point light per mesh."""
    parts: dict[str, list[str]] = {"stored": [], "written": []}
    agree = {"stored": True, "written": True}
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        light = growth.standard_light(mesh)
        want = {tuple(e) for e in mesh.edges[detect(mesh, light, "reference").edge_ids].tolist()}
        got_stored = {tuple(e) for e in mesh.edges[detect(mesh, light, "ta", engine="fast").edge_ids].tolist()}
        S, _ = _run_s(_lit_sides(mesh), [], "written")
        got_written = {(min(a, b), max(a, b)) for a, b in S}
        for key, got in (("stored", got_stored), ("written", got_written)):
            agree[key] &= got == want
            parts[key].append(agreement(name, got, want))
    readings = [
        Reading("Delete v_p v_q as the edge the test found (its stored inverse)", agree["stored"],
                "; ".join(parts["stored"])),
        Reading("Delete v_p v_q as written (the directed side, not in S: nothing is deleted)", agree["written"],
                "; ".join(parts["written"])),
    ]  # fmt: skip
    return _judged(
        c,
        source,
        "algorithm",
        readings,
        reason="S starts empty and each light-facing face's sides are looked up in S as the pseudo-code prints; "
        "the edges left in S against the reference (an edge whose two faces differ in facing the light, the "
        "papers' Sec. 2 definition) for one point light per mesh.",
    )


def one_pass(c: dict, source: str, ev: Evidence) -> Claim:
    """TA as the HSD prose describes it (Sec. 4.1): S holds every triangle's sides; one pass from the first,
    an edge whose inverse is in S omitted, the others kept: with the omissions made one at a time in array order
    (the first of each twin pair goes, the second then finds no inverse and stays) or for both twins at once.
    No step looks at the light, so neither can give a light's silhouette."""
    parts: dict[str, list[str]] = {"one at a time": [], "twins at once": []}
    silhouette = {"one at a time": True, "twins at once": True}
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        want = len(detect(mesh, growth.standard_light(mesh), "reference").edge_ids)
        sides = _sides(mesh, range(mesh.n_faces))
        alive, every = set(sides), set(sides)
        for a, b in sides:  # one at a time, in array order
            if (b, a) in alive:
                alive.discard((a, b))
        together = {(a, b) for a, b in sides if (b, a) not in every}
        for key, left in (("one at a time", alive), ("twins at once", together)):
            edges = {(min(a, b), max(a, b)) for a, b in left}
            silhouette[key] &= len(edges) == want
            parts[key].append(f"{name}: {len(edges)} edges left of {mesh.n_edges}, {want} silhouette edges")
    readings = [Reading(f"omissions made {key}", silhouette[key], "; ".join(parts[key])) for key in parts]
    return _judged(
        c,
        source,
        "algorithm",
        readings,
        reason="no step of the prose looks at the light, so what is left cannot depend on it; on closed meshes "
        "every edge has its inverse in S.",
    )


def search_bound(c: dict, source: str, ev: Evidence) -> Claim:
    """'Search in the array which needs e_n Compares': the most entries one linear search of S examines (its
    position plus one when found, all of S when not), TA run as its pseudo-code with the found edge deleted,
    S started empty or with every edge (each in its stored orientation), against e_n; one point light per
    mesh."""
    readings = []
    for start, label in (("empty", "S started empty"), ("full", "S started with every edge")):
        parts, ok = [], True
        for name in c["meshes"]:
            mesh = builtin_mesh(name)
            initial = [] if start == "empty" else [(a, b) for a, b in mesh.edges.tolist()]
            _, most = _run_s(_lit_sides(mesh), initial, "found")
            ok &= most <= mesh.n_edges
            parts.append(f"{name}: at most {most} compares in one search, e_n = {mesh.n_edges}")
        readings.append(Reading(label, ok, "; ".join(parts)))
    return _judged(
        c,
        source,
        "algorithm",
        readings,
        reason="a search of S compares against at most the entries S holds; started empty S never holds an edge "
        "twice, started with every edge it also gains the lit sides whose inverse it does not hold.",
    )


def toggle_all(c: dict, source: str, ev: Evidence) -> Claim:
    parts, empty = [], True
    for name in c["meshes"]:
        mesh = builtin_mesh(name)
        S: set[tuple[int, int]] = set()
        for a, b in _sides(mesh, range(mesh.n_faces)):
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


RULES = {
    "search_bound": search_bound,
    "ta_pseudocode": ta_pseudocode,
    "one_pass": one_pass,
    "toggle_all": toggle_all,
}
