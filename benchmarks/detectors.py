"""Benchmark the detectors on a ~1.1M-face mesh and print the figures (issues 3 and 15, Performance).

    SILCOUNT_MESH_DIR=/path/to/shared/data python -m benchmarks.detectors [--rounds 3] [--timeout 300] \
        [--baseline-tree DIR] [--sections reference,many,audit,fast,naive,literature]

``--baseline-tree``: a checkout of the code to compare with (e.g. ``git
archive 318ab63 | tar -x -C DIR``); the sections ``reference`` and ``audit``
then run once in a child process per tree (``PYTHONPATH`` set to it), in the
same run, and print both figures and their ratio.

1. The mesh: the shared bunny (16,301 faces) with ``--rounds`` rounds of 1-to-4
   midpoint subdivision (``trimesh.remesh.subdivide``; 3 rounds: 1,043,264 faces).
2. ``reference`` per-light query after precompute, next to a plain numpy
   baseline written here and the memory-bandwidth floor: the bytes the query
   must read (each face's ``p0`` and normal, 48 B; each two-sided edge's two
   face ids as int32, 8 B) over the read bandwidth measured in the same run
   (the best of several ``np.sum`` and ``np.max`` over a 256 MiB array).
3. ``fast`` tallies of every available detector and variant on that mesh
   (both cost models come from one run): wall time of the first call (with
   the detector's per-mesh precompute) and of a second light, and the peak
   resident memory of a fresh process that loads the mesh and runs it.
4. ``naive`` vs ``fast`` at ~2,000 faces (a 40 x 25 torus) for every
   available detector and variant.
5. ``many``: ``detect_many`` for 64 lights against 64 ``detect`` calls (per
   light), both against the floor; the results compared field by field.
6. ``audit``: ``run_audit`` with all nine detector variants (``--variant
   both``), one light: wall time, peak RSS, per-variant times, and whether the
   two trees' audits (without times) are identical.
7. ``literature`` (not in the default set): ``gaussmap`` and ``cones`` (their
   compiled queries and builds) against the reference kernel, a leaf size x
   fan-out sweep and a table of targets; in ``benchmarks/literature.py``.

Timings on a shared 2-core machine are noisy: read the ratios, not the digits.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import resource
import subprocess
import sys
import time

import numpy as np

import silcount
from benchmarks.common import best_time, build_mesh, child_command, floor_of, lights, load_line, tree_env
from silcount.detectors import DETECTORS
from silcount.detectors import adjacency as ref_module


def numpy_baseline(mesh: silcount.Mesh):
    """A plain numpy reference query: facing values by einsum, then one comparison per two-sided edge."""
    p0, nrm = mesh.face_p0, mesh.face_normals
    pairs = mesh.side_face[mesh.manifold_sides[mesh.edge_valence == 2]]
    f1, f2 = np.ascontiguousarray(pairs[:, 0]), np.ascontiguousarray(pairs[:, 1])

    def query(light):
        if light.is_directional:
            val = nrm @ np.asarray(light.direction)
        else:
            val = np.einsum("ij,ij->i", np.asarray(light.position) - p0, nrm)
        flags = val > 0
        return np.flatnonzero(flags[f1] != flags[f2])

    return query


def reference_figures(mesh: silcount.Mesh) -> dict:
    """Per-light query times (s) of the reference: kernels only, detect() (edge ids), detect() with everything."""
    ls = lights(mesh, 8)
    t = time.perf_counter()
    ref_module.silhouette_edge_ids(mesh, ls[0])
    first = time.perf_counter() - t
    assert silcount.detect(mesh, ls[0], "reference").tally  # the paper tally's first evaluation (sympy)
    q_core = min(best_time(lambda L=L: ref_module.silhouette_edge_ids(mesh, L), 5) for L in ls)
    q_detect = min(best_time(lambda L=L: silcount.detect(mesh, L, "reference").edge_ids, 5) for L in ls)

    def full(L):
        r = silcount.detect(mesh, L, "reference")
        return r.edges, r.oriented, r.tally

    q_full = min(best_time(lambda L=L: full(L), 3) for L in ls[:4])
    base = numpy_baseline(mesh)
    q_np = min(best_time(lambda L=L: base(L), 3) for L in ls)
    return {"first": first, "core": q_core, "detect": q_detect, "full": q_full, "numpy": q_np}


def section_reference(mesh: silcount.Mesh, baseline: str | None, rounds: int) -> None:
    print("\n== reference per-light query (after precompute) ==")
    need, bw, floor = floor_of(mesh)
    print(f"bytes the query must read: {need / 2**20:.1f} MiB (48 B per face + 8 B per two-sided edge)")
    print(f"read bandwidth (np.sum/np.max over 256 MiB): {bw / 2**30:.2f} GiB/s -> floor {floor * 1e3:.2f} ms")
    trees = {"this tree": None} if baseline is None else {"baseline": baseline, "this tree": None}
    got = {label: child_json("reference", tree, rounds) for label, tree in trees.items()}
    rows = (
        ("core", "kernels (facing + edge ids)"),
        ("detect", "detect(): edge ids (lazy rest)"),
        ("full", "detect() + edges, oriented, tally"),
        ("numpy", "numpy baseline (einsum + pairs)"),
    )
    for key, label in rows:
        line = "  ".join(
            f"{name} {fig[key] * 1e3:7.2f} ms = {fig[key] / floor:5.2f} x floor" for name, fig in got.items()
        )
        if baseline is not None:
            line += f"  ratio {got['baseline'][key] / got['this tree'][key]:5.2f} x"
        print(f"{label:36s} {line}")


def many_figures(mesh: silcount.Mesh, k: int = 64) -> dict:
    from silcount.detectors import detect_many

    ls = lights(mesh, k, seed=3)
    detect_many(mesh, ls[:2])
    single = best_time(lambda: [silcount.detect(mesh, L, "reference").edge_ids for L in ls], 2) / k
    many = best_time(lambda: detect_many(mesh, ls), 3) / k
    a, b = detect_many(mesh, ls), [silcount.detect(mesh, L, "reference") for L in ls]
    same = all(
        np.array_equal(x.edge_ids, y.edge_ids)
        and np.array_equal(x.oriented, y.oriented)
        and x.ties == y.ties
        and x.tally == y.tally
        for x, y in zip(a, b, strict=True)
    )
    return {"single": single, "many": many, "identical": same, "k": k}


def section_many(mesh: silcount.Mesh) -> None:
    print("\n== detect_many: 64 lights in one pass vs 64 detect() calls (reference) ==")
    _, _, floor = floor_of(mesh)
    fig = many_figures(mesh)
    print(f"detect() per light:      {fig['single'] * 1e3:7.2f} ms = {fig['single'] / floor:5.2f} x floor")
    print(f"detect_many per light:   {fig['many'] * 1e3:7.2f} ms = {fig['many'] / floor:5.2f} x floor")
    print(f"speed-up per light {fig['single'] / fig['many']:.2f} x; identical to detect: {fig['identical']}")


def audit_figures(mesh: silcount.Mesh, dump: str | None) -> dict:
    from silcount.audit.compute import AuditSettings, run_audit

    d = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
    L = silcount.PointLight(mesh.centre + 3 * mesh.bounding_radius * d)
    t = time.perf_counter()
    a = run_audit(mesh, [L], AuditSettings(variants=("intended", "literal")), quiet=True)
    wall = time.perf_counter() - t
    if dump:
        with open(dump, "w") as fh:
            json.dump(_without_times(a), fh, sort_keys=True)
    return {
        "wall": wall,
        "rss": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        "times": {k: v["time_s"] for k, v in a["detectors"].items()},
        "edges": {k: v["silhouette_edges"] for k, v in a["detectors"].items()},
    }


def _without_times(x):
    if isinstance(x, dict):
        return {k: _without_times(v) for k, v in x.items() if k != "time_s"}
    if isinstance(x, list):
        return [_without_times(v) for v in x]
    return x


def section_audit(baseline: str | None, rounds: int) -> None:
    print("\n== nine-variant audit (run_audit, --variant both), one light, fresh process per tree ==")
    trees = {"this tree": None} if baseline is None else {"baseline": baseline, "this tree": None}
    dumps = {label: f"/tmp/bench_audit_{os.getpid()}_{i}.json" for i, label in enumerate(trees)}
    got = {label: child_json("audit", tree, rounds, dumps[label]) for label, tree in trees.items()}
    for label, fig in got.items():
        print(f"{label:10s} audit {fig['wall']:7.1f} s  peak RSS {fig['rss'] / 2**30:5.2f} GiB (the process)")
    for key in got["this tree"]["times"]:
        line = "  ".join(f"{label} {fig['times'][key]:8.2f} s" for label, fig in got.items())
        print(f"  {key:14s} {line}  edges {got['this tree']['edges'][key]}")
    if baseline is not None:
        print(f"ratio (baseline / this tree): {got['baseline']['wall'] / got['this tree']['wall']:.2f} x")
        same = open(dumps["baseline"]).read() == open(dumps["this tree"]).read()
        print(f"audits identical (all fields but time_s): {same}")
    for path in dumps.values():
        os.remove(path)


def child_json(section: str, tree: str | None, rounds: int, dump: str | None = None) -> dict:
    """Run one section's figures in a fresh process on ``tree`` (None: this one); its JSON."""
    env = tree_env(tree)
    if tree is not None:
        env["NUMBA_CACHE_DIR"] = env.get("NUMBA_CACHE_DIR", "/tmp/numba") + "-baseline"
    cmd = child_command(__spec__.name, "--child", section, "--rounds", str(rounds)) + (["--dump", dump] if dump else [])
    out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def _child_fast(mesh, name, variant, out):
    try:
        ls = lights(mesh, 2, seed=5)
        t = time.perf_counter()
        r = silcount.detect(mesh, ls[0], name, variant, "fast")
        t1 = time.perf_counter() - t
        t = time.perf_counter()
        silcount.detect(mesh, ls[1], name, variant, "fast")
        t2 = time.perf_counter() - t
        maxrss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
        out.put(("ok", t1, t2, maxrss, r.n_edges, r.tally, r.agreement["disagreement_with_reference"]))
    except Exception as exc:  # reported, not hidden
        out.put(("error", f"{type(exc).__name__}: {exc}"))


