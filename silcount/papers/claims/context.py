"""What the rules may measure with: growth exponents (any source), the stencil-step evidence, real meshes."""

from __future__ import annotations

from dataclasses import dataclass

from silcount.papers.growth import Exponent


@dataclass(frozen=True)
class Evidence:
    """Measured inputs of the claims.

    ``exponents``: growth exponents with confidence intervals, from any number of sources (the icosphere
    sweep of :mod:`silcount.papers.growth` by default; the corpus sweep plugs in here); ``stencil``: the
    render experiments' mismatch of each literal stencil step against ray casting, or None when not
    measured; ``real``: whether the shared real meshes (``$SILCOUNT_MESH_DIR``) are measured too.
    """

    exponents: tuple[Exponent, ...]
    stencil: dict[str, dict] | None = None
    real: bool = False
