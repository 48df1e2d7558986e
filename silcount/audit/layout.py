"""Rendering audits as text (terminal tables), Markdown or JSON, deterministically.

Numbers are formatted by :func:`fmt`: integers in full, other floats with
six significant digits; JSON keeps full ``repr`` precision (input
coordinates must survive exactly) and sorted-as-built keys.  Nothing here
computes: it only lays out the dictionary built by :mod:`silcount.audit.compute`.
Each table is a :class:`pandas.DataFrame` of formatted cells, laid out by
``DataFrame.to_markdown`` (tabulate): ``pipe`` for Markdown, ``simple`` for
the terminal.  The JSON document's schema is ``docs/schemas/audit.schema.json``.
"""

from __future__ import annotations

import json

from silcount.counting.arithmetic import KINDS


def fmt(x) -> str:
    """Stable human formatting: ``-`` for missing, ints in full, floats to 6 significant digits."""
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        return f"{x:.6g}"
    return str(x)


def table(header: list[str], rows: list[list[str]], markdown: bool) -> list[str]:
    """Aligned plain-text or Markdown table lines: the first column left-aligned, the others right-aligned."""
    import pandas as pd  # pandas (~0.5 s): only when a table is laid out

    frame = pd.DataFrame(rows, columns=header, dtype=object)
    align = ("left",) + ("right",) * (len(header) - 1)
    text = frame.to_markdown(
        index=False, tablefmt="pipe" if markdown else "simple", disable_numparse=True, colalign=align
    )
    return text.splitlines()


def _kinds(entries: list[dict], model: str) -> list[str]:
    extra = sorted({k for e in entries for k in e["tallies"].get(model, {}) if k not in KINDS})
    return list(KINDS) + extra


def _detector_table(detectors: dict, model: str, markdown: bool) -> list[str]:
    kinds = _kinds(list(detectors.values()), model)
    header = ["detector", "edges", "agrees", *kinds, "cycles", "printed cycles per light", "measured/printed per light",
              "time s"]  # fmt: skip
    rows = []
    for key, d in detectors.items():
        printed = d["formula_printed"]
        tally = d["tallies"].get(model)  # none: the detector has no such model (the warnings say so)
        rows.append(
            [
                key,
                fmt(d["silhouette_edges"]),
                fmt(d["agrees_with_reference"]),
                *(fmt(tally.get(k, 0)) if tally is not None else "" for k in kinds),
                fmt(d["cycles"][model]) if tally is not None else "",
                fmt(printed["cycles"]) if printed else "-",
                fmt(printed["cycles_ratio"][model]) if printed else "-",
                fmt(d["time_s"]),
            ]
        )
    return table(header, rows, markdown)


def _hierarchy_table(detectors: dict, lights: int, markdown: bool) -> list[str]:
    """The hierarchies' build tally by kind (once per mesh, not in the query tallies), its cycles and break-even."""
    tree = {key: d["hierarchy"] for key, d in detectors.items() if d.get("hierarchy")}
    extra = sorted({k for h in tree.values() for k in h["build"] if k not in KINDS})
    kinds = [*KINDS, *extra]
    header = ["detector", "leaf/fan-out", "tree bytes", *kinds, "build cycles", "edges visited",
              "true ops saved per light", "break-even lights (true ops)"]  # fmt: skip
    rows = [
        [
            key,
            f"{h['leaf_size']}/{h['fanout']}",
            fmt(h["tree_bytes"]),
            *(fmt(h["build"].get(k, 0)) for k in kinds),
            fmt(h["build_cycles"]),
            fmt(h["edges_visited_fraction"]),
            fmt(h["query_saving"] / lights),
            fmt(h["break_even_lights"]),
        ]
        for key, h in tree.items()
    ]
    return table(header, rows, markdown)


