"""Write the built-in meshes of ``silcount.mesh.shapes`` to ``data/`` as OBJ files.

Run: ``.venv/bin/python scripts/make_data.py``.  The files are committed so
that other tools can read them; ``tests/test_data.py`` checks that they
equal what this script writes.
"""

from __future__ import annotations

import sys
from pathlib import Path

import silcount
from silcount.mesh.shapes import BUILTIN

DATA = Path(__file__).resolve().parent.parent / "data"


def obj_text(mesh: silcount.Mesh) -> str:
    """An OBJ with polygon faces kept as authored and shortest round-trip float repr."""
    lines = [f"# silcount built-in mesh {mesh.name}: V={mesh.n_vertices} F={mesh.n_faces} E={mesh.n_edges}"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in mesh.vertices.tolist()]
    for p in range(mesh.n_faces):
        idx = mesh.corners[mesh.face_start[p] : mesh.face_start[p + 1]] + 1
        lines.append("f " + " ".join(str(i) for i in idx.tolist()))
    return "\n".join(lines) + "\n"


def main() -> int:
    DATA.mkdir(exist_ok=True)
    for name, make in BUILTIN.items():
        path = DATA / f"{name}.obj"
        path.write_text(obj_text(make()))
        print(f"wrote {path.relative_to(DATA.parent)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
