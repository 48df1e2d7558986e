"""EESD, Extended Edge Silhouette Detection (Kolivand & Sunar, EESD 2012 Sec. 3.3, 5.3), and the kernels only it uses.

``detector.py`` (the detector: its spec, both engines and variants, the batch of lights), ``rays.py`` (each
edge's outward points and rays, traced against the mesh's faces), ``counted.py`` (the routines on counting
arithmetic: the outward point, the ray, the triangle hit, with their fixed costs) and ``onplane.py`` (the
``literal`` variant's point-on-plane search, the paper's own ``aR_x+bR_y+cR_z+d=0`` test, in a box tree).
"""
