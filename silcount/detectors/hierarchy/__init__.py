"""The bounded plane hierarchy that ``gaussmap`` and ``cones`` share, and the two detectors on it.

``tree.py`` (the tree, its records and the proof of its exact test), ``build.py`` (its compiled build),
``walk.py`` (its compiled walk of one light), ``naive.py`` (build and walk on counting arithmetic, the
``naive`` engine), ``query.py`` (the detector glue: the tree cached with the mesh, the ``fast`` query),
``morton.py`` (the Z-order keys), ``prefetch.py`` (the walk's prefetch hint), and the two detectors,
``gaussmap.py`` (Gooch et al., I3D 1999, Sec. 4.1) and ``cones.py`` (Johnson & Cohen, I3D 2001, Sec. 3;
Sander et al., SIGGRAPH 2000, Sec. 3), each a key scheme on the same tree.
"""
