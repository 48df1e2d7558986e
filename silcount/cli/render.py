"""`silcount render SCENE.json --method zpass|zfail|pertriangle|planar|raycast --out mask.png`: a shadow mask.

Scenes are ``silcount-scene/1`` files (``../shared/scenes/README.md``).  The
stencil methods take the silhouette of ``--detector`` (``--variant`` goes to
the detector); ``planar`` projects the casters onto the floor with the
stencil paper's shadow matrix (``--variant literal`` is the printed matrix,
``intended`` the corrected one).  ``--shadow-test parity`` and ``--volume
truncated`` are the stencil paper's printed steps taken literally (the final
``If (~Stencil % 2)``; the volumes clipped at the receiver by the "new pixel"
formula); ``--volume sides`` is the EESD paper's z-fail, the volume's sides without caps; see
:mod:`silcount.render.stencil` and :mod:`silcount.render.volumes`.  ``pertriangle`` extrudes every
light-facing triangle on its own (no detector).  ``--stages FILE`` writes the frame's stage table
(:mod:`silcount.render.stages`).
Warnings (open casters, the eye inside a shadow volume) go to stderr.

:func:`report` renders the built-in scenes (:mod:`silcount.render.builtin`)
and every shared scene into ``<out>/renders/`` with every method, every
literal step and every installed detector and writes ``summary.json`` and
``summary.md``: each mask against the ray-cast ground truth, each detector's
z-fail mask against the reference detector's.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from silcount.errors import BadArgument, SilcountError
from silcount.options import RENDER_METHODS, SHADOW_TESTS, STAGE_FORMATS, VOLUMES

if TYPE_CHECKING:
    import numpy as np

    from silcount.render.methods import Rendered
    from silcount.render.scene import Scene


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", type=Path, metavar="SCENE.json", help="a silcount-scene/1 file")
    parser.add_argument("--method", choices=RENDER_METHODS, required=True, help="how to compute the mask")
    parser.add_argument(
        "--detector",
        default="reference",
        metavar="NAME",
        help="silhouette detector for zpass/zfail, any registered one (default: reference)",
    )
    parser.add_argument(
        "--variant",
        choices=("intended", "literal"),
        default="intended",
        help="detector variant (zpass/zfail) or shadow matrix (planar); default intended",
    )
    parser.add_argument(
        "--shadow-test",
        choices=SHADOW_TESTS,
        default="nonzero",
        help="zpass/zfail final test: nonzero (the text's 'not zero means shadow', default) or parity "
        "(the printed 'If (~Stencil %% 2)': shadow where the stencil is odd)",
    )
    parser.add_argument(
        "--volume",
        choices=VOLUMES,
        default="infinite",
        help="zpass/zfail volumes: infinite (default), truncated at the floor plane by the paper's 'new pixel', "
        "or sides (infinite, no caps: the EESD paper's z-fail, 'like Z-pass except step 5 and 6')",
    )
    parser.add_argument(
        "--out",
        type=Path,
        required=True,
        metavar="mask.png",
        help="8-bit mask PNG, 255 in shadow (missing folders are created)",
    )
    parser.add_argument("--coverage", type=Path, metavar="cov.png", help="also write the coverage PNG")
    parser.add_argument(
        "--stages",
        type=Path,
        metavar="FILE",
        help="also write the frame's stages (zpass, zfail, pertriangle): operations, fragments, stencil updates "
        "and seconds per stage, as .csv, .json or .parquet by the extension",
    )
    parser.add_argument("--image", type=Path, metavar="shaded.png", help="also write a Phong-shaded picture")
    parser.add_argument(
        "--max-memory",
        default=None,
        metavar="SIZE",
        help="refuse a render estimated to need more (e.g. 8G; default $SILCOUNT_MAX_MEMORY or free RAM)",
    )


WARN_BYTES = 1 << 30  # a render estimated to need more says so on stderr before it starts


def check_memory(scene: Scene, method: str, image: bool, max_memory: int | None) -> None:
    """Refuse, in one line, a render whose estimate (:mod:`silcount.render.memory`) exceeds the limit."""
    from silcount.errors import InvalidMesh
    from silcount.mesh.io import MAX_MEMORY_ENV, format_size, memory_limit
    from silcount.render.memory import render_bytes

    need = render_bytes(scene.width, scene.height, method, image)
    limit = memory_limit(max_memory)
    what = f"{scene.path}: {scene.width}x{scene.height} by {method}{' with --image' if image else ''}"
    if need > limit:
        raise InvalidMesh(
            f"{what} needs about {format_size(need)}, over the limit of {format_size(limit)} "
            f"(set --max-memory or ${MAX_MEMORY_ENV} to raise it)"
        )
    if need > WARN_BYTES:
        print(f"silcount render: warning: {what} needs about {format_size(need)} of memory", file=sys.stderr)


def write_outputs(scene: Scene, r: Rendered, out: Path, coverage: Path | None, image: Path | None) -> list[Path]:
    from silcount.render.masks import write_mask, write_png

    paths = [write_mask(out, r.mask)]
    if coverage is not None:
        paths.append(write_mask(coverage, r.coverage))
    if image is not None:
        from silcount.render.shade import shade

        paths.append(write_png(image, shade(scene, r.tri_id, r.eye_depth, r.mask)))
    return paths


def check_stages(args: argparse.Namespace) -> None:
    """``--stages``: a stencil method, volumes it counts, a known extension; one line otherwise (exit 2)."""
    if args.method not in ("zpass", "zfail", "pertriangle"):
        raise BadArgument(f"--stages applies to zpass, zfail and pertriangle, not to {args.method}")
    if args.volume == "truncated":
        raise BadArgument("--stages counts infinite and uncapped ('sides') volumes, not truncated ones")
    if args.stages.suffix.lower() not in STAGE_FORMATS:
        raise BadArgument(f"--stages {args.stages}: the extension must be one of {', '.join(STAGE_FORMATS)}")


def run(args: argparse.Namespace) -> int:
    from silcount.atomic import check_writable
    from silcount.detectors import get
    from silcount.mesh.io import parse_size
    from silcount.render.methods import render_method
    from silcount.render.scene import load_scene

    get(args.detector, prefix="--detector: ")  # checked here, not by argparse: the registry fills on first use
    if args.stages is not None:
        check_stages(args)
    for path in (args.out, args.coverage, args.image, args.stages):
        if path is not None:
            check_writable(path)  # before the render, which may take long
    max_memory = parse_size(args.max_memory, "--max-memory") if args.max_memory else None
    scene = load_scene(args.scene, max_memory)
    if args.method not in ("zpass", "zfail", "pertriangle") and (
        args.shadow_test != "nonzero" or args.volume != "infinite"
    ):
        raise BadArgument(f"--shadow-test and --volume apply to zpass, zfail and pertriangle, not to {args.method}")
    check_memory(scene, args.method, args.image is not None, max_memory)
    r = render_method(scene, args.method, args.detector, args.variant, args.shadow_test, args.volume)
    for msg in r.messages:
        print(f"silcount render: warning: {msg}", file=sys.stderr)
    write_outputs(scene, r, args.out, args.coverage, args.image)
    if args.stages is not None and r.log is not None:
        from silcount.render.stages import stage_table, write_table

        detector = "" if args.method == "pertriangle" else args.detector
        write_table(stage_table(r.log, scene.light, args.method, detector), args.stages)
    print(
        f"{args.out}: {int(r.mask.sum())} pixels in shadow of {int(r.coverage.sum())} covered "
        f"({scene.width}x{scene.height}, {args.method}"
        + (
            f", {args.detector} {args.variant}, {args.shadow_test} test, {args.volume} volumes"
            if args.method in ("zpass", "zfail")
            else f", {args.shadow_test} test"
            if args.method == "pertriangle"
            else ""
        )
        + (f", {args.variant} shadow matrix" if args.method == "planar" else "")
        + ")"
    )
    return 0


# ---- the report part -------------------------------------------------------------------------------


def shared_scene_dir() -> Path | None:
    """``$SILCOUNT_SCENE_DIR`` (the Makefile sets ``../shared/scenes``) if it names a folder, else None."""
    env = os.environ.get("SILCOUNT_SCENE_DIR")
    return Path(env) if env and Path(env).is_dir() else None


def _entry(mask: np.ndarray, truth: np.ndarray, coverage: np.ndarray) -> dict:
    from silcount.render.masks import compare_masks

    c = compare_masks(mask, truth, coverage)
    return {
        "shadow_pixels": int(mask.sum()),
        "mismatched": c.mismatched,
        "covered": c.covered,
        "fraction": round(c.fraction, 6),
        "far_mismatches": c.far,
        "matches": c.ok,
    }


LITERAL_STEPS = {  # key: (method, shadow test, volume); the papers' printed steps (stencil paper Sec. 5, EESD Sec. 4)
    "zfail-parity": ("zfail", "parity", "infinite"),
    "zpass-parity": ("zpass", "parity", "infinite"),
    "zpass-truncated": ("zpass", "nonzero", "truncated"),
    "zfail-truncated": ("zfail", "nonzero", "truncated"),
    "zfail-uncapped": ("zfail", "nonzero", "sides"),
}


def _render_scene(scene: Scene, dest: Path, written: list[Path]) -> dict:
    """Every method, literal step and detector on one scene; masks into ``dest``; the scene's summary entry."""
    import numpy as np

    from silcount.detectors import get, names
    from silcount.render.masks import write_mask
    from silcount.render.methods import render_method
    from silcount.render.planar import floor_plane

    name = scene.name
    truth = render_method(scene, "raycast")
    written += write_outputs(
        scene, truth, dest / f"{name}.raycast.png", dest / f"{name}.coverage.png", dest / f"{name}.raycast.shaded.png"
    )
    entry: dict = {"resolution": [scene.width, scene.height], "methods": {}, "literal_steps": {}, "detectors": {}}
    for method in ("zpass", "zfail"):
        r = render_method(scene, method)
        shaded = dest / f"{name}.{method}.shaded.png" if method == "zfail" else None
        written += write_outputs(scene, r, dest / f"{name}.{method}.png", None, shaded)
        entry["methods"][method] = _entry(r.mask, truth.mask, truth.coverage) | {"messages": r.messages}
        if method == "zfail":
            ref_mask = r.mask
    try:
        k, _, _ = floor_plane(scene)
    except BadArgument:
        k = None
    for key, (method, test, volume) in LITERAL_STEPS.items():
        if volume == "truncated" and k is None:
            continue
        r = render_method(scene, method, shadow_test=test, volume=volume)
        written += write_outputs(scene, r, dest / f"{name}.{key}.png", None, None)
        entry["literal_steps"][key] = _entry(r.mask, truth.mask, truth.coverage)
    if k is not None:
        floor = truth.coverage & (scene.triangle_object[np.maximum(truth.tri_id, 0)] == k)
        for variant in ("intended", "literal"):
            r = render_method(scene, "planar", variant=variant)
            written += write_outputs(scene, r, dest / f"{name}.planar-{variant}.png", None, None)
            entry["methods"][f"planar-{variant}"] = _entry(r.mask, truth.mask, floor)
    for det in names():
        # the literature's hierarchies have one variant (a literal run would repeat it); the others keep a literal row
        for variant in ("intended",) if get(det).role == "literature" else ("intended", "literal"):
            key = f"{det}-{variant}"
            try:
                r = render_method(scene, "zfail", det, variant)
            except SilcountError as exc:  # fail the report, naming the part
                raise type(exc)(f"renders: {name}: z-fail with detector {key}: {exc}") from None
            same = int((r.mask != ref_mask).sum())
            entry["detectors"][key] = _entry(r.mask, truth.mask, truth.coverage) | {
                "pixels_differing_from_reference": same
            }
            if same:
                written.append(write_mask(dest / f"{name}.zfail.{key}.png", r.mask))
    return entry


