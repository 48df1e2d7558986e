"""How long ``import silcount`` and ``silcount claims --help`` take here against a baseline checkout.

Usage: ``python -m benchmarks.import_time BASELINE_DIR [--runs N]``.  Each run is a fresh interpreter with
``PYTHONPATH`` set to one tree; the trees alternate run by run so that the machine's load falls on both alike.
Prints the median wall time of each, their ratio and the load average (os.getloadavg()) before and after.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent
CASES = {
    "import silcount": [sys.executable, "-c", "import silcount"],
    "silcount claims --help": [sys.executable, "-m", "silcount.cli.main", "claims", "--help"],
}


def once(tree: Path, argv: list[str]) -> float:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    start = time.perf_counter()
    # run in the tree itself: `python -c` puts its working folder first on sys.path
    subprocess.run(argv, env=env, check=True, capture_output=True, cwd=tree)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("baseline", type=Path)
    parser.add_argument("--runs", type=int, default=15)
    args = parser.parse_args()
    print(f"load before: {os.getloadavg()}")
    for name, argv in CASES.items():
        times: dict[str, list[float]] = {"this": [], "baseline": []}
        for tree in (HERE, args.baseline):  # warm the bytecode caches once
            once(tree, argv)
        for _ in range(args.runs):
            times["this"].append(once(HERE, argv))
            times["baseline"].append(once(args.baseline, argv))
        this, base = statistics.median(times["this"]), statistics.median(times["baseline"])
        print(f"{name}: this {this * 1000:.0f} ms, baseline {base * 1000:.0f} ms, ratio {this / base:.3f}")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