def run_child(target, args, timeout: float):
    ctx = mp.get_context("fork")
    q = ctx.Queue()
    p = ctx.Process(target=target, args=(*args, q))
    p.start()
    p.join(timeout)
    if p.is_alive():
        p.terminate()
        p.join()
        return ("timeout",)
    return q.get() if not q.empty() else ("error", f"exit code {p.exitcode}")


def section_fast(mesh: silcount.Mesh, names: list[str], timeout: float) -> None:
    print(f"\n== fast tallies on {mesh.n_faces:,} faces (fresh forked process per run; timeout {timeout:.0f} s) ==")
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    print(
        f"parent peak RSS with the mesh loaded: {rss0 / 2**30:.2f} GiB; each child shares the parent's pages and"
        " reports its own peak RSS (the pages it touched): the total is at most the sum"
    )
    for name in names:
        for variant in ("intended", "literal") if name != "reference" else ("intended",):
            res = run_child(_child_fast, (mesh, name, variant), timeout)
            if res[0] == "ok":
                _, t1, t2, rss, k, tally, dis = res
                print(
                    f"{name:9s} {variant:8s} first {t1:7.2f} s  next light {t2:7.2f} s  peak RSS {rss / 2**30:5.2f} GiB"
                    f"  edges {k:7d}  vs reference {dis}"
                )
                print(f"{'':18s} paper {tally['paper']}")
                print(f"{'':18s} true  {tally['true']}")
            else:
                print(f"{name:9s} {variant:8s} {' '.join(map(str, res))}")


