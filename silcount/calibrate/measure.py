"""A cycle profile measured on this machine: nanoseconds per operation kind (``silcount calibrate --measure``).

Each kind is timed by a numba kernel (:mod:`silcount.calibrate.microbench`),
best of ``repeats`` runs of ``n`` loop steps, and divided by the operations
per step:

* latency: one dependent chain (``x = x + c``, ``x = x * c``, ``x = c / x``;
  ``sqrt`` and ``cmp`` ride on an add, ``x = sqrt(x) + c`` and
  ``x = x + (c if x < limit else 2c)``, and the add chain's time is
  subtracted; ``write`` is a store and its forwarded reload on an add chain,
  the add subtracted);
* throughput: eight independent chains of the same, time divided by eight
  (the same subtractions, per stream);
* ``read``: chasing a random cyclic permutation of indices, in an L1-sized
  array (512 indices, 4 KiB) and, as ``read_dram``, in a DRAM-sized one
  (``dram_bytes``, default 256 MiB, past any last-level cache).

A difference that comes out below zero (timer noise on a loaded machine) is
kept as measured: it is data, not a weight to trust; the profile file records
every raw timing.  The file is named after ``/proc/cpuinfo``'s model name
(``measured-<model-name>.toml``, e.g. ``measured-amd-epyc.toml``).
"""

from __future__ import annotations

import platform
import re
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from silcount.atomic import make_folder, write_text
from silcount.calibrate import microbench as K

L1_INDICES = 512
DRAM_BYTES = 256 * 2**20


def cpu_model_name() -> str:
    """``model name`` of ``/proc/cpuinfo`` (``platform.processor()`` elsewhere)."""
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        text = ""
    match = re.search(r"^model name\s*:\s*(.+)$", text, re.M)
    return (match.group(1).strip() if match else platform.processor()) or "unknown-cpu"


