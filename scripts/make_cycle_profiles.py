"""Write silcount/models/cycles/<cpu>-llvm-mca.toml from llvm-mca's scheduling models (issue 14).

For each CPU (default: skylake, znver3 and LLVM's own name for this machine,
the "Host CPU" line of ``llvm-mca --version``), ask llvm-mca for the latency
and reciprocal throughput of the instruction behind each operation kind
(:data:`silcount.calibrate.mca.INSTRUCTIONS`) and write one TOML file:
``llvm_mcpu``, ``llvm_version``, and ``[latency]`` / ``[rthroughput]`` tables
of ``kind = {value = ..., instruction = "..."}``.

    python scripts/make_cycle_profiles.py [--out silcount/models/cycles] [CPU ...]

Prints one line per CPU with its numbers.  Needs llvm-mca (Debian: ``apt-get install llvm``).
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

from silcount.atomic import write_text
from silcount.calibrate import mca

DEFAULT_CPUS = ("skylake", "znver3")
DESCRIPTION = {
    "skylake": "Intel Skylake (client)",
    "znver3": "AMD Zen 3",
    "znver2": "AMD Zen 2",
    "znver1": "AMD Zen 1",
}


def host_cpu(exe: str) -> str | None:
    """LLVM's name for this machine's CPU (``Host CPU:`` in ``llvm-mca --version``), or None."""
    out = subprocess.run([exe, "--version"], capture_output=True, text=True, check=True).stdout
    match = re.search(r"Host CPU:\s*(\S+)", out)
    return match.group(1) if match and match.group(1) != "generic" else None


def _fmt(value: float) -> str:
    return str(int(value)) if float(value).is_integer() else repr(value)


def render(cpu: str, llvm_version: str, tables: dict[str, dict[str, tuple[float, str]]]) -> str:
    lines = [
        f"# {DESCRIPTION.get(cpu, cpu)}: scalar SSE2 double precision, in core cycles, from LLVM's scheduling model.",
        "# Written by scripts/make_cycle_profiles.py; each value is the Latency or RThroughput column of",
        f"#   echo '<instruction>' | llvm-mca -mtriple={mca.TRIPLE} -mcpu={cpu}",
        "# (tests/test_cycles_mca.py reruns every entry). add also stands for subsd (checked equal).",
        "# write latency is llvm-mca's store latency (1), not the store-to-load forwarding delay.",
        f'name = "{cpu}"',
        f'description = "{DESCRIPTION.get(cpu, cpu)}, scalar SSE2 double precision (llvm-mca)"',
        f'llvm_mcpu = "{cpu}"',
        f'llvm_version = "{llvm_version}"',
        f'mtriple = "{mca.TRIPLE}"',
    ]
    for table in ("latency", "rthroughput"):
        lines += ["", f"[{table}]"]
        for kind, (value, ins) in tables[table].items():
            lines.append(f'{kind} = {{ value = {_fmt(value)}, instruction = "{ins}" }}')
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cpus", nargs="*", help="LLVM -mcpu names (default: skylake, znver3 and this machine's)")
    default_out = Path(__file__).resolve().parent.parent / "silcount" / "models" / "cycles"
    parser.add_argument("--out", type=Path, default=default_out)
    args = parser.parse_args(argv)
    exe = mca.executable()
    if exe is None:
        print("llvm-mca not found on the PATH (Debian: apt-get install llvm)", file=sys.stderr)
        return 2
    cpus = list(args.cpus) or list(DEFAULT_CPUS)
    host = host_cpu(exe)
    if not args.cpus and host and host not in cpus:
        cpus.append(host)
    llvm_version = mca.version(exe)
    print(f"llvm-mca {llvm_version} ({exe}); host CPU: {host}")
    for cpu in cpus:
        tables = mca.profile_tables(exe, cpu)
        path = write_text(args.out / f"{cpu}-llvm-mca.toml", render(cpu, llvm_version, tables))
        for table in ("latency", "rthroughput"):
            print(f"{cpu:8s} {table:11s} " + "  ".join(f"{k}={_fmt(v)}" for k, (v, _) in tables[table].items()))
        print(f"  wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
