"""A witness on disk: its mesh as OBJ (faces in the order the detector reads them), its light and genome as JSON.

silcount reads meshes but has no mesh writer, so the OBJ is written here: ``v`` lines with every coordinate
as Python's shortest round-trip repr, ``f`` lines with 1-based indices in face order.  Reading it back with
:func:`silcount.mesh.io.load_mesh` gives the same welded mesh (the vertices are already welded and in
coordinate order), so re-running the detector on the files gives the same tally.
"""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path

from silcount.atomic import make_folder, write_text
from silcount.mesh.lights import DirectionalLight, Light, PointLight
from silcount.mesh.model import Mesh
from silcount.worstcase.space import Genome


def obj_text(mesh: Mesh) -> str:
    lines = [f"# {mesh.name}: {mesh.n_vertices} vertices, {mesh.n_faces} faces (silcount worst-case witness)"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in mesh.vertices.tolist()]
    c, s = mesh.corners.tolist(), mesh.face_start.tolist()
    lines += ["f " + " ".join(str(v + 1) for v in c[s[i] : s[i + 1]]) for i in range(mesh.n_faces)]
    return "\n".join(lines) + "\n"


def light_record(light: Light) -> dict:
    if isinstance(light, DirectionalLight):
        return {"kind": "directional", "direction": list(light.direction)}
    return {"kind": "point", "position": list(light.position)}


def light_from(record: dict) -> Light:
    if record["kind"] == "directional":
        return DirectionalLight(record["direction"])
    return PointLight(record["position"])


def save_witness(folder: str | Path, stem: str, mesh: Mesh, light: Light, genome: Genome, extra: dict) -> dict:
    """Write ``<stem>.obj`` and ``<stem>.light.json`` into ``folder``; the paths written, by role."""
    out = make_folder(folder)
    mesh_path = write_text(out / f"{stem}.obj", obj_text(mesh))
    record = {"light": light_record(light), "genome": asdict(genome), "mesh": mesh_path.name, **extra}
    light_path = write_text(out / f"{stem}.light.json", json.dumps(record, indent=2, sort_keys=True) + "\n")
    return {"mesh": str(mesh_path), "light": str(light_path)}


def load_witness(light_json: str | Path) -> tuple[Mesh, Light, dict]:
    """The mesh, light and record of a witness written by :func:`save_witness`."""
    from silcount.mesh.io import load_mesh

    path = Path(light_json)
    record = json.loads(path.read_text())
    return load_mesh(path.parent / record["mesh"]), light_from(record["light"]), record
