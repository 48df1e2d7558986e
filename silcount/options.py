"""The names and defaults the command line offers, in a module that imports nothing.

``silcount --help`` and every subcommand's parser read their choices here, so
that building a parser never imports the code behind the choices (numba's
kernels, scipy, pandas); that code reads the same tuples, so each list has
one home:

* :data:`DETECTORS`: the detectors, in the order tables list them; each is
  the module ``silcount/detectors/<name>.py`` (:mod:`silcount.detectors`
  imports them from this tuple);
* :data:`RENDER_METHODS`, :data:`SHADOW_TESTS`, :data:`VOLUMES`: the mask
  methods of :mod:`silcount.render.methods` and the stencil paper's literal
  steps of :mod:`silcount.render.stencil`;
* :data:`AUDIT_FORMATS`, :data:`DEFAULT_LIGHT_COUNT`, :data:`DEFAULT_SEED`:
  :mod:`silcount.audit`'s layouts and default random lights.
"""

from __future__ import annotations

DETECTORS: tuple[str, ...] = ("reference", "ta", "vnv", "hsd", "eesd", "gaussmap", "cones")
RENDER_METHODS: tuple[str, ...] = ("zpass", "zfail", "planar", "raycast")
SHADOW_TESTS: tuple[str, ...] = ("nonzero", "parity")
VOLUMES: tuple[str, ...] = ("infinite", "truncated", "sides")
AUDIT_FORMATS: tuple[str, ...] = ("text", "md", "json")
DEFAULT_LIGHT_COUNT = 16
DEFAULT_SEED = 0
