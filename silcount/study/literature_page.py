"""``literature.md``: the papers' detectors beside the literature's, on the sweep's meshes (markdown).

One table (per size band and light kind: ``true`` operations per light, edges
visited as a fraction of E, time per light, for TA, VnV, HSD, EESD,
``reference``, ``gaussmap`` and ``cones``; the lowest of each row in bold),
the figures ``literature`` and ``output_sensitivity``
(:mod:`silcount.study.figures`), the output-sensitivity fits and the findings
of :func:`silcount.study.literature.findings`.  Every number is computed from
the sweep; none is written here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from silcount.detectors import with_role
from silcount.study.literature import AGAINST, band_table, findings, label, order

if TYPE_CHECKING:
    import pandas as pd

    from silcount.study.work import Settings

TITLE = "The papers' detectors beside the literature"
QUANTITIES = (
    ("true_ops", "true operations per light"),
    ("visited_fraction", "edges visited / E"),
    ("time_s", "time per light"),
)


def ops_text(v: float) -> str:
    """``12,345`` below a million, ``1.23e+06`` above."""
    return f"{v:,.0f}" if v < 1e6 else f"{v:.3g}"


def time_text(v: float) -> str:
    """Seconds in ns, us, ms or s, three significant digits."""
    for scale, unit in ((1.0, "s"), (1e-3, "ms"), (1e-6, "us")):
        if v >= scale:
            return f"{v / scale:.3g} {unit}"
    return f"{v / 1e-9:.3g} ns"


def _cell(entry: dict | None, quantity: str, best: bool) -> str:
    if entry is None:
        return ""
    value = entry[quantity]
    if value is None or value != value:
        return "-"
    text = {"true_ops": ops_text, "time_s": time_text}.get(quantity, lambda v: f"{v:.3f}")(value)
    if quantity == "time_s" and entry["timed"] < entry["meshes"]:
        text += f" ({entry['timed']}/{entry['meshes']})"
    return f"**{text}**" if best else text


def table(frame: pd.DataFrame) -> str:
    """The per-band table as markdown; the lowest operations and time of each row in bold; no time rows when
    nothing was timed."""
    bands = band_table(frame)
    timed = bool(frame["time_s"].notna().any())
    dets = [d for d in order() if any(d in b["detectors"] for b in bands)]
    head = ["faces F", "light kind", "meshes", "quantity"] + [label(d) for d in dets]
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join(["---"] * 4 + ["---:"] * len(dets)) + "|"]
    for b in bands:
        for quantity, name in QUANTITIES if timed else QUANTITIES[:2]:
            values = {d: e[quantity] for d, e in b["detectors"].items() if e[quantity] is not None}
            low = min(values.values()) if values and quantity != "visited_fraction" else None
            cells = [_cell(b["detectors"].get(d), quantity, low is not None and values.get(d) == low) for d in dets]
            lines.append("| " + " | ".join([b["band"], b["light_kind"], str(b["meshes"]), name, *cells]) + " |")
    return "\n".join(lines)


def fits_table(fits: dict) -> str:
    """The output-sensitivity fits (``<detector>:<kind>:edge_test~<x>``) as markdown."""
    lines = ["| fit | against | meshes | alpha | 95% interval | c |", "|---|---|---:|---:|---|---:|"]
    for name, f in fits.items():
        if ":edge_test~" not in name:
            continue
        if f["alpha"] is None:
            lines.append(f"| {name} | {f['against']} | {f['meshes']} | | | |")
            continue
        ci = f["alpha_ci"]
        interval = f"[{ci[0]:.3f}, {ci[1]:.3f}]" if ci else ""
        lines.append(f"| {name} | {f['against']} | {f['meshes']} | {f['alpha']:.3f} | {interval} | {f['c']:.4g} |")
    return "\n".join(lines)


def page(frame: pd.DataFrame, fits: dict, settings: Settings, failed: int) -> str:
    """The whole ``literature.md``."""
    timed = settings.timing and frame["time_s"].notna().any()
    # the figure output_sensitivity is written
    hierarchies = bool(frame["detector"].isin(with_role("literature")).any())
    n = frame[["file", "level"]].drop_duplicates().shape[0]
    kinds = ", ".join(sorted(set(frame["light_kind"]))) or "no"
    lights = {"both": f"{settings.lights} directional and {settings.lights} point"}.get(
        settings.light_kind, f"{settings.lights} {settings.light_kind}"
    )
    what = (
        f"{n} meshes ({failed} more could not be audited), {lights} lights each (seed {settings.seed}), every "
        f"detector `intended`, `{settings.engine}` engine; light kinds here: {kinds}."
    )
    timing = (
        "Time per light: each algorithm's own compiled, uncounted loops (each detector module's `plain_edge_ids`); for "
        "the Gauss map and the normal cones, their compiled query (one numba thread) on the mesh's tree, built "
        "before the clock starts (the build is in no time; its counted cost is the `build` of `meshes.csv`), "
        f"mean of the first {settings.time_lights} light(s) of each kind; `(timed/meshes)` when a band's "
        "meshes were not all timed (VnV and EESD past "
        f"E x F = {settings.time_max_pairs:,}, the others past {settings.time_max_faces:,} faces)."
        if timed
        else "Time per light: not measured in this sweep (no time rows)."
    )
    lines = [
        f"# {TITLE}",
        "",
        "TA and VnV (HSD 2011 Sec. 4; EESD 2012 Sec. 3), HSD (HSD 2011) and EESD (EESD 2012) beside silcount's "
        "O(E) `reference` and the literature's output-sensitive detectors of the time: the Gauss-map hierarchy "
        "(Gooch et al., I3D 1999) and the spatialized normal-cone hierarchy (Johnson and Cohen, I3D 2001; Sander "
        "et al., SIGGRAPH 2000), as silcount reads them (`docs/literature.md`).  The last three return exactly "
        "the reference edge set.",
        "",
        what,
        "",
        "![true operations per light against F](literature.png)",
        "",
        "## Per size band",
        "",
        "Each value is the median over the band's meshes of the mesh's mean per light; bold: the row's lowest.  "
        "Edges visited: the edges each per-light loop examines (every edge for reference, VnV and EESD; the "
        "sides of the light-facing faces, or polygons, that TA and HSD look up in S; the edges of the leaves "
        "the hierarchies open).  " + timing,
        "",
        table(frame),
        "",
        "## Output sensitivity",
        "",
        "Edges tested per light by the hierarchies (their `steps.edge_test`, mean per mesh) against the "
        "silhouette s, the faces F and " + AGAINST["s_log2F"] + ": least squares in log-log, 95% bootstrap "
        "interval over the meshes (`fits.json`).",
        "",
        fits_table(fits),
        "",
        *(["![edges tested against s log2 F](output_sensitivity.png)", ""] if hierarchies else []),
        "## Worst cases",
        "",
        "These are typical meshes.  The worst exponent the worst-case search finds for each detector, beside "
        "its typical one, and for the hierarchies the worst fraction of E tested under adversarial meshes and "
        "lights, with the mesh and light that cause it: `silcount report`'s [worst-case rows](../worst-case/rows.md) "
        "(docs/worst-case.md).",
        "",
        "## Findings",
        "",
        "silcount's counts on these meshes, each line computed from the tables above.  'X below Y' compares "
        "each mesh's means per light; the orderings are those the papers' conclusions rank.",
        "",
    ]
    lines += [f"- {line}" for line in findings(frame, fits, bool(timed))]
    return "\n".join(lines) + "\n"
