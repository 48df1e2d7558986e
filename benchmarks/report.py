"""Time `silcount report` on this tree and on a baseline checkout, in one run; check the outputs are byte-identical.

    python -m benchmarks.report --baseline-tree DIR [--runs 1]

Each tree runs ``python -m silcount.cli.main report --out TMP`` in a fresh
process (``PYTHONPATH`` set to the tree, its own numba cache directory) after
one untimed warm-up run that fills that cache, so the timed runs measure the
report, not numba's first compilation.  Printed: wall time and the sum of the
children's CPU time of each, their ratio, and whether every file under the
two output directories (and the committed ``reports/`` of this tree) has the
same bytes.  Timings on a shared machine are noisy: read the ratio.
"""

from __future__ import annotations

import argparse
import filecmp
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.common import ROOT, load_line


def run_report(tree: Path, out: Path, cache: str) -> tuple[float, float]:
    env = dict(os.environ, PYTHONPATH=str(tree), NUMBA_CACHE_DIR=cache)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run(
        [sys.executable, "-m", "silcount.cli.main", "report", "--out", str(out)],
        env=env,
        cwd=tree,
        check=True,
        stdout=subprocess.DEVNULL,
    )
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def differing(a: Path, b: Path) -> list[str]:
    """Relative paths present in only one tree or with different bytes."""
    names_a = {p.relative_to(a) for p in a.rglob("*") if p.is_file()}
    names_b = {p.relative_to(b) for p in b.rglob("*") if p.is_file()}
    out = sorted(str(p) for p in names_a ^ names_b)
    out += sorted(str(p) for p in names_a & names_b if not filecmp.cmp(a / p, b / p, shallow=False))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline-tree", type=Path, required=True, help="a checkout to compare with")
    ap.add_argument("--runs", type=int, default=1, help="timed runs per tree (the best is printed)")
    args = ap.parse_args(argv)
    print(f"at start: {load_line()}")
    trees = {"baseline": args.baseline_tree.resolve(), "this tree": ROOT}
    with tempfile.TemporaryDirectory() as tmp:
        figures = {}
        for label, tree in trees.items():
            cache = str(Path(tmp) / f"numba-{label.replace(' ', '-')}")
            out = Path(tmp) / label.replace(" ", "-")
            run_report(tree, out, cache)  # warm-up: numba's cache
            figures[label] = min((run_report(tree, out, cache) for _ in range(args.runs)), key=lambda x: x[0])
            print(f"{label:10s} make report {figures[label][0]:7.1f} s wall, {figures[label][1]:7.1f} s CPU")
        base, mine = figures["baseline"][0], figures["this tree"][0]
        print(f"ratio (baseline / this tree): {base / mine:.2f} x")
        diff = differing(Path(tmp) / "baseline", Path(tmp) / "this-tree")
        print(f"outputs byte-identical between the trees: {not diff}" + (f" (differ: {diff})" if diff else ""))
        diff = differing(ROOT / "reports", Path(tmp) / "this-tree")
        print(f"identical to this tree's committed reports/: {not diff}" + (f" (differ: {diff})" if diff else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
