"""Pixel evidence for the stencil paper's literal steps, for the claims' ``measured`` fields (issue 10, Sec. 5).

Each literal step is rendered on the built-in scenes (:mod:`.builtin`, generated in code, so this runs
without ``../shared``) at 256 x 256 and compared with ray casting (:mod:`.raycast`, the ground truth),
as :func:`silcount.render.masks.compare_masks` does: mismatched pixels over covered pixels, and the
*far* mismatches (more than one pixel from an edge of either mask: real disagreements, not edge noise).

* ``shadow_test_parity``: the printed final test ``If (~Stencil % 2)``, shadow where the z-fail stencil
  is odd (:func:`.stencil.shadow_from_stencil`), against the text's "not zero means shadow".
* ``volume_truncated``: z-pass with each side quad stopped at the receiver plane by the "new pixel"
  formula (Sec. 5, :mod:`.volumes`), against the infinite volume.
* ``zfail_uncapped``: z-fail on the volume's sides alone (the EESD paper's "like Z-pass algorithm except step
  5 and 6", Sec. 4: its step 4 gives the silhouette's quads and nothing closes them), against the capped
  volume of Everitt & Kilgard.
* ``planar_literal``: the printed shadow matrix with ``E = D - N.L`` (Sec. 4, :mod:`.planar`), on the
  floor pixels only, against the corrected matrix.

Everything is deterministic (no sampling, fixed scenes); two scenes, about a second each.
"""

from __future__ import annotations

import numpy as np

from silcount.render.builtin import BUILTIN, builtin_scene
from silcount.render.camera import Camera
from silcount.render.masks import Comparison, compare_masks
from silcount.render.planar import planar_mask
from silcount.render.raycast import raycast
from silcount.render.receiver import floor_plane
from silcount.render.stencil import depth_pass, render_stencil, shadow_from_stencil

RESOLUTION = 256


def _entry(c: Comparison) -> dict:
    return {"mismatch_fraction": round(c.fraction, 6), "far_mismatches": int(c.far)}


def _summary(step: str, literal: dict[str, Comparison], baseline: dict[str, Comparison], base_name: str) -> str:
    parts = []
    for name in literal:
        a, b = literal[name], baseline[name]
        parts.append(
            f"{name}: {a.fraction:.3%} of {a.covered} px mismatched ({a.mismatched} px, {a.far} far) vs "
            f"{base_name} {b.fraction:.3%} ({b.mismatched} px, {b.far} far)"
        )
    return f"{step} against ray casting at {RESOLUTION}x{RESOLUTION}: " + "; ".join(parts)


def stencil_step_evidence() -> dict[str, dict]:
    """Deterministic mismatch of each literal stencil step against ray casting.
    Keys: "shadow_test_parity", "volume_truncated", "zfail_uncapped", "planar_literal" (E = D - N.L, already in
    render/planar.py).
    Each value: {"scenes": {scene_name: {"mismatch_fraction": float, "far_mismatches": int}}, "summary": str}."""
    lit: dict[str, dict[str, Comparison]] = {"parity": {}, "truncated": {}, "uncapped": {}, "planar": {}}
    base: dict[str, dict[str, Comparison]] = {"parity": {}, "truncated": {}, "planar": {}}  # parity's: capped z-fail
    for name in BUILTIN:
        scene = builtin_scene(name, RESOLUTION)
        truth = raycast(scene)
        cov = truth.coverage
        sd = depth_pass(scene, Camera.of(scene))
        zfail = render_stencil(scene, "zfail", depth=sd)
        base["parity"][name] = compare_masks(zfail.mask, truth.mask, cov)
        parity = sd.coverage & shadow_from_stencil(zfail.stencil, "parity")
        lit["parity"][name] = compare_masks(parity, truth.mask, cov)
        base["truncated"][name] = compare_masks(render_stencil(scene, "zpass", depth=sd).mask, truth.mask, cov)
        trunc = render_stencil(scene, "zpass", depth=sd, volume="truncated")
        lit["truncated"][name] = compare_masks(trunc.mask, truth.mask, cov)
        sides = render_stencil(scene, "zfail", depth=sd, volume="sides")
        lit["uncapped"][name] = compare_masks(sides.mask, truth.mask, cov)
        k, _, _ = floor_plane(scene)
        floor = cov & (scene.triangle_object[np.maximum(truth.tri_id, 0)] == k)
        for variant, into in (("literal", lit), ("intended", base)):
            into["planar"][name] = compare_masks(planar_mask(scene, variant, depth=sd)[0], truth.mask, floor)
    return {
        "shadow_test_parity": {
            "scenes": {n: _entry(c) for n, c in lit["parity"].items()},
            "summary": _summary(
                "z-fail with the printed If (~Stencil % 2) (shadow where the stencil is odd)",
                lit["parity"],
                base["parity"],
                "nonzero",
            ),
        },
        "volume_truncated": {
            "scenes": {n: _entry(c) for n, c in lit["truncated"].items()},
            "summary": _summary(
                "z-pass with volumes truncated at the floor plane by the new-pixel step",
                lit["truncated"],
                base["truncated"],
                "infinite volumes",
            ),
        },
        "zfail_uncapped": {
            "scenes": {n: _entry(c) for n, c in lit["uncapped"].items()},
            "summary": _summary(
                "z-fail on the volumes' sides alone (no caps)",
                lit["uncapped"],
                base["parity"],
                "capped volumes",
            ),
        },
        "planar_literal": {
            "scenes": {n: _entry(c) for n, c in lit["planar"].items()},
            "summary": _summary(
                "the printed shadow matrix (E = D - N.L), floor pixels only",
                lit["planar"],
                base["planar"],
                "corrected matrix",
            ),
        },
    }


__all__ = ["RESOLUTION", "stencil_step_evidence"]