def report(out_dir: Path) -> list[Path]:
    """Render the built-in scenes and the shared ones into ``out_dir/renders/``: masks, shaded images, a summary.

    The built-in scenes (:mod:`silcount.render.builtin`) are always rendered; the shared scenes when
    :func:`shared_scene_dir` finds them.  Without them an existing summary is left as it is (a clone without
    the shared scenes loses none of its rows); only a missing one is written, of the built-in scenes.
    """
    from silcount.atomic import make_folder, write_text
    from silcount.render.builtin import BUILTIN, builtin_scene
    from silcount.render.scene import load_scene

    scenes = [builtin_scene(n) for n in BUILTIN]
    dest = out_dir / "renders"
    shared = shared_scene_dir()
    keep = shared is None and (dest / "summary.json").is_file()
    if shared is None:
        print("silcount report: renders: no shared scenes (set SILCOUNT_SCENE_DIR); built-in only"
              + (", the summary left as it is (nothing to recompute its shared scenes from)" if keep else ""),
              file=sys.stderr)  # fmt: skip
    else:
        scenes += [load_scene(p) for p in sorted(shared.glob("*.json"))]
    make_folder(dest)
    written: list[Path] = []
    summary: dict = {
        "scenes": {},
        "note": "fractions are mismatched / covered pixels against raycast "
        "(planar: floor pixels only); far = more than one pixel from a mask edge",
    }
    for scene in scenes:
        summary["scenes"][scene.name] = _render_scene(scene, dest, written)
    if not keep:
        written.append(write_text(dest / "summary.json", json.dumps(summary, indent=2, sort_keys=True) + "\n"))
        written.append(write_text(dest / "summary.md", summary_markdown(summary)))
    return written


