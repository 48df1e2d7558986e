"""The ``literature`` section of ``benchmarks.detectors``: gaussmap and cones against the reference kernel.

    SILCOUNT_MESH_DIR=/path/to/shared/data python -m benchmarks.detectors --sections literature

On the mesh of ``benchmarks.detectors`` (1,043,264 faces with 3 rounds), in one run:

* per light (8 directional, 8 point: ``lights(mesh, 16, seed=11)``), the first call
  of each compiled query right after a reference pass (its caches as a frame's other
  work would leave them), and the best of ``REPEAT`` calls of each compiled query (``hierarchy_query.query_fast`` on a
  tree built once with the defaults) and of the reference kernel
  (``adjacency.silhouette_edge_ids``) on the same light, timed back to back;
  medians over the lights, their ratios, and the bandwidth floor of one
  reference pass (``floor_of``); every answer compared with the reference's ids;
  the reference kernel on one thread too (context: both kernels are parallel on a mesh this size);
* edges tested per query (``steps['edge_test']``) over E;
* the build (best of 3, the mesh's cached edge table, sides, p0 and normals
  and the reference's per-mesh arrays warmed first), its ratio to one reference query, the break-even number of
  lights (build / (reference query - hierarchy query)), ``tree.nbytes``, and the
  peak of the allocations traced by ``tracemalloc`` during a separate build
  (numpy and numba arrays both go through the traced allocator), against the
  mesh's memory (``vertices + corners + face_start + edges``); tracemalloc was
  chosen over RSS: it sees exactly the build's allocations, shared pages aside;
  and the first fill of a fresh array the size of the tree's planes, allocated
  by numpy and by the compiled runtime (numpy advises huge pages from 4 MiB);
* a leaf_size x fanout sweep of both schemes, then a table of targets.

Timings on a shared 2-core machine are noisy: read the ratios, not the digits.
No assertion is made on any time.
"""

from __future__ import annotations

import gc
import time
import tracemalloc

import numba
import numpy as np

import silcount
from benchmarks.common import best_time, floor_of, lights
from silcount.detectors import adjacency, cones, gaussmap, hierarchy, hierarchy_build, hierarchy_query

REPEAT = 5  # best of, per light and query
SWEEP_LEAF = (4, 8, 16, 32)
SWEEP_FANOUT = (2, 4, 8)
SWEEP_REPEAT = 3  # best of, per light, in the sweep
SCHEMES = {"gaussmap": gaussmap.SCHEME, "cones": cones.SCHEME}
OWN_KIND = {"gaussmap": "dir", "cones": "point"}  # the light kind each hierarchy is meant for
TARGET_SPEEDUP = {"gaussmap": 10.0, "cones": 5.0}
TARGET_BUILD = 20.0  # build <= 20 reference queries
TARGET_MEMORY = 2.0  # tree and build peak <= 2 x the mesh


def mesh_bytes(mesh: silcount.Mesh) -> int:
    return int(sum(a.nbytes for a in (mesh.vertices, mesh.corners, mesh.face_start, mesh.edges)))


def build_best(mesh, scheme, leaf: int, fanout: int, repeat: int):
    best, tree = float("inf"), None
    for _ in range(repeat):
        tree = None
        t = time.perf_counter()
        tree = hierarchy_build.build_fast(mesh, scheme, leaf, fanout)
        best = min(best, time.perf_counter() - t)
    return tree, best


def build_peak(mesh, scheme, leaf: int, fanout: int) -> int:
    """Peak bytes traced by tracemalloc during one build, above its start (the returned tree included)."""
    gc.collect()
    tracemalloc.start()
    tree = hierarchy_build.build_fast(mesh, scheme, leaf, fanout)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    del tree
    return int(peak)


def query_figures(mesh, tree, ls, ref_ids, repeat: int) -> dict:
    """Per light: best time, edges tested / E, and whether the sorted ids equal the reference's."""
    t, frac, same = [], [], []
    for L, ref in zip(ls, ref_ids, strict=True):
        ids, steps, _ = hierarchy_query.query_fast(mesh, tree, L)
        same.append(bool(np.array_equal(np.sort(ids), ref)))
        frac.append(steps["edge_test"] / mesh.n_edges)
        t.append(best_time(lambda L=L: hierarchy_query.query_fast(mesh, tree, L), repeat))
    return {"t": np.array(t), "frac": np.array(frac), "same": same}


def _ms(x: float) -> str:
    return f"{x * 1e3:7.2f} ms"


