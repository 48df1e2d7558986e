"""A silcount detector plug-in: VTK's edge-based silhouette rule (``vtkPolyDataSilhouette``).

Installed beside silcount, it is found through its entry point (``pyproject.toml``)::

    [project.entry-points."silcount.detectors"]
    vtk-edge = "silcount_edge_detector:SPEC"

and then runs in ``silcount audit``, ``silcount corpus`` and ``silcount render --detector vtk-edge`` like
a built-in.  The rule and its two engines are :mod:`.rule`; its ``paper`` cost model is this package's
``vtk-edge.toml`` (an annotation of VTK's loop in the papers' style: VTK prints no costs).  It has no plain
loops: the corpus study's time column stays empty for it, and says so.
"""

from __future__ import annotations

from pathlib import Path

from silcount import DetectorSpec
from silcount.detectors.base import make_silhouette
from silcount.detectors.result import Silhouette
from silcount.mesh.lights import Light
from silcount.mesh.model import Mesh
from silcount_edge_detector.rule import fast, naive

NAME = "vtk-edge"
PAPER_MODEL = str(Path(__file__).with_name("vtk-edge.toml"))


def detect(mesh: Mesh, light: Light, variant: str = "intended", engine: str = "fast") -> Silhouette:
    """VTK's silhouette of ``mesh`` for ``light``: its steps and both tallies.  One variant (``variant`` is
    accepted for silcount's uniform call and ignored)."""
    run = naive(mesh, light) if engine == "naive" else fast(mesh, light)
    return make_silhouette(mesh, light, NAME, variant, engine, run, PAPER_MODEL)


SPEC = DetectorSpec(
    name=NAME,
    label="VTK edge rule",
    detect=detect,
    role="yardstick",
    paper_model=PAPER_MODEL,
    variants=("intended",),
    engines=("fast", "naive"),
    visited_step="edge_test",
    style=("#8c564b", "D"),
)

__all__ = ["SPEC", "detect"]
