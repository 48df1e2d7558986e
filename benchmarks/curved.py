"""The nine-variant audit on a curved mesh with no coplanar runs (issue 44, item 5): a torus or a sphere.

    python -m benchmarks.curved [--shape torus|sphere] [--faces 1000000] [--baseline-tree DIR]

``benchmarks.detectors``' audit section measures the subdivided bunny, where
every 64 consecutive faces lie in one plane: the best case of EESD literal's
plane walk (:mod:`silcount.detectors.eesd.onplane`).  Here the same audit
(``run_audit`` with ``--variant both``, one light, ``benchmarks.detectors.audit_figures``)
runs on a torus (``shapes.torus``, 2 x n x n/2 faces) or an icosphere
(20 x 4^k faces) of about ``--faces`` faces, in a fresh process per tree:
wall time, peak RSS, each variant's time, and the load average before and
after.  ``--baseline-tree``: a checkout to compare with (``git archive main |
tar -x -C DIR``), run in the same session; with it the ratio and whether both
audits (without times) are identical.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess

from benchmarks.common import child_command, load_line, tree_env
from benchmarks.detectors import audit_figures
from silcount.mesh import shapes
from silcount.mesh.model import Mesh


def curved_mesh(shape: str, faces: int) -> Mesh:
    if shape == "torus":
        n = max(4, round(math.sqrt(faces)))  # 2 x n x n/2 = n^2 faces
        return shapes.torus(n_major=n, n_minor=n // 2)
    return shapes.icosphere(max(0, round(math.log(faces / 20, 4))))


def child(shape: str, faces: int, dump: str) -> None:
    mesh = curved_mesh(shape, faces)
    fig = audit_figures(mesh, dump)
    print(json.dumps({**fig, "faces": mesh.n_faces}))


def run_tree(tree: str | None, shape: str, faces: int, dump: str) -> dict:
    env = tree_env(tree)
    if tree is not None:
        env["NUMBA_CACHE_DIR"] = env.get("NUMBA_CACHE_DIR", "/tmp/numba") + "-baseline"
    cmd = child_command(__spec__.name, "--child", "--shape", shape, "--faces", str(faces), "--dump", dump)
    out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shape", choices=("torus", "sphere"), default="torus")
    parser.add_argument("--faces", type=int, default=1_000_000)
    parser.add_argument("--baseline-tree", default=None)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--dump", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.shape, args.faces, args.dump)
        return
    print(f"at start: {load_line()}")
    trees = {"this tree": None} if args.baseline_tree is None else {"baseline": args.baseline_tree, "this tree": None}
    dumps = {label: f"/tmp/bench_curved_{os.getpid()}_{i}.json" for i, label in enumerate(trees)}
    got = {label: run_tree(tree, args.shape, args.faces, dumps[label]) for label, tree in trees.items()}
    faces = got["this tree"]["faces"]
    print(f"== nine-variant audit (--variant both), one light, {args.shape} of {faces:,} faces ==")
    for label, fig in got.items():
        print(f"{label:10s} audit {fig['wall']:7.1f} s  peak RSS {fig['rss'] / 2**30:5.2f} GiB (the process)")
    for key in got["this tree"]["times"]:
        line = "  ".join(f"{label} {fig['times'][key]:8.2f} s" for label, fig in got.items())
        print(f"  {key:14s} {line}  edges {got['this tree']['edges'][key]}")
    if args.baseline_tree is not None:
        print(f"ratio (baseline / this tree): {got['baseline']['wall'] / got['this tree']['wall']:.2f} x")
        same = open(dumps["baseline"]).read() == open(dumps["this tree"]).read()
        print(f"audits identical (all fields but time_s): {same}")
    for path in dumps.values():
        os.remove(path)
    print(f"after: {load_line()} (figures taken under this load)")


if __name__ == "__main__":
    main()
