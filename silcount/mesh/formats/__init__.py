"""The mesh file readers, one module per format; :data:`silcount.mesh.io.READERS` maps extensions to them.

| module     | format                           | why silcount reads it itself                               |
|------------|----------------------------------|------------------------------------------------------------|
| obj.py     | Wavefront OBJ                    | trimesh triangulates polygons and splits vertices by UV    |
| off.py     | Geomview OFF (all header forms)  | trimesh triangulates polygons, reads plain OFF only        |
| ply.py     | Stanford PLY, ASCII and binary   | trimesh triangulates polygons, reads no tristrips          |
| ply_lines.py | ASCII PLY read one record a line, when lines carry values the header does not declare     |
| stl.py     | STL, ASCII and binary            | to tell a truncated binary file from an ASCII one          |
| gltf.py    | glTF 2.0, GLB                    | (read by trimesh: indexed triangles, kept as they are)     |
| common.py  | :class:`Parsed`, the bad-face rules shared by all readers                                     |

See ``docs/loading.md`` for what each reads, what it refuses on purpose, and the diagnostics.
"""
