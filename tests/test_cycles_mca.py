"""The committed llvm-mca profiles, rerun: every entry is what llvm-mca says for its CPU and instruction."""

from __future__ import annotations

import tomllib

import pytest

from silcount.calibrate import mca
from silcount.counting.cycles import cycles_dir
from silcount.errors import BadArgument

FILES = sorted(cycles_dir().glob("*-llvm-mca.toml"))
EXE = mca.executable()


def _load(path):
    with open(path, "rb") as fh:
        return tomllib.load(fh)


@pytest.mark.skipif(EXE is None, reason="llvm-mca is not on the PATH (Debian: apt-get install llvm)")
@pytest.mark.parametrize("path", FILES, ids=[p.name for p in FILES])
def test_every_entry_is_what_llvm_mca_says(path):
    data = _load(path)
    if mca.version(EXE) != data["llvm_version"]:
        pytest.skip(f"llvm-mca here is {mca.version(EXE)}, the file was written by {data['llvm_version']}")
    for kind in data["latency"]:
        ins = data["latency"][kind]["instruction"]
        assert data["rthroughput"][kind]["instruction"] == ins
        lat, rtp = mca.query(EXE, data["llvm_mcpu"], ins)
        assert (data["latency"][kind]["value"], data["rthroughput"][kind]["value"]) == (lat, rtp), kind


@pytest.mark.skipif(EXE is None, reason="llvm-mca is not on the PATH (Debian: apt-get install llvm)")
def test_subsd_costs_what_addsd_costs_and_pentium4_has_no_model():
    for cpu in ("skylake", "znver3"):
        assert mca.query(EXE, cpu, "subsd %xmm1, %xmm0") == mca.query(EXE, cpu, "addsd %xmm1, %xmm0")
    with pytest.raises(BadArgument, match="scheduling information"):
        mca.query(EXE, "pentium4", "addsd %xmm1, %xmm0")
