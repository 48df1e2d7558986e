"""The names and defaults the command line offers, in a module that imports nothing.

``silcount --help`` and every subcommand's parser read their choices here (detector names are
the registry's, checked after parsing: ``silcount.detectors.registry``), so
that building a parser never imports the code behind the choices (numba's
kernels, scipy, pandas); that code reads the same tuples, so each list has
one home:

* :data:`RENDER_METHODS`, :data:`SHADOW_TESTS`, :data:`VOLUMES`: the mask
  methods of :mod:`silcount.render.methods` and the stencil paper's literal
  steps of :mod:`silcount.render.stencil`; :data:`STAGE_FORMATS`: the files
  ``render --stages`` writes (:mod:`silcount.render.stages`);
* :data:`AUDIT_FORMATS`, :data:`DEFAULT_LIGHT_COUNT`, :data:`DEFAULT_SEED`:
  :mod:`silcount.audit`'s layouts and default random lights;
* :data:`PAPER_HELP`: ``--paper DIR`` of `claims`, `tables`, `figures` and `audit`
  (:mod:`silcount.papers.plugins`).
"""

from __future__ import annotations

RENDER_METHODS: tuple[str, ...] = ("zpass", "zfail", "pertriangle", "planar", "raycast")
STAGE_FORMATS: tuple[str, ...] = (".csv", ".json", ".parquet")
SHADOW_TESTS: tuple[str, ...] = ("nonzero", "parity")
VOLUMES: tuple[str, ...] = ("infinite", "truncated", "sides")
AUDIT_FORMATS: tuple[str, ...] = ("text", "md", "json")
DEFAULT_LIGHT_COUNT = 16
DEFAULT_SEED = 0
PAPER_HELP = (
    "a paper given as a folder of TOML files (docs/papers-as-data.md; repeatable); default: the built-in papers and "
    "those installed under the entry-point group silcount.papers"
)
WORST_CASE_GOALS: tuple[str, ...] = ("exceed", "family", "per-output")
"""``silcount worst-case --goal`` (:mod:`silcount.worstcase.goals`)."""
WORST_CASE_METHODS: tuple[str, ...] = ("evolve", "hypothesis")
"""``silcount worst-case --method`` (:mod:`silcount.worstcase.search`)."""
WORST_CASE_KINDS: tuple[str, ...] = ("add", "mul", "cmp", "read", "write", "total", "any")
"""``silcount worst-case --kind``: an operation kind, the five's total, or any one kind (goal ``exceed``)."""
