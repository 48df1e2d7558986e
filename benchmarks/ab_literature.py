"""gaussmap's and cones' per-light queries against the reference kernel, in two source trees, interleaved.

    SILCOUNT_MESH_DIR=/path/to/shared/data python -m benchmarks.ab_literature --baseline-tree DIR [--pairs 4]

Each round runs one subprocess per tree (the baseline first), alternating, so
that the machine's drift (10-20 % over minutes on a shared 2-core machine)
falls on both alike.  A subprocess imports ``silcount`` from its tree, builds
the mesh of ``benchmarks.detectors`` (the 1.04 M-face bunny, this checkout's ``benchmarks.common``) and both default
trees, and times, per light (``lights(mesh, 16, seed=11)``: 8 directional,
8 point), the reference kernel (``adjacency.silhouette_edge_ids``) and each
compiled query (``hierarchy_query.query_fast``), the best of 5 calls, three
rounds, keeping each one's smallest; every answer is compared with the
reference's ids.  It prints the medians over the lights.  This script then
prints, per tree, the median and range over the pairs.  No assertion is
made on any time.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from benchmarks.common import ROOT, tree_env

CHILD = r"""
import json, sys
tree = sys.argv[1]
import numpy as np
from benchmarks.common import best_time, build_mesh, lights
import silcount
from silcount.detectors import adjacency, cones, gaussmap, hierarchy_query
assert silcount.__file__.startswith(tree), silcount.__file__
mesh = build_mesh(3)
trees = {m.NAME: hierarchy_query.tree_for(mesh, m.SCHEME) for m in (gaussmap, cones)}
per = {}
for light in lights(mesh, 16, seed=11):
    kind = "dir" if light.is_directional else "point"
    ref = adjacency.silhouette_edge_ids(mesh, light)
    for t in trees.values():
        assert np.array_equal(np.sort(hierarchy_query.query_fast(mesh, t, light)[0]), ref)
    best = {}
    for _ in range(3):
        ref_s = best_time(lambda: adjacency.silhouette_edge_ids(mesh, light), 5)
        best["reference"] = min(best.get("reference", 1.0), ref_s)
        for name, t in trees.items():
            best[name] = min(best.get(name, 1.0), best_time(lambda: hierarchy_query.query_fast(mesh, t, light), 5))
    for name, s in best.items():
        per.setdefault(f"{kind} {name} ms", []).append(s * 1e3)
    for name in trees:
        per.setdefault(f"{kind} reference/{name}", []).append(best["reference"] / best[name])
print(json.dumps({k: float(np.median(v)) for k, v in per.items()}))
"""


def run(tree: Path) -> dict[str, float]:
    cmd = [sys.executable, "-P", "-c", CHILD, str(tree)]  # -P: the working directory's silcount stays unseen
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=tree_env(tree))
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline-tree", type=Path, required=True, help="a checkout of the code to compare against")
    ap.add_argument("--pairs", type=int, default=4, help="rounds of (baseline, this tree); default 4")
    args = ap.parse_args()
    if "SILCOUNT_MESH_DIR" not in os.environ:
        sys.exit("set SILCOUNT_MESH_DIR to the directory holding bunny.ply")
    trees = {"baseline": args.baseline_tree.resolve(), "this tree": ROOT}
    got: dict[str, list[dict[str, float]]] = {name: [] for name in trees}
    for i in range(args.pairs):
        for name, tree in trees.items():
            got[name].append(run(tree))
            print(f"pair {i + 1}, {name}: {got[name][-1]}", flush=True)
    for name, rows in got.items():
        print(f"\n{name} ({trees[name]}), {len(rows)} runs: median [range] of the per-run medians over the lights")
        for key in rows[0]:
            vals = [r[key] for r in rows]
            print(f"  {key:26s} {np.median(vals):6.2f}  [{min(vals):.2f}, {max(vals):.2f}]")


if __name__ == "__main__":
    main()
