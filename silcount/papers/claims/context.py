"""What the rules may measure with: growth exponents (any source, witness families too), stencil steps, real meshes."""

from __future__ import annotations

from dataclasses import dataclass

from silcount.papers.growth import Exponent


@dataclass(frozen=True)
class Evidence:
    """Measured inputs of the claims.

    ``exponents``: growth exponents with confidence intervals, from any number of sources (the icosphere
    sweep of :mod:`silcount.papers.growth` by default; the corpus sweep plugs in here); ``stencil``: the
    render experiments' mismatch of each literal stencil step against ray casting, or None when not
    measured; ``real``: whether the shared real meshes (``$SILCOUNT_MESH_DIR``) are measured too;
    ``worst``: growth exponents on witness families, inputs built to be expensive
    (:mod:`silcount.papers.witness`): lower bounds on the worst case, which judges an O() claim.
    """

    exponents: tuple[Exponent, ...]
    stencil: dict[str, dict] | None = None
    real: bool = False
    worst: tuple[Exponent, ...] = ()