def _child_naive(mesh, name, variant, out):
    try:
        L = silcount.PointLight(mesh.centre + 3 * mesh.bounding_radius * np.array([0.3, 0.5, 0.8]))
        t = time.perf_counter()
        a = silcount.detect(mesh, L, name, variant, "naive")
        tn = time.perf_counter() - t
        silcount.detect(mesh, L, name, variant, "fast")
        tf = best_time(lambda: silcount.detect(mesh, L, name, variant, "fast"), 3)
        b = silcount.detect(mesh, L, name, variant, "fast")
        same = a.tally == b.tally and a.steps == b.steps and np.array_equal(a.edges, b.edges)
        out.put(("ok", tn, tf, same))
    except Exception as exc:
        out.put(("error", f"{type(exc).__name__}: {exc}"))


def _child_fast_only(mesh, name, variant, out):
    L = silcount.PointLight(mesh.centre + 3 * mesh.bounding_radius * np.array([0.3, 0.5, 0.8]))
    silcount.detect(mesh, L, name, variant, "fast")
    out.put(("ok", best_time(lambda: silcount.detect(mesh, L, name, variant, "fast"), 3)))


def section_naive(names: list[str], timeout: float) -> None:
    mesh = silcount.mesh.shapes.torus(1.0, 0.35, 40, 25)
    print(f"\n== naive vs fast on a torus of {mesh.n_faces} faces (timeout {timeout:.0f} s per naive run) ==")
    for name in names:
        for variant in ("intended", "literal") if name != "reference" else ("intended",):
            res = run_child(_child_naive, (mesh, name, variant), timeout)
            if res[0] == "ok":
                _, tn, tf, same = res
                print(
                    f"{name:9s} {variant:8s} naive {tn:8.2f} s  fast {tf * 1e3:8.2f} ms  speed-up {tn / tf:10.0f} x"
                    f"  identical {same}"
                )
            elif res[0] == "timeout":
                tf = run_child(_child_fast_only, (mesh, name, variant), timeout)[1]
                print(
                    f"{name:9s} {variant:8s} naive > {timeout:.0f} s (timed out)  fast {tf * 1e3:8.2f} ms  "
                    f"speed-up > {timeout / tf:8.0f} x"
                )
            else:
                print(f"{name:9s} {variant:8s} {' '.join(map(str, res))}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3, help="1-to-4 subdivision rounds of the bunny (default 3)")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per fast run in a child process")
    ap.add_argument("--naive-timeout", type=float, default=120.0, help="seconds per naive run")
    ap.add_argument(
        "--sections",
        default="reference,many,audit,fast,naive",
        help="comma-separated subset of reference,many,audit,fast,naive,literature",
    )
    ap.add_argument("--baseline-tree", default=None, help="a checkout to compare with (reference and audit sections)")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--dump", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    sections = set(args.sections.split(","))
    if "SILCOUNT_MESH_DIR" not in os.environ:
        print("set SILCOUNT_MESH_DIR to the directory holding bunny.ply", file=sys.stderr)
        return 2
    t = time.perf_counter()
    mesh = build_mesh(args.rounds)
    _ = mesh.edges, mesh.edge_sides, mesh.manifold_sides, mesh.face_normals, mesh.face_p0  # shared by the children
    if args.child == "reference":
        print(json.dumps(reference_figures(mesh)))
        return 0
    if args.child == "audit":
        print(json.dumps(audit_figures(mesh, args.dump)))
        return 0
    print(
        f"mesh: bunny.ply + {args.rounds} rounds of 1-to-4 midpoint subdivision: V={mesh.n_vertices:,} "
        f"F={mesh.n_faces:,} E={mesh.n_edges:,} (built in {time.perf_counter() - t:.1f} s)"
    )
    print(f"at start: {load_line()}")
    names = list(DETECTORS)
    if "reference" in sections:
        section_reference(mesh, args.baseline_tree, args.rounds)
    if "many" in sections:
        section_many(mesh)
    if "audit" in sections:
        section_audit(args.baseline_tree, args.rounds)
    if "fast" in sections:
        section_fast(mesh, names, args.timeout)
    if "naive" in sections:
        section_naive(names, args.naive_timeout)
    if "literature" in sections:
        from benchmarks.literature import section_literature

        section_literature(mesh)
    return 0


if __name__ == "__main__":
    sys.exit(main())
