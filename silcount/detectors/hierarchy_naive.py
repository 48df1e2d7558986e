"""The bounded edge hierarchy on counting arithmetic: the ``naive`` engine of ``gaussmap`` and ``cones``.

:func:`build_naive` builds the tree :func:`~silcount.detectors.hierarchy_build.build_fast`
builds, and :func:`query_naive` answers a light with every scalar operation
counted (``docs/counting.md``, "gaussmap and cones"): one depth-first pass
over the preorder nodes, each face evaluated exactly.  The compiled
:func:`~silcount.detectors.hierarchy_query.query_fast` takes the same steps
level by level, with a float32 pre-test of each face's sign.  The tests hold
the two engines' trees, edge sets, steps and tallies equal.
"""

from __future__ import annotations

import math

import numpy as np

from silcount.counting.arithmetic import Memory, Num, OpCounter, plain
from silcount.detectors.base import MeshMemory, counted_face_normal
from silcount.detectors.hierarchy import (
    DIGIT_BITS,
    STEP_NAMES,
    Hierarchy,
    KeyScheme,
    level_slots,
    n_leaves,
    overflows,
    shape,
    tree_edges,
)
from silcount.detectors.hierarchy_build import face_planes
from silcount.mesh.lights import DirectionalLight, Light
from silcount.mesh.model import Mesh