def _pct(x: float) -> str:
    return f"{100 * x:6.2f} %"


def _even(build: float, ref: float, query: float) -> str:
    return f"{build / (ref - query):7.1f}" if ref > query else "  never"


@numba.njit(cache=True, parallel=True)
def _fill(a):  # pragma: no cover - compiled
    for i in numba.prange(a.shape[0]):
        for c in range(4):
            a[i, c] = 1.0


@numba.njit(cache=True, parallel=True)
def _new_filled(n):  # pragma: no cover - compiled
    a = np.empty((n, 4), dtype=np.float32)
    for i in numba.prange(n):
        for c in range(4):
            a[i, c] = 1.0
    return a


def fresh_fill_figures(n: int) -> dict:
    """First touch of a fresh array: numpy's allocation (huge-page advice at 4 MiB and more) against numba's."""
    _fill(np.empty((4, 4), dtype=np.float32))
    _new_filled(4)
    out = {"mib": n * 16 / 2**20, "numpy": float("inf"), "compiled": float("inf")}
    for _ in range(3):
        gc.collect()
        t = time.perf_counter()
        a = np.empty((n, 4), dtype=np.float32)
        _fill(a)
        out["numpy"] = min(out["numpy"], time.perf_counter() - t)
        del a
        gc.collect()
        t = time.perf_counter()
        b = _new_filled(n)
        out["compiled"] = min(out["compiled"], time.perf_counter() - t)
        del b
    return out


