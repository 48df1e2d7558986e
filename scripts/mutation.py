"""Mutation testing (issue 11): mutmut 2 over each module with the tests that judge it, then kill rates.

    make mutation                      # every module below
    make mutation MUTATE=silcount/detectors/ta.py

Each module is mutated with its own fast selection (hand-counted and
engine-equality tests; hypothesis properties deselected), so one mutant costs
one short pytest run instead of the whole suite.  The runner is this script's
``--judge``: mutmut 2 counts a mutant as killed only when the tests exit
with status 1, so a mutant that crashes the interpreter (a segfault in a
compiled kernel fed a wrong index) or breaks collection would count as a
survivor; ``--judge`` maps every non-zero pytest status to 1.  mutmut edits the tree in
place and restores it, so run this in a scratch checkout when you are editing.
Prints, per module, killed / survived / timed out and the survivors' ids
(``.venv/bin/mutmut show ID`` prints one).
"""

from __future__ import annotations

import argparse
import ctypes
import signal
import sqlite3
import subprocess
import sys
from pathlib import Path

COMMON = "tests/test_edge_rules.py"
SELECTION: dict[str, str] = {
    "silcount/counting/arithmetic.py": "tests/test_arithmetic.py",
    "silcount/counting/models.py": "tests/test_models_dir.py tests/test_ta.py tests/test_formulas.py",
    "silcount/counting/cycles.py": "tests/test_cycles.py",
    "silcount/detectors/base.py": f"tests/test_base.py tests/test_vnv.py tests/test_reference.py tests/test_eesd.py "
    f"{COMMON}",
    "silcount/detectors/edge_array.py": f"tests/test_ta.py tests/test_hsd.py {COMMON}",
    "silcount/detectors/adjacency.py": f"tests/test_reference.py tests/test_detect_many.py {COMMON}",
    "silcount/detectors/reference.py": f"tests/test_reference.py tests/test_detect_many.py {COMMON}",
    "silcount/detectors/ta.py": f"tests/test_ta.py {COMMON}",
    "silcount/detectors/vnv.py": f"tests/test_vnv.py {COMMON}",
    "silcount/detectors/hsd.py": f"tests/test_hsd.py tests/test_coplanar_counted.py {COMMON}",
    "silcount/detectors/eesd/detector.py": f"tests/test_eesd.py {COMMON}",
    "silcount/detectors/eesd/counted.py": f"tests/test_eesd.py {COMMON}",
    "silcount/detectors/eesd/onplane.py": "tests/test_onplane.py",
    "silcount/papers/formulas.py": "tests/test_formulas.py tests/test_claims.py tests/test_tables.py",
}
DESELECT = "not torus and not soup and not match_the_committed"


def _die_with_parent() -> None:
    """In the pytest child: be killed when the judge is (Linux ``PR_SET_PDEATHSIG``).

    On a timeout mutmut SIGKILLs the judge; without this its pytest (a mutant
    looping forever) would live on holding mutmut's pty, and mutmut would wait
    on it for ever instead of recording the timeout.
    """
    ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # 1 = PR_SET_PDEATHSIG


def judge(tests: list[str]) -> int:
    """Run the selection; 0 if it passes, 1 for any failure (failed test, crash, collection error)."""
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "-m", "not hypothesis"]
    linux = sys.platform.startswith("linux")
    done = subprocess.run([*cmd, "-k", DESELECT, *tests], check=False, preexec_fn=_die_with_parent if linux else None)
    return 0 if done.returncode == 0 else 1


def run(module: str, tests: str, python: str) -> None:
    runner = f"{python} {Path(__file__).resolve()} --judge {tests}"
    cmd = [str(Path(python).with_name("mutmut")), "run", "--paths-to-mutate", module, "--tests-dir", "tests"]
    subprocess.run([*cmd, "--no-progress", "--runner", runner], check=False)


def summary(cache: Path) -> list[tuple[str, int, int, int, list[int]]]:
    """(module, killed, survived, timeout, survivor ids) from mutmut's cache."""
    con = sqlite3.connect(cache)
    rows = con.execute(
        "SELECT SourceFile.filename, Mutant.status, Mutant.id FROM Mutant "
        "JOIN Line ON Mutant.line = Line.id JOIN SourceFile ON Line.sourcefile = SourceFile.id"
    ).fetchall()
    out: dict[str, list] = {}
    for name, status, ident in rows:
        k, s, t, ids = out.setdefault(name, [0, 0, 0, []])
        survived = status == "bad_survived"  # ok_suspicious: killed, but the tests ran slowly (numba recompiling)
        out[name] = [k + (status in ("ok_killed", "ok_suspicious")), s + survived, t + (status == "bad_timeout"), ids]
        if survived:
            ids.append(ident)
    return [(name, k, s, t, ids) for name, (k, s, t, ids) in sorted(out.items())]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("modules", nargs="*", help="modules to mutate (default: all of SELECTION)")
    ap.add_argument("--summary-only", action="store_true", help="print the kill rates of the last run")
    ap.add_argument("--judge", action="store_true", help=argparse.SUPPRESS)  # the runner mutmut calls
    args = ap.parse_args(argv)
    if args.judge:
        return judge(args.modules)
    modules = args.modules or list(SELECTION)
    unknown = [m for m in modules if m not in SELECTION]
    if unknown:
        print(f"mutation: no test selection for {', '.join(unknown)}", file=sys.stderr)
        return 2
    if not args.summary_only:
        for module in modules:
            run(module, SELECTION[module], sys.executable)
    total_k = total_n = 0
    for name, k, s, t, ids in summary(Path(".mutmut-cache")):
        n = k + s + t
        total_k, total_n = total_k + k, total_n + n
        print(f"{name:40s} killed {k:4d} / {n:4d} ({100 * k / max(n, 1):5.1f} %)  survived {s}  timeout {t}  {ids}")
    print(f"{'all':40s} killed {total_k:4d} / {total_n:4d} ({100 * total_k / max(total_n, 1):5.1f} %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
