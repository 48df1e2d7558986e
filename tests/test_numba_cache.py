"""Every compiled kernel of the hierarchies' build and query can be cached (issue 22: the first run).

numba refuses to cache a kernel that reads a dynamic global (a ctypes pointer such as
``numba.get_num_threads()`` called inside it, or a large global array) and only warns; each new process
then compiles it again.  Here a fresh process with an empty cache builds and queries both hierarchies with
that warning turned into an error.
"""

from __future__ import annotations

import os
import subprocess
import sys

CHILD = """
import warnings
from numba.core.errors import NumbaWarning
warnings.simplefilter("error", NumbaWarning)
import silcount
from silcount.detectors.hierarchy import cones, gaussmap
from silcount.mesh.shapes import builtin_mesh

mesh = builtin_mesh("torus")
for light in (silcount.PointLight((3.0, 2.0, 1.0)), silcount.DirectionalLight((0.2, 1.0, 0.3))):
    for module in (gaussmap, cones):
        module.detect(mesh, light, "intended", "fast")
print("ok")
"""


def test_hierarchy_kernels_are_cached(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    done = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr[-2000:]
    cached = {p.name.split("-")[0] for p in tmp_path.rglob("*.nbi")}
    assert {"build._gather_pairs", "gaussmap._keys", "cones._keys"} <= cached