def _mismatch_row(scene: str, what: str, m: dict) -> str:
    """One Markdown row of a mask compared with ray casting."""
    return (
        f"| {scene} | {what} | {m['shadow_pixels']} | {m['mismatched']} | {m['fraction']:.6f} "
        f"| {m['far_mismatches']} | {'yes' if m['matches'] else 'NO'} |"
    )


def summary_markdown(summary: dict) -> str:
    lines = [
        "# Shadow masks of the shared scenes against ray casting",
        "",
        "Mismatched pixels as a fraction of covered pixels (planar: of floor pixels), and the far",
        "mismatches (more than one pixel from an edge of either mask). Regenerate with `silcount report`.",
        "",
        "| scene | method | shadow px | mismatched | fraction | far | matches |",
        "|---|---|---:|---:|---:|---:|---|",
    ]
    for scene, e in summary["scenes"].items():
        lines += [_mismatch_row(scene, method, m) for method, m in e["methods"].items()]
    lines += [
        "",
        "## The papers' literal steps",
        "",
        "`parity`: the stencil paper's printed final test `If (~Stencil % 2)` (shadow where the stencil is odd)",
        "instead of the text's 'not zero'; `truncated`: volumes stopped at the floor plane by its 'new pixel' step",
        "(Sec. 5); `uncapped`: the EESD paper's z-fail, 'like Z-pass algorithm except step 5 and 6' (Sec. 4), on",
        "the volumes' sides alone.",
        "",
        "| scene | step | shadow px | mismatched | fraction | far | matches |",
        "|---|---|---:|---:|---:|---:|---|",
    ]
    for scene, e in summary["scenes"].items():
        lines += [_mismatch_row(scene, key, m) for key, m in e["literal_steps"].items()]
    lines += [
        "",
        "## z-fail masks per detector",
        "",
        "| scene | detector-variant | fraction vs raycast | far | pixels differing from reference |",
        "|---|---|---:|---:|---:|",
    ]
    for scene, e in summary["scenes"].items():
        for key, d in e["detectors"].items():
            lines.append(
                f"| {scene} | {key} | {d['fraction']:.6f} | {d['far_mismatches']} "
                f"| {d['pixels_differing_from_reference']} |"
            )
    notes = [
        f"- {scene} {method}: {msg}"
        for scene, e in summary["scenes"].items()
        for method, m in e["methods"].items()
        for msg in m.get("messages", [])
    ]
    if notes:
        lines += ["", "## Messages", ""] + notes
    return "\n".join(lines) + "\n"