def _mesh_lines(mesh: dict, markdown: bool) -> list[str]:
    rows = [
        [k, fmt(mesh[k])]
        for k in (
            "vertices",
            "faces",
            "edges",
            "mean_sides",
            "closed",
            "consistently_wound",
            "boundary_edges",
            "nonmanifold_edges",
            "inconsistent_edges",
            "degenerate_faces",
            "zero_normal_faces",
            "duplicate_faces",
            "collapsed_faces_dropped",
            "components",
            "euler_characteristic",
            "genus",
        )
    ]
    cop = mesh.get("coplanar")
    if cop:
        rows += [
            ["coplanar polygons (HSD)", fmt(cop["polygons"])],
            ["polygon mean sides m (HSD)", fmt(cop["mean_sides"])],
        ]
    rows += [[f"{r} (paper assumes {fmt(mesh['paper_ratios'][r])})", fmt(v)] for r, v in mesh["ratios"].items()]
    return table(["mesh statistic", "value"], rows, markdown)


def _light_text(light: dict) -> str:
    where = light.get("position") or light.get("direction") or ()
    return f"{light['kind']} ({', '.join(fmt(c) for c in where)})"


def render_text(audit: dict, markdown: bool = False) -> str:
    """The audit as readable tables (``markdown=True``: for a paper or an issue thread)."""
    h = (lambda s: f"## {s}") if markdown else (lambda s: f"{s}:")
    s = audit["settings"]
    n = len(audit["lights"])
    out = [
        ("# " if markdown else "") + f"silcount audit of {audit['source']}",
        "",
        f"silcount {audit['silcount_version']}, engine {s['engine']}, variants {', '.join(s['variants'])}, "
        f"cycle profile {s['cycles']}",
        "",
        h("Mesh"),
        "",
        *_mesh_lines(audit["mesh"], markdown),
        "",
        h(f"Lights ({n})"),
        "",
    ]
    out += [
        f"- {i}: {_light_text(l)}"
        + (f", ties {l['ties']}" if l["ties"] else "")
        + (", inside the mesh" if l.get("inside") else "")
        for i, l in enumerate(audit["lights"])
    ]
    out += ["", h("Warnings"), ""] + ([f"- {w}" for w in audit["warnings"]] or ["- none"])
    if audit.get("refused"):
        out += ["", h("Refused (not in the tables below)"), ""]
        out += [f"- {k}: {why}" for k, why in audit["refused"].items()]
    scope = "summed over the lights" if n > 1 else "one light"
    for model in ("paper", "true"):
        out += [
            "",
            h(f"Detectors, {model} cost model ({scope})"),
            "",
            *_detector_table(audit["detectors"], model, markdown),
        ]
    if any(d.get("hierarchy") for d in audit["detectors"].values()):
        out += [
            "",
            h("Hierarchies: the tree's build, once per mesh (true cost model, not in the tallies above)"),
            "",
            *_hierarchy_table(audit["detectors"], n, markdown),
            "",
            "edges visited: edges whose faces the query evaluated, over E (mean over the lights); true ops saved per "
            "light: the reference's true total minus the query's, in operations (not cycles); break-even lights: "
            "how many lights before build plus queries cost fewer true operations than the reference's queries "
            "(- when a query saves nothing; weighted by a cycle profile the break-even can differ). Their time s "
            "includes the build wherever a call made it: once per mesh with the fast engine, at every call with "
            "the naive one.",
        ]
    printed = [(k, d["formula_printed"]) for k, d in audit["detectors"].items() if d["formula_printed"]]
    if printed:
        out += ["", h("Printed formulas at this mesh (per light)"), ""]
        out += table(
            ["detector", "source", "n", "m", *KINDS],
            [
                [
                    k,
                    fmt(p.get("source")),
                    fmt(p.get("n")),
                    fmt(p.get("m")),
                    *(fmt(p["tally"].get(kind)) for kind in KINDS),
                ]
                for k, p in printed
            ],
            markdown,
        )
    return "\n".join(out) + "\n"


def render_json(audit: dict) -> str:
    return json.dumps(audit, indent=1, allow_nan=False) + "\n"


def format_audit(audit: dict, form: str) -> str:
    if form == "json":
        return render_json(audit)
    return render_text(audit, markdown=form == "md")