def section_literature(mesh: silcount.Mesh) -> None:
    print(f"\n== literature: gaussmap and cones vs the reference kernel on {mesh.n_faces:,} faces ==")
    _ = mesh.edges, mesh.manifold_sides, mesh.face_normals, mesh.face_p0, mesh.edge_sides, mesh.side_face
    ls = lights(mesh, 16, seed=11)
    kinds = {
        "dir": [L for L in ls if L.is_directional],
        "point": [L for L in ls if not L.is_directional],
    }
    ref_ids = {k: [adjacency.silhouette_edge_ids(mesh, L) for L in v] for k, v in kinds.items()}  # + precompute
    need, bw, floor = floor_of(mesh)
    mb = mesh_bytes(mesh)
    print(
        f"lights: {len(kinds['dir'])} directional, {len(kinds['point'])} point (lights(mesh, 16, seed=11)); "
        f"per light best of {REPEAT}, medians over the lights"
    )
    print(f"floor: {need / 2**20:.1f} MiB at {bw / 2**30:.2f} GiB/s = {_ms(floor)} (one reference pass)")
    print(
        f"mesh memory (vertices + corners + face_start + edges): {mb / 2**20:.1f} MiB; "
        f"defaults leaf_size={hierarchy.LEAF_SIZE} fanout={hierarchy.FANOUT}"
    )

    # ---- builds with the defaults ----
    trees, build_t, peak = {}, {}, {}
    for name, scheme in SCHEMES.items():
        trees[name], build_t[name] = build_best(mesh, scheme, hierarchy.LEAF_SIZE, hierarchy.FANOUT, 3)
        peak[name] = build_peak(mesh, scheme, hierarchy.LEAF_SIZE, hierarchy.FANOUT)

    # ---- queries: each light timed for the reference and both trees back to back ----
    ref_t: dict[str, list[float]] = {k: [] for k in kinds}
    q: dict[tuple[str, str], dict[str, list[float]]] = {
        (name, k): {"t": [], "frac": [], "same": []} for name in SCHEMES for k in kinds
    }
    cold: dict[tuple[str, str], list[float]] = {(name, k): [] for name in SCHEMES for k in kinds}
    for k, ls_k in kinds.items():
        for L, ref in zip(ls_k, ref_ids[k], strict=True):
            ref_t[k].append(best_time(lambda L=L: adjacency.silhouette_edge_ids(mesh, L), REPEAT))
            for name, tree in trees.items():
                adjacency.silhouette_edge_ids(mesh, L)  # a reference pass streams the mesh through the caches
                t0 = time.perf_counter()
                hierarchy_query.query_fast(mesh, tree, L)
                cold[name, k].append(time.perf_counter() - t0)
                got = query_figures(mesh, tree, [L], [ref], REPEAT)
                for key in ("t", "frac", "same"):
                    q[name, k][key].extend(list(got[key]))
    ref_med = {k: float(np.median(v)) for k, v in ref_t.items()}
    print(f"\n{'per-light query':22s} {'directional':>40s}   {'point':>40s}")
    threads = numba.get_num_threads()
    print(f"{f'reference kernel ({threads} thr)':22s} {_ms(ref_med['dir']):>40s}   {_ms(ref_med['point']):>40s}")
    numba.set_num_threads(1)  # context only: on one thread, as the corpus study times every kernel
    try:
        one = {k: float(np.median([best_time(lambda L=L: adjacency.silhouette_edge_ids(mesh, L), REPEAT)
                                   for L in v])) for k, v in kinds.items()}  # fmt: skip
    finally:
        numba.set_num_threads(threads)
    print(f"{'reference (1 thread)':22s} {_ms(one['dir']):>40s}   {_ms(one['point']):>40s}")
    speedup = {}
    for name in SCHEMES:
        cells = []
        for k in kinds:
            t = np.array(q[name, k]["t"])
            ratio = np.array(ref_t[k]) / t
            speedup[name, k] = ref_med[k] / float(np.median(t))
            cells.append(
                f"{_ms(float(np.median(t)))} ref/this {speedup[name, k]:6.1f}x ({ratio.min():.1f}..{ratio.max():.1f})"
            )
        print(f"{name + ' query_fast':22s} {cells[0]:>40s}   {cells[1]:>40s}")
    for name in SCHEMES:
        cells = [f"{_ms(float(np.median(cold[name, k])))} ref/this {ref_med[k] / float(np.median(cold[name, k])):6.1f}x"
                 for k in kinds]  # fmt: skip
        print(f"{name + ', first call':22s} {cells[0]:>40s}   {cells[1]:>40s}")
    print("  (first call: one query right after a reference pass, which streams the mesh through the caches, as a "
          "frame's other work would)")  # fmt: skip
    print(
        f"vs floor: reference {ref_med['dir'] / floor:.2f} / {ref_med['point'] / floor:.2f} x floor (dir / point); "
        f"gaussmap dir {float(np.median(q['gaussmap', 'dir']['t'])) / floor:.3f} x floor"
    )
    print("edges tested per query (steps['edge_test'] / E), median / max over the lights:")
    for name in SCHEMES:
        line = "   ".join(
            f"{k:5s} {_pct(float(np.median(q[name, k]['frac'])))} / {_pct(max(q[name, k]['frac']))}" for k in kinds
        )
        print(f"  {name:9s} {line}   (other edges: {trees[name].order.size - trees[name].n_pairs})")
    exact = {name: sum(sum(q[name, k]["same"]) for k in kinds) for name in SCHEMES}
    print(
        "answers equal the reference (np.sort(ids) == silhouette_edge_ids): "
        + ", ".join(f"{name} {exact[name]}/{len(ls)} lights" for name in SCHEMES)
    )
    det = {}
    for name in SCHEMES:  # the full detector (its own cached default tree), for completeness
        silcount.detect(mesh, ls[0], name)
        per_light = [best_time(lambda L=L, n=name: silcount.detect(mesh, L, n).edge_ids, 3) for L in ls]
        det[name] = float(np.median(per_light))
    print(
        "silcount.detect() per light (cached tree, all 16 lights): "
        + ", ".join(f"{n} {_ms(t)}" for n, t in det.items())
    )

    print(f"\nbuild (best of 3; mesh caches warm), defaults leaf_size={hierarchy.LEAF_SIZE} fanout={hierarchy.FANOUT}:")
    even = {}
    for name in SCHEMES:
        k = OWN_KIND[name]
        tq = float(np.median(q[name, k]["t"]))
        even[name] = _even(build_t[name], ref_med[k], tq)
        print(
            f"  {name:9s} build {build_t[name]:6.3f} s = {build_t[name] / ref_med[k]:6.1f} x one reference {k} query;"
            f" break-even ({k} lights) {even[name].strip()}"
        )
        print(
            f"  {'':9s} tree.nbytes {trees[name].nbytes / 2**20:6.1f} MiB = {trees[name].nbytes / mb:.2f} x mesh;"
            f" build peak (tracemalloc) {peak[name] / 2**20:6.1f} MiB = {peak[name] / mb:.2f} x mesh"
            f" (tree + transient {(peak[name] - trees[name].nbytes) / 2**20:.1f} MiB)"
        )
    print("  break-even = build / (reference query - hierarchy query), medians of the hierarchy's own light kind")
    fresh = fresh_fill_figures(trees["gaussmap"].planes.shape[0])
    print(
        f"  a fresh (n, 4) float32 array the size of the tree's planes ({fresh['mib']:.0f} MiB) filled by a compiled "
        f"loop, best of 3: allocated by numpy {_ms(fresh['numpy']).strip()}, by the compiled runtime "
        f"{_ms(fresh['compiled']).strip()} (the build's first touch of its arrays)"
    )

    sweep = sweep_figures(mesh, kinds, ref_ids, ref_med, mb)
    targets(speedup, build_t, ref_med, trees, peak, mb, exact, len(ls), sweep)


