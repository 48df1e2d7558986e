"""LLVM's CPU models as cycle profiles: llvm-mca's latency and reciprocal throughput per operation kind.

Each kind the ``true`` cost model counts (:data:`silcount.counting.cycles.TRUE_KINDS`)
is the scalar double-precision SSE2 instruction a compiler emits for it (the
plain kernels are compiled by numba through LLVM, so these are the instructions
they run):

* ``add``: ``addsd`` (``subsd`` is checked to cost the same); ``mul``: ``mulsd``;
* ``cmp``: ``ucomisd`` (a branch on ``a < b`` compiles to ``ucomisd`` + ``jcc``);
* ``div``: ``divsd``; ``sqrt``: ``sqrtsd``;
* ``read``: a ``movsd`` load from memory; ``write``: a ``movsd`` store.

``llvm-mca`` prints, per instruction, the latency and reciprocal throughput of
its scheduling model for ``-mcpu``; :func:`query` runs it on one AT&T line.
``scripts/make_cycle_profiles.py`` writes ``silcount/models/cycles/<cpu>-llvm-mca.toml``
from these answers and ``tests/test_cycles_mca.py`` reruns every entry.
LLVM has no scheduling model for the papers' Pentium IV (``-mcpu=pentium4``:
"unable to find instruction-level scheduling information"), so no profile
of the papers' own machine can come from here.
"""

from __future__ import annotations

import re
import shutil
import subprocess

from silcount.errors import BadArgument

TRIPLE = "x86_64-unknown-linux-gnu"
INSTRUCTIONS: dict[str, str] = {
    "add": "addsd %xmm1, %xmm0",
    "mul": "mulsd %xmm1, %xmm0",
    "cmp": "ucomisd %xmm1, %xmm0",
    "div": "divsd %xmm1, %xmm0",
    "sqrt": "sqrtsd %xmm1, %xmm0",
    "read": "movsd (%rax), %xmm0",
    "write": "movsd %xmm0, (%rax)",
}
"""Kind -> the exact AT&T line given to llvm-mca."""
SAME_AS = {"add": "subsd %xmm1, %xmm0"}
"""Instructions a kind also stands for, which must cost the same as its own."""
_ROW = re.compile(r"^\s*(\d+)\s+(\d+)\s+(\d+\.\d+)\s")


def executable() -> str | None:
    """The llvm-mca on the PATH (``llvm-mca`` or a versioned ``llvm-mca-N``), or None."""
    found = shutil.which("llvm-mca")
    if found:
        return found
    for version in range(30, 9, -1):
        found = shutil.which(f"llvm-mca-{version}")
        if found:
            return found
    return None


def version(exe: str) -> str:
    """llvm-mca's LLVM version, e.g. ``"14.0.6"``."""
    out = subprocess.run([exe, "--version"], capture_output=True, text=True, check=True).stdout
    match = re.search(r"LLVM version (\S+)", out)
    if not match:
        raise BadArgument(f"cannot read the LLVM version from {exe} --version")
    return match.group(1)


def query(exe: str, mcpu: str, instruction: str) -> tuple[float, float]:
    """``(latency, reciprocal throughput)`` in cycles of one AT&T instruction on ``mcpu``."""
    proc = subprocess.run(
        [exe, f"-mtriple={TRIPLE}", f"-mcpu={mcpu}", "-resource-pressure=false"],
        input=instruction + "\n",
        capture_output=True,
        text=True,
    )
    if proc.returncode != 0:
        raise BadArgument(f"llvm-mca -mcpu={mcpu} on {instruction!r}: {proc.stderr.strip().splitlines()[0]}")
    lines = proc.stdout.splitlines()
    header = next(i for i, line in enumerate(lines) if line.rstrip().endswith("Instructions:"))
    match = _ROW.match(lines[header + 1])
    if not match:
        raise BadArgument(f"llvm-mca -mcpu={mcpu}: no instruction-info row for {instruction!r}")
    return float(match.group(2)), float(match.group(3))


def profile_tables(exe: str, mcpu: str) -> dict[str, dict[str, tuple[float, str]]]:
    """``{"latency": {kind: (value, instruction)}, "rthroughput": {...}}`` for one CPU."""
    tables: dict[str, dict[str, tuple[float, str]]] = {"latency": {}, "rthroughput": {}}
    for kind, ins in INSTRUCTIONS.items():
        lat, rtp = query(exe, mcpu, ins)
        if kind in SAME_AS and query(exe, mcpu, SAME_AS[kind]) != (lat, rtp):
            raise BadArgument(f"llvm-mca -mcpu={mcpu}: {SAME_AS[kind]!r} costs differently from {ins!r}")
        tables["latency"][kind] = (lat, ins)
        tables["rthroughput"][kind] = (rtp, ins)
    return tables