def build_naive(mesh: Mesh, scheme: KeyScheme, leaf_size: int, fanout: int, counter: OpCounter) -> Hierarchy:
    """:func:`~silcount.detectors.hierarchy_build.build_fast`'s tree, built on counting arithmetic."""
    mem = MeshMemory(mesh, DirectionalLight((0.0, 0.0, 1.0)), counter)  # the build reads no light
    F = mesh.n_faces
    p0, nrm = Memory(np.zeros((F, 3)), counter), Memory(np.zeros((F, 3)), counter)
    for f in range(F):
        corner, n = counted_face_normal(mem, f)
        for c in range(3):
            p0[f, c], nrm[f, c] = corner[c], n[c]
    consts = scheme.setup_naive(p0, F, counter)
    ids_plain, rest, start_plain, faces_plain, _ = tree_edges(mesh)
    T = ids_plain.size
    ids, start, faces = (Memory(a, counter) for a in (ids_plain, start_plain, faces_plain))
    keys = Memory(np.zeros(T, dtype=np.uint64), counter)
    for i in range(T):
        e = int(ids_plain[i])  # the loop's own edge: a register
        s = plain(start[e])
        two = int(mesh.edge_valence[e] > 1)  # the valence is the CSR's (bookkeeping)
        f1, f2 = plain(faces[s]), plain(faces[s + two])
        keys[i] = scheme.naive(p0, nrm, f1, f2, consts, counter)
    perm = _counted_radix_argsort(keys, T, scheme.bits, counter)
    # renumber the faces in the order the sorted edges first reach them
    order = Memory(np.zeros(T, dtype=np.int64), counter)
    e_start = Memory(np.zeros(T + 1, dtype=np.int64), counter)
    e_faces = Memory(np.zeros(faces_plain.size, dtype=np.int32), counter)
    local = Memory(np.full(F, -1, dtype=np.int32), counter)
    lp0, lnrm = Memory(np.zeros((F, 3)), counter), Memory(np.zeros((F, 3)), counter)
    nxt = w = 0

    def number(f: int) -> None:
        nonlocal nxt
        local[f] = nxt
        for c in range(3):
            lp0[nxt, c], lnrm[nxt, c] = p0[f, c], nrm[f, c]
        nxt += 1

    for i in range(T):
        e = plain(ids[plain(perm[i])])
        order[i] = e
        for q in range(plain(start[e]), plain(start[e + 1])):
            f = plain(faces[q])
            loc = local[f]
            if loc < 0:
                number(f)
            e_faces[w] = local.data[f]  # the id just read or just written: a register
            w += 1
        e_start[i + 1] = w
    for f in range(F):
        if local[f] < 0:
            number(f)
    r_faces = []
    for e in rest:
        for q in range(int(start_plain[e]), int(start_plain[e + 1])):
            r_faces.append(plain(local[plain(faces[q])]))
            counter.tick("write")  # stored in the rest CSR
    r_start = np.concatenate([[0], np.cumsum(mesh.edge_valence[rest])]).astype(np.int64)
    nodes, depth, bounds, boundary = _bounds_naive(e_start, e_faces, lp0, lnrm, T, leaf_size, fanout, counter)
    level_of, level_start = level_slots(nodes, depth, T, leaf_size, fanout)
    b = np.empty_like(np.asarray(bounds.data))  # stored in level order (a layout, not counted)
    b[level_of] = np.asarray(bounds.data)
    flags = np.empty_like(np.asarray(boundary.data))
    flags[level_of] = np.asarray(boundary.data)
    p0_max = float(np.abs(b[0, 6:]).max()) if T else 0.0
    sizes = {
        "faces": F,
        "tree_edges": T,
        "tree_sides": w,
        "rest_edges": int(rest.size),
        "rest_sides": len(r_faces),
        "nodes": int(nodes.shape[0]),
        "leaves": n_leaves(nodes),
        "sort_passes": -(-scheme.bits // DIGIT_BITS) if T else 0,
    }
    return Hierarchy(
        order=np.asarray(order.data),
        edge_start=np.asarray(e_start.data),
        edge_faces=np.asarray(e_faces.data[:w]),
        nodes=nodes,
        level_of=level_of,
        level_start=level_start,
        nbox=np.ascontiguousarray(b[:, :6]),
        pbox=np.ascontiguousarray(b[:, 6:]),
        boundary=flags,
        rest=rest,
        rest_start=r_start,
        rest_faces=np.asarray(r_faces, dtype=np.int32),
        p0=np.asarray(lp0.data),
        nrm=np.asarray(lnrm.data),
        plane=face_planes(np.asarray(lnrm.data), np.asarray(lp0.data), p0_max),  # the compiled pre-test's (uncounted)
        p0_max=p0_max,
        leaf_size=leaf_size,
        fanout=fanout,
        build_steps=sizes,
        build_tally=dict(counter),
    )


def _bounds_naive(e_start: Memory, e_faces: Memory, p0: Memory, nrm: Memory, T: int, leaf_size: int, fanout: int,
                  counter: OpCounter) -> tuple:  # fmt: skip
    """The nodes' boxes and boundary flags in preorder, last node first, on counting arithmetic."""
    nodes_plain, depth = shape(T, leaf_size, fanout)
    N = nodes_plain.shape[0]
    nodes = Memory(nodes_plain.copy(), counter)  # the shape, as computed; stored below with the boxes
    bounds = Memory(np.zeros((N, 12)), counter)
    boundary = Memory(np.zeros(N, dtype=np.bool_), counter)
    for i in range(N - 1, -1, -1):
        lo, hi = [math.inf] * 6, [-math.inf] * 6  # normal lo, p0 lo; normal hi, p0 hi
        flag = False
        skip = nodes[i, 2]
        if skip == i + 1:
            for e in range(plain(nodes[i, 0]), plain(nodes[i, 1])):
                s, t = e_start[e], e_start[e + 1]
                flag |= (t - s) == 1
                for q in range(plain(s), plain(t)):
                    f = plain(e_faces[q])
                    vals = [nrm[f, c] for c in range(3)] + [p0[f, c] for c in range(3)]
                    lo, hi = _widen(lo, hi, vals, vals)
        else:
            k = i + 1
            while k < skip:
                clo = [bounds[k, c] for c in (0, 1, 2, 6, 7, 8)]
                chi = [bounds[k, c] for c in (3, 4, 5, 9, 10, 11)]
                lo, hi = _widen(lo, hi, clo, chi)
                flag |= bool(plain(boundary[k]))
                k = plain(nodes[k, 2])
        for c in range(3):
            bounds[i, c], bounds[i, 3 + c] = plain(lo[c]), plain(hi[c])
            bounds[i, 6 + c], bounds[i, 9 + c] = plain(lo[3 + c]), plain(hi[3 + c])
        boundary[i] = flag
        for c in range(3):
            nodes[i, c] = int(nodes_plain[i, c])
    return nodes_plain, depth, bounds, boundary


def _widen(lo: list, hi: list, vlo: list, vhi: list) -> tuple[list, list]:
    """Box ``lo``/``hi`` widened by ``vlo``/``vhi``: one counted compare per bound."""
    lo = [v if v < x else x for x, v in zip(lo, vlo)]
    hi = [v if v > x else x for x, v in zip(hi, vhi)]
    return lo, hi


def _counted_radix_argsort(keys: Memory, n: int, key_bits: int, counter: OpCounter) -> Memory:
    """The compiled radix argsort on counting arithmetic (digit extraction is index arithmetic, not counted)."""
    radix = 1 << DIGIT_BITS
    k, idx = Memory(np.array(keys.data, dtype=np.uint64), counter), Memory(np.arange(n, dtype=np.int64), counter)
    k2, idx2 = Memory(np.zeros(n, dtype=np.uint64), counter), Memory(np.zeros(n, dtype=np.int64), counter)
    for shift in range(0, key_bits if n else 0, DIGIT_BITS):
        hist = Memory(np.zeros(radix + 1, dtype=np.int64), counter)
        for i in range(n):
            d = (int(plain(k[i])) >> shift) & (radix - 1)
            hist[d + 1] = hist[d + 1] + 1
        for d in range(radix):
            hist[d + 1] = hist[d + 1] + hist[d]
        for i in range(n):
            key = k[i]
            d = (int(plain(key)) >> shift) & (radix - 1)
            slot = hist[d]
            k2[plain(slot)] = key
            idx2[plain(slot)] = idx[i]
            hist[d] = slot + 1
        k, k2, idx, idx2 = k2, k, idx2, idx
    return idx


def query_naive(mesh: Mesh, tree: Hierarchy, light: Light, counter: OpCounter) -> tuple[np.ndarray, dict, int]:
    """:func:`~silcount.detectors.hierarchy_query.query_fast` on counting arithmetic."""
    directional = isinstance(light, DirectionalLight)
    bounds = Memory(np.full_like(tree.bounds, np.nan) if overflows(tree, light) else tree.bounds, counter)
    boundary = Memory(tree.boundary, counter)
    e_start, e_faces, order = Memory(tree.edge_start, counter), Memory(tree.edge_faces, counter), tree.order
    p0, nrm = Memory(tree.p0, counter), Memory(tree.nrm, counter)
    lv = Memory(np.asarray(light.vector, dtype=np.float64), counter)
    L = [lv[c] for c in range(3)]
    steps = dict.fromkeys(STEP_NAMES, 0)
    out = Memory(np.zeros(tree.order.size + tree.rest.size, dtype=np.int64), counter)
    state = {"k": 0, "ties": 0}

    def test_edge(starts: Memory, faces: Memory, ids: Memory, e: int) -> None:
        steps["edge_test"] += 1
        count: Num | int = 0
        for q in range(plain(starts[e]), plain(starts[e + 1])):
            steps["edge_side"] += 1
            f = plain(faces[q])
            n = [nrm[f, c] for c in range(3)]
            a = L if directional else [L[c] - p0[f, c] for c in range(3)]
            dot = a[0] * n[0] + a[1] * n[1] + a[2] * n[2]
            state["ties"] += plain(dot) == 0.0
            count = Num(int(dot > 0.0), counter) + count
        if count == 1:
            out[state["k"]] = ids[e]
            state["k"] += 1

    nodes = Memory(tree.nodes, counter)
    ids = Memory(order, counter)
    i = 0
    while i < tree.n_nodes:
        steps["node_test"] += 1
        slot = int(tree.level_of[i])  # where preorder node i's boxes are stored (index arithmetic)
        lb, ub = _counted_bound(bounds, slot, L, directional)
        if lb > 0.0:
            if not plain(boundary[slot]):
                steps["node_lit"] += 1
                i = plain(nodes[i, 2])
                continue
            steps["node_lit_open"] += 1
        elif ub <= 0.0:
            steps["node_unlit"] += 1
            i = plain(nodes[i, 2])
            continue
        if nodes[i, 2] != i + 1:
            steps["node_open"] += 1
            i += 1
            continue
        steps["leaf_open"] += 1
        for e in range(plain(nodes[i, 0]), plain(nodes[i, 1])):
            test_edge(e_start, e_faces, ids, e)
        i += 1
    r_start, r_faces, rest = (Memory(a, counter) for a in (tree.rest_start, tree.rest_faces, tree.rest))
    for r in range(tree.rest.size):
        test_edge(r_start, r_faces, rest, r)
    steps["add"] = state["k"]
    return np.asarray(out.data[: state["k"]]), steps, int(state["ties"])


def _counted_bound(bounds: Memory, i: int, L: list[Num], directional: bool) -> tuple[Num, Num]:
    """The node's lower and upper bound of the rounded facing value, as the compiled query computes them."""
    lb = ub = None
    for c in range(3):
        nlo, nhi = bounds[i, c], bounds[i, 3 + c]
        if directional:
            a_lo = a_hi = L[c]
        else:
            a_lo, a_hi = L[c] - bounds[i, 9 + c], L[c] - bounds[i, 6 + c]
        lo, hi = _ordered(a_lo * nlo, a_lo * nhi)
        if not directional:
            lo2, hi2 = _ordered(a_hi * nlo, a_hi * nhi)
            lo = lo2 if lo2 < lo else lo
            hi = hi2 if hi2 > hi else hi
        lb, ub = (lo, hi) if c == 0 else (lb + lo, ub + hi)
    assert lb is not None and ub is not None
    return lb, ub


def _ordered(p: Num, q: Num) -> tuple[Num, Num]:
    return (p, q) if p <= q else (q, p)


__all__ = ["build_naive", "query_naive"]
