"""``import silcount``'s cost, this tree against a baseline tree (issue 39: "no longer than today").

Each round runs ``python -X importtime -c "import silcount"`` in a fresh process once with this checkout
and once with ``--baseline DIR`` (a checkout of the commit before; e.g. ``git worktree add``) first on
``PYTHONPATH``, alternating which goes first, and reads the cumulative microseconds of ``silcount``'s own
import from ``-X importtime`` (the interpreter's start-up is not in it).  Prints the medians, their ratio
and the machine's load (``os.getloadavg()``) before and after; bytecode is cached by a warm-up round.

    python -m benchmarks.import_time --baseline ../main --rounds 30
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent


def import_us(tree: Path) -> int:
    """Microseconds of ``import silcount`` (cumulative, its own line of ``-X importtime``) from ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    got = subprocess.run(
        [sys.executable, "-X", "importtime", "-c", "import silcount"], capture_output=True, text=True, env=env
    )
    got.check_returncode()
    for line in got.stderr.splitlines():
        parts = [p.strip() for p in line.split("|")]
        if len(parts) == 3 and parts[2] == "silcount":
            return int(parts[1])
    raise RuntimeError(f"no 'silcount' line in -X importtime's output from {tree}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", type=Path, required=True, help="a checkout of the baseline commit")
    parser.add_argument("--rounds", type=int, default=30)
    args = parser.parse_args()
    load = os.getloadavg()
    trees = {"this tree": HERE, "baseline": args.baseline.resolve()}
    for tree in trees.values():
        import_us(tree)  # warm-up: bytecode written
    times: dict[str, list[int]] = {name: [] for name in trees}
    for i in range(args.rounds):
        for name in list(trees)[:: 1 if i % 2 else -1]:
            times[name].append(import_us(trees[name]))
    med = {name: statistics.median(t) for name, t in times.items()}
    print(f"load before {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; after {os.getloadavg()[0]:.2f}")
    for name, t in times.items():
        print(f"{name}: median {med[name] / 1000:.2f} ms over {len(t)} (min {min(t) / 1000:.2f} ms)")
    print(f"ratio this tree / baseline: {med['this tree'] / med['baseline']:.3f}")


if __name__ == "__main__":
    main()
