"""Measure a corpus unit's time and peak memory against its faces, per detector, and write the profile JSON.

    python -m scripts.unit_profile [--out silcount/models/measured/unit-profile.json] [--max-faces N]

(from the checkout's root).  Each unit is one file at level 0 with ``silcount corpus``'s default settings
(64 directional lights, seed 0, ``intended``, ``fast``, the plain loops timed on one light), run by
:func:`silcount.study.work.audit_task` in a fresh process on one numba thread (``NUMBA_NUM_THREADS=1``),
after a warm-up unit on an icosphere of 320 faces.  The process reports:

* ``seconds``: the unit's wall time (the file's bytes in hand: loading, checking, every detector, timings);
* ``base_bytes``: its peak resident set (``VmHWM`` of ``/proc/self/status``) after the warm-up, before the unit;
* ``peak_bytes``: its peak resident set after the unit.

(``VmHWM``, not ``getrusage``'s ``ru_maxrss``: a process started by fork and exec keeps its parent's
``ru_maxrss``, here the gigabytes of the meshes this script wrote.)

The files are corpus meshes subdivided to sizes from 1 k to 4 M faces (:mod:`benchmarks.collection`, two
corpus files per size from 1 M) and the 1.04 M-face bunny of :func:`benchmarks.common.build_mesh` (3 rounds).  The
units run: every detector at every size; each detector alone (the reference always runs: it gives the
silhouette sizes and the agreement) at three sizes (up to 1 M); every detector on 8 lights at two sizes (the lights'
share of time and memory).  Units run one at a time, smallest first; the JSON is rewritten after each.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from datetime import UTC, date, datetime
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "silcount" / "models" / "measured" / "unit-profile.json"
ALL_SIZES = (1_000, 4_000, 16_000, 64_000, 256_000, 1_000_000, 4_000_000)
ALONE_SIZES = (4_000, 256_000, 1_000_000)
FEW_LIGHTS_SIZES = (1_000_000, 4_000_000)
FEW_LIGHTS = 8


def peak_rss() -> int:
    """This process's peak resident set in bytes (``VmHWM``)."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError("no VmHWM in /proc/self/status")


def one(path: str, detectors: str, lights: int) -> dict:
    """One unit in this (fresh) process; see the module docstring."""
    from benchmarks.collection import ply_bytes
    from silcount.mesh.shapes import icosphere
    from silcount.study.work import Settings, audit_task

    names = tuple(detectors.split(",")) if detectors else None
    settings = Settings(lights=lights, **({"detectors": names} if names else {}))
    audit_task("warm.ply", ply_bytes(icosphere(2)), 0, settings)
    base = peak_rss()
    data = Path(path).read_bytes()
    t0 = time.perf_counter()
    result = audit_task(Path(path).name, data, 0, settings)
    seconds = time.perf_counter() - t0
    peak = peak_rss()
    return {"seconds": seconds, "base_bytes": base, "peak_bytes": peak, "faces": result["mesh"].get("faces"),
            "error": result["error"]}  # fmt: skip


def plan(folder: Path, max_faces: int) -> list[dict]:
    """The units to measure, smallest first (files written to ``folder``)."""
    from benchmarks import collection
    from benchmarks.common import build_mesh
    from silcount.detectors import names

    files: dict[int, list[Path]] = {}
    for size in (s for s in ALL_SIZES if s <= max_faces):
        ranked = sorted(collection.recipes(), key=lambda r: (abs(__import__("math").log(r.faces / size)), r.file))
        picked: list = []
        for r in ranked:
            if r.file not in {p.file for p in picked}:
                picked.append(r)
            if len(picked) == 2:
                break
        files[size] = [collection.write(r, folder, f"{Path(r.file).stem}-L{r.level}") for r in picked]
    units = []
    for size, paths in files.items():
        units += [{"path": str(p), "detectors": "", "lights": 64} for p in paths[: 2 if size >= 1_000_000 else 1]]
        if size in ALONE_SIZES:
            units += [{"path": str(paths[0]), "detectors": d, "lights": 64} for d in names()]
        if size in FEW_LIGHTS_SIZES:
            units.append({"path": str(paths[0]), "detectors": "", "lights": FEW_LIGHTS})
    if max_faces >= 1_000_000:
        bunny = folder / "bunny_sub3.ply"
        bunny.write_bytes(collection.ply_bytes(build_mesh(3)))
        units.append({"path": str(bunny), "detectors": "", "lights": 64})
    return sorted(units, key=lambda u: (Path(u["path"]).stat().st_size, u["detectors"], u["lights"]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--max-faces", type=int, default=max(ALL_SIZES))
    ap.add_argument("--resume", action="store_true", help="keep the units already in --out, run the others")
    ap.add_argument("--one", nargs=3, metavar=("PATH", "DETECTORS", "LIGHTS"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        print(json.dumps(one(args.one[0], args.one[1], int(args.one[2]))))
        return
    env = {
        **os.environ,
        "NUMBA_NUM_THREADS": "1",
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    }
    profile = {
        "about": {
            "machine": f"{platform.machine()}, {os.cpu_count()} cores",
            "date": date.today().isoformat(),
            "settings": "level 0, 64 directional lights (8 where lights is 8), seed 0, intended, fast, "
            "plain loops timed on one light; one numba thread",
        },
        "units": [],
    }
    done = {}
    if args.resume and args.out.is_file():
        profile["units"] = json.loads(args.out.read_text())["units"]
        done = {(u["file"], u["detectors"], u["lights"]) for u in profile["units"]}
    with tempfile.TemporaryDirectory(prefix="silcount-unit-profile-") as tmp:
        units = plan(Path(tmp), args.max_faces)
        for k, u in enumerate(units):
            if (Path(u["path"]).name, u["detectors"] or "all", u["lights"]) in done:
                continue
            load = os.getloadavg()[0]
            cmd = [
                sys.executable,
                "-P",
                "-m",
                "scripts.unit_profile",
                "--one",
                u["path"],
                u["detectors"],
                str(u["lights"]),
            ]
            out = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=ROOT)
            if out.returncode:
                sys.exit(f"{u}: failed:\n{out.stderr}")
            r = json.loads(out.stdout.strip().splitlines()[-1])
            row = {"file": Path(u["path"]).name, "detectors": u["detectors"] or "all", "lights": u["lights"], **r,
                   "load_1min": load, "at": datetime.now(UTC).strftime("%H:%M:%S")}  # fmt: skip
            profile["units"].append(row)
            args.out.write_text(json.dumps(profile, indent=1) + "\n")
            print(f"[{k + 1}/{len(units)}] {row['file']} {row['faces']:,} faces, {row['detectors']}, "
                  f"{row['lights']} lights: {row['seconds']:.2f} s, peak {row['peak_bytes'] / 2**20:.0f} MiB "
                  f"(base {row['base_bytes'] / 2**20:.0f}), load {load:.2f}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
