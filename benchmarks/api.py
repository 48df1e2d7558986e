"""The hierarchies against the reference through the public API, the kernels alone beside them (issue 42).

    SILCOUNT_MESH_DIR=/path/to/shared/data python -m benchmarks.api [--rounds 3] [--lights 8]

Target (issue 42, "Through the public API"): on the 1.04 M-face bunny (:func:`benchmarks.common.build_mesh`,
3 rounds), best of 5 calls, ``silcount.detect(mesh, light, "gaussmap")`` at least 10x faster than
``silcount.detect(mesh, light, "reference")`` per directional light, and ``"cones"`` at least 5x per point
light.  For each kind of light, over ``--lights`` random lights (:func:`benchmarks.common.lights`), the
median over lights of each light's best of 5 calls, made in turn round the lights (:func:`round_robin`):

* through the API: ``silcount.detect(...).edge_ids`` (the rest of the result is lazy);
* the kernels alone: the reference's :func:`silcount.detectors.adjacency.silhouette_edge_ids` and the
  hierarchy's :func:`silcount.detectors.hierarchy.query.query_fast` (its compiled walk on the cached tree);
* per light through ``detect_many`` (all the lights of that kind in one call, over their number).

Printed with the load average; the ratios are taken within each round, and every round is printed.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import silcount
from benchmarks.common import build_mesh, lights, load_line

REPEAT = 5
PAIRS = {"directional": ("gaussmap", 10.0), "point": ("cones", 5.0)}


def round_robin(fn, items: list, repeat: int) -> list[float]:
    """Each item's best of ``repeat`` calls ``fn(item)``, the calls going round the items, so that no item is
    asked twice in a row: the reference keeps the last light's facing flags with the mesh and ``detect_many``
    the last lights' results (``silcount.detectors.adjacency``), which a repeated call would only read back."""
    best = [float("inf")] * len(items)
    for _ in range(repeat):
        for i, x in enumerate(items):
            t = time.perf_counter()
            fn(x)
            best[i] = min(best[i], time.perf_counter() - t)
    return best


def figures(mesh: silcount.Mesh, ls: list, name: str) -> dict[str, float]:
    """Median over ``ls`` of each light's best of ``REPEAT`` calls: API and kernel, reference and ``name``;
    and ``detect_many`` of all of ``ls`` per light (the lights in turn forwards and backwards)."""
    from silcount.detectors import adjacency, detect_many
    from silcount.detectors.hierarchy import cones, gaussmap
    from silcount.detectors.hierarchy import query as hq

    tree = hq.tree_for(mesh, {"gaussmap": gaussmap.SCHEME, "cones": cones.SCHEME}[name])

    def med(fn) -> float:
        return float(np.median(round_robin(fn, ls, REPEAT)))

    def many(n: str) -> float:
        return min(round_robin(lambda group: detect_many(mesh, group, n), [ls, ls[::-1]], REPEAT)) / len(ls)

    return {
        "reference api": med(lambda L: silcount.detect(mesh, L, "reference").edge_ids),
        f"{name} api": med(lambda L: silcount.detect(mesh, L, name).edge_ids),
        "reference kernel": med(lambda L: adjacency.silhouette_edge_ids(mesh, L)),
        f"{name} kernel": med(lambda L: hq.query_fast(mesh, tree, L)),
        "reference detect_many": many("reference"),
        f"{name} detect_many": many(name),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--lights", type=int, default=8)
    args = ap.parse_args()
    mesh = build_mesh(3)
    every = lights(mesh, 2 * args.lights, seed=7)
    kinds = {"directional": every[1::2], "point": every[0::2]}
    for kind, (name, _) in PAIRS.items():  # warm: kernels loaded, trees built, the tallies' first evaluation
        for n in ("reference", name):
            assert silcount.detect(mesh, kinds[kind][0], n).tally
            silcount.detect_many(mesh, kinds[kind][:2], n)
    print(f"{mesh.n_faces:,} faces; {load_line()}")
    for r in range(args.rounds):
        for kind, (name, target) in PAIRS.items():
            fig = figures(mesh, kinds[kind], name)
            api = fig["reference api"] / fig[f"{name} api"]
            kern = fig["reference kernel"] / fig[f"{name} kernel"]
            many = fig["reference detect_many"] / fig[f"{name} detect_many"]
            cells = "  ".join(f"{k} {v * 1e3:.3f} ms" for k, v in fig.items())
            print(f"round {r + 1} {kind:11s} {cells}")
            mark = "met" if api >= target else "NOT met"
            load = os.getloadavg()[0]
            print(f"  {name} over reference: API {api:5.2f}x ({mark}, target {target:.0f}x)  kernels alone "
                  f"{kern:5.2f}x  detect_many per light {many:5.2f}x  [1-min load {load:.1f}]")  # fmt: skip
    print(load_line())


if __name__ == "__main__":
    main()