def slug(name: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-") or "unknown-cpu"


def _cycle(size: int, seed: int = 0) -> np.ndarray:
    """A random single-cycle permutation: following ``nxt`` from 0 visits every index once (Sattolo)."""
    order = np.random.default_rng(seed).permutation(size)
    nxt = np.empty(size, dtype=np.int64)
    nxt[order] = np.roll(order, -1)
    return nxt


def _best(fn: Callable, args: tuple, repeats: int) -> float:
    fn(*args)  # compile and warm up
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn(*args)
        best = min(best, time.perf_counter() - t0)
    return float(best)


def raw_timings(n: int, repeats: int = 5, dram_bytes: int = DRAM_BYTES) -> dict[str, float]:
    """Seconds per loop step of every kernel (best of ``repeats``)."""
    l1 = _cycle(L1_INDICES)
    dram = _cycle(max(dram_bytes // 8, L1_INDICES))
    starts_l1 = np.arange(K.STREAMS, dtype=np.int64) * (L1_INDICES // K.STREAMS)
    starts_dram = np.arange(K.STREAMS, dtype=np.int64) * (dram.size // K.STREAMS)
    buf, slot = np.zeros(L1_INDICES), np.array([3, 3], dtype=np.int64)
    n_dram = max(n // 20, 1)
    calls: dict[str, tuple[Callable, tuple, int]] = {
        "lat_add": (K.lat_add, (n, 1.0, 1e-9), n),
        "lat_mul": (K.lat_mul, (n, 1.0, 1.0000001), n),
        "lat_div": (K.lat_div, (n, 1.5, 2.0), n),
        "lat_sqrt_add": (K.lat_sqrt_add, (n, 2.0, 1.0), n),
        "lat_cmp_add": (K.lat_cmp_add, (n, 1.0, 1e-9), n),
        "lat_read": (K.lat_read, (n, l1), n),
        "lat_read_dram": (K.lat_read, (n_dram, dram), n_dram),
        "lat_write_add": (K.lat_write_add, (n, 1.0, 1e-9, buf, slot), n),
        "tp_add": (K.tp_add, (n, 1.0, 1e-9), n),
        "tp_mul": (K.tp_mul, (n, 1.0, 1.0000001), n),
        "tp_div": (K.tp_div, (n, 1.5, 2.0), n),
        "tp_sqrt_add": (K.tp_sqrt_add, (n, 2.0, 1.0), n),
        "tp_cmp_add": (K.tp_cmp_add, (n, 1.0, 1e-9), n),
        "tp_read": (K.tp_read, (n, l1, starts_l1), n),
        "tp_read_dram": (K.tp_read, (n_dram, dram, starts_dram), n_dram),
        "tp_write": (K.tp_write, (n, 1.0, buf), n),
    }
    return {name: _best(fn, args, repeats) / steps for name, (fn, args, steps) in calls.items()}


METHOD = {
    "add": "chain x = x + c",
    "mul": "chain x = x * c",
    "div": "chain x = c / x",
    "sqrt": "chain x = sqrt(x) + c, minus the add chain",
    "cmp": "chain x = x + (c if x < limit else 2c), minus the add chain",
    "read": "random pointer chase, 4 KiB (L1)",
    "read_dram": "random pointer chase, DRAM-sized array",
    "write": "store x + c, reload through a run-time index, minus the add chain",
}
METHOD_TP = {
    "add": "8 independent chains x = x + c, time / 8",
    "mul": "8 independent chains x = x * c, time / 8",
    "div": "8 independent chains x = c / x, time / 8",
    "sqrt": "8 independent chains x = sqrt(x) + c, minus the add chains, time / 8",
    "cmp": "8 independent chains x = x + (c if x < limit else 2c), minus the add chains, time / 8",
    "read": "8 interleaved random pointer chases, 4 KiB (L1), time / 8",
    "read_dram": "8 interleaved random pointer chases, DRAM-sized array, time / 8",
    "write": "8 stores per step into a 4 KiB buffer, time / 8",
}


def profile_values(raw: dict[str, float]) -> dict[str, dict[str, float]]:
    """Nanoseconds per operation, ``{"latency": {kind: ns}, "rthroughput": {kind: ns}}``."""
    s = K.STREAMS
    ns = {k: v * 1e9 for k, v in raw.items()}
    lat = {
        "add": ns["lat_add"],
        "mul": ns["lat_mul"],
        "div": ns["lat_div"],
        "sqrt": ns["lat_sqrt_add"] - ns["lat_add"],
        "cmp": ns["lat_cmp_add"] - ns["lat_add"],
        "read": ns["lat_read"],
        "read_dram": ns["lat_read_dram"],
        "write": ns["lat_write_add"] - ns["lat_add"],
    }
    tp = {
        "add": ns["tp_add"] / s,
        "mul": ns["tp_mul"] / s,
        "div": ns["tp_div"] / s,
        "sqrt": (ns["tp_sqrt_add"] - ns["tp_add"]) / s,
        "cmp": (ns["tp_cmp_add"] - ns["tp_add"]) / s,
        "read": ns["tp_read"] / s,
        "read_dram": ns["tp_read_dram"] / s,
        "write": ns["tp_write"] / s,
    }
    return {"latency": lat, "rthroughput": tp}


def render_toml(model: str, raw: dict[str, float], n: int, repeats: int, dram_bytes: int) -> str:
    values = profile_values(raw)
    lines = [
        "# Measured on this machine by `silcount calibrate --measure` (silcount/calibrate/measure.py):",
        f"# nanoseconds per operation, best of {repeats} runs of {n} loop steps; DRAM array {dram_bytes} bytes.",
        "# Taken on whatever load the machine had: rerun on a quiet machine before citing a digit.",
        f'name = "{slug(model)}"',
        f'cpu_model = "{model}"',
        'unit = "ns"',
        "",
        "[raw_seconds_per_step]",
        *(f"{k} = {v!r}" for k, v in raw.items()),
    ]
    for table, method in (("latency", METHOD), ("rthroughput", METHOD_TP)):
        lines += ["", f"[{table}]"]
        for kind, value in values[table].items():
            lines.append(f'{kind} = {{ value = {value:.4f}, method = "{method[kind]}" }}')
    return "\n".join(lines) + "\n"


def measure(out_dir: Path, n: int = 2_000_000, repeats: int = 5, dram_bytes: int = DRAM_BYTES) -> Path:
    """Run the micro-benchmarks and write ``out_dir/measured-<cpu model>.toml``; returns its path."""
    model = cpu_model_name()
    raw = raw_timings(n, repeats, dram_bytes)
    make_folder(out_dir)
    return write_text(out_dir / f"measured-{slug(model)}.toml", render_toml(model, raw, n, repeats, dram_bytes))
