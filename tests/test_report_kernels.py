"""The report's numpy and OpenBLAS kernels are pinned (Makefile, docs/evidence.md): the pin must still name
features this numpy can disable, or the report would silently go back to the machine's own kernels."""

from __future__ import annotations

import json
import platform
import re
import subprocess
import sys
from pathlib import Path

import pytest

MAKEFILE = Path(__file__).resolve().parent.parent / "Makefile"


def pinned() -> dict[str, str]:
    """The variables the Makefile exports for ``report``."""
    text = MAKEFILE.read_text(encoding="utf-8")
    return dict(re.findall(r"^report: export (\w+) := (.+)$", text, flags=re.M))


@pytest.mark.skipif(platform.machine() != "x86_64", reason="the pin is for x86-64 only")
def test_the_report_runs_numpy_without_avx512_and_openblas_on_haswell_kernels():
    env = pinned()
    assert set(env) == {"NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE"}
    code = (
        "import numpy; from numpy._core._multiarray_umath import __cpu_features__ as f, __cpu_dispatch__ as d; "
        "import json; print(json.dumps(sorted(k for k in d if f[k])))"
    )
    got = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert got.stderr == ""  # numpy warns of a feature name it cannot disable
    active = json.loads(got.stdout)
    assert not any(k.startswith(("AVX512", "X86_V4")) for k in active), active
