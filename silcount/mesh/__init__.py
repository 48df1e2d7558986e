"""Geometry in: the mesh model, loaders, statistics, built-in shapes, lights, ray casting.

| module       | what it holds                                                        |
|--------------|----------------------------------------------------------------------|
| model.py     | :class:`Mesh`: welded vertices, polygon faces (CSR), the edge table  |
| io.py        | :func:`load_mesh`: OBJ, OFF, PLY, STL, GLB/GLTF, with one-line errors |
| formats/     | the readers, one module per format (``docs/loading.md``)             |
| stats.py     | the audit's mesh statistics and warnings                             |
| shapes.py    | built-in meshes (icospheres, quad cube, torus, ...)                  |
| coplanar.py  | HSD's merge of coplanar neighbours into polygons (HSD 2011 Sec. V)   |
| lights.py    | point and directional lights, the facing value                       |
| raytrace.py  | a uniform-grid ray caster (EESD's intersection test, ground truth)   |

Nothing here imports another silcount subpackage but :mod:`silcount.errors`.
Submodules are imported where they are used (trimesh and scipy load only then).
"""