def sweep_figures(mesh, kinds, ref_ids, ref_med, mb) -> dict:
    print(
        f"\nleaf_size x fanout sweep (query: own light kind, {len(kinds['dir'])} lights, best of {SWEEP_REPEAT}, "
        "median; build best of 2; * = default)"
    )
    print(
        f"  {'scheme':9s} {'leaf':>4s} {'fan':>3s} {'query':>10s} {'ref/q':>7s} {'tested/E':>9s} {'max':>8s} "
        f"{'build':>8s} {'build/ref':>9s} {'tree MiB':>8s} {'x mesh':>6s} {'break-even':>10s} exact"
    )
    out = {}
    for name, scheme in SCHEMES.items():
        k = OWN_KIND[name]
        for leaf in SWEEP_LEAF:
            for fanout in SWEEP_FANOUT:
                tree, tb = build_best(mesh, scheme, leaf, fanout, 2)
                got = query_figures(mesh, tree, kinds[k], ref_ids[k], SWEEP_REPEAT)
                tq = float(np.median(got["t"]))
                out[name, leaf, fanout] = {"t": tq, "build": tb, "exact": all(got["same"])}
                mark = "*" if (leaf, fanout) == (hierarchy.LEAF_SIZE, hierarchy.FANOUT) else " "
                print(
                    f" {mark}{name:9s} {leaf:4d} {fanout:3d} {_ms(tq):>10s} {ref_med[k] / tq:6.1f}x "
                    f"{_pct(float(np.median(got['frac'])))} {_pct(float(got['frac'].max()))} {tb:7.3f}s "
                    f"{tb / ref_med[k]:8.1f}x {tree.nbytes / 2**20:8.1f} {tree.nbytes / mb:6.2f} "
                    f"{_even(tb, ref_med[k], tq):>10s} {all(got['same'])}"
                )
                del tree
        best = min((v["t"], lf, fo) for (n, lf, fo), v in out.items() if n == name)
        print(f"  {name}: fastest {k} query at leaf_size={best[1]} fanout={best[2]} ({_ms(best[0]).strip()})")
    return out


def targets(speedup, build_t, ref_med, trees, peak, mb, exact, n_lights, sweep) -> None:
    rows = []
    for name in SCHEMES:
        k = OWN_KIND[name]
        rows.append((f"{name}: reference / {name} query ({k}) >= {TARGET_SPEEDUP[name]:.0f}x",
                     f"{speedup[name, k]:.1f}x", speedup[name, k] >= TARGET_SPEEDUP[name]))  # fmt: skip
    for name in SCHEMES:
        r = build_t[name] / ref_med[OWN_KIND[name]]
        rows.append((f"{name}: build <= {TARGET_BUILD:.0f} x one reference {OWN_KIND[name]} query", f"{r:.1f}x",
                     r <= TARGET_BUILD))  # fmt: skip
    for name in SCHEMES:
        r = trees[name].nbytes / mb
        rows.append((f"{name}: tree.nbytes <= {TARGET_MEMORY:.0f} x mesh memory", f"{r:.2f}x", r <= TARGET_MEMORY))
        r = peak[name] / mb
        rows.append((f"{name}: build peak (tracemalloc) <= {TARGET_MEMORY:.0f} x mesh memory", f"{r:.2f}x",
                     r <= TARGET_MEMORY))  # fmt: skip
    for name in SCHEMES:
        swept = all(v["exact"] for (n, _, _), v in sweep.items() if n == name)
        rows.append((f"{name}: ids == reference (all lights, defaults and sweep)",
                     f"{exact[name]}/{n_lights}, sweep {swept}", exact[name] == n_lights and swept))  # fmt: skip
    print("\ntargets (measured in this run):")
    width = max(len(r[0]) for r in rows)
    for label, value, ok in rows:
        print(f"  {label:{width}s}  {value:>16s}  {'met' if ok else 'NOT met'}")
