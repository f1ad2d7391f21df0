"""Render an :class:`~planner.plan.outcome.Outcome` as one HTML file: the interactive site map
(:mod:`planner.report.site_map`), the 3-D view (:mod:`planner.report.view3d_section`), inputs and parameters, closure
table, station table, comparison of methods, figures, network and accuracy check, verification, and floors and ceilings
where the plan has them (:mod:`planner.report.surfaces_section`).

The file needs nothing else (no external CSS, fonts or images). A short script marks on ``<body data-images-ok="k/n">``
how many embedded images decoded, which the render test reads back from headless Chromium.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from planner import __version__
from planner.core.checks import argument
from planner.figures import network_figure
from planner.figures.base import png_bytes
from planner.figures.plan_fig import plan_pngs
from planner.network.summary import network_summary
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering
from planner.plan.tripod import MIN_RADIUS_M
from planner.report.hours_section import hours_section
from planner.report.markup import esc as _e
from planner.report.markup import image as _img
from planner.report.markup import table
from planner.report.replan_section import replan_section
from planner.report.site_map import (
    read_field_sheet,
    report_numbering,
    site_map_html,
    site_plan_html,
    station_row_id,
)
from planner.report.surfaces_section import surfaces_section
from planner.report.view3d_section import view3d_section
from planner.solve.result import Status, state_words

CSS = """body{font-family:system-ui,sans-serif;margin:2em;max-width:1400px;color:#222}
table{border-collapse:collapse;margin:0.5em 0 1.5em;font-size:0.9em}th,td{border:1px solid #bbb;padding:3px 7px;text-align:right}
th{background:#eee}td.l,th.l{text-align:left}img{max-width:100%;height:auto;border:1px solid #ddd;margin:0.5em 0}
.pass{color:#176317;font-weight:bold}.fail{color:#b00;font-weight:bold}figure{margin:0 0 2em;max-width:100%}
.scroll{overflow-x:auto;max-width:100%;-webkit-overflow-scrolling:touch}.scroll>table{margin-bottom:0.5em}
.scroll{margin-bottom:1em}h1,h2,h3,p,li,figcaption{overflow-wrap:anywhere}
ul.notes{font-size:0.9em}ul.notes li{margin:0.15em 0}
@media (max-width:600px){body{margin:0.6em}h1{font-size:1.35em}h2{font-size:1.15em}table{font-size:0.8em}
th,td{padding:2px 4px}figure{margin:0 0 1.2em}ul{padding-left:1.2em}}"""
SCRIPT = (
    "window.addEventListener('load',function(){var im=document.images,ok=0;for(var i=0;i<im.length;i++)"
    "{if(im[i].complete&&im[i].naturalWidth>0)ok++;}document.body.setAttribute('data-images-ok',ok+'/'+im.length);});"
)


def _f(v: Any, fmt: str = ".3f") -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, fmt) if isinstance(v, (int, float)) and not isinstance(v, bool) else _e(v)


def _parameters(o: Outcome) -> str:
    p, lim, m = o.site.parameters, o.validation.range_limit, o.meta.get("parameters", {})
    rows = [
        ("site file", _e(o.site.source or "-")),
        ("instrument", _e(f"{o.validation.scanner.name}: {o.validation.scanner.description}")),
        ("S_max (slant range)", f"{lim.max_slant_range_m:.3f} m ({_e(lim.source)})"),
        ("theta_max", f"{p.theta_max_deg:g} deg"),
        ("overlap", f"{p.overlap:.0%}"),
        ("sigma_req", f"{p.sigma_req_m * 1000:g} mm" + (f" (scale 1:{p.drawing_scale})" if p.drawing_scale else "")),
        ("sigma_instr", f"{lim.sigma_instr_m * 1000:.3f} mm"),
        ("instrument height", f"{p.instrument_height_m:g} m"),
        ("wall pieces", f"{m.get('target_spacing_m', '-')} m"),
        ("incidence", _e(m.get("incidence", "horizontal"))),
        ("method", _e(f"{o.meta.get('method')} {o.meta.get('backend') or ''}")),
        ("solver", _e(", ".join(f"{k} {v}" for k, v in (m.get("milp") or {}).items() if v is not None) or "-")),
    ]
    return table(("parameter", "value"), rows, left=2)


def _closure(o: Outcome) -> str:
    rows = []
    for z in o.site.zones:
        c = z.closure
        rows.append(
            (
                _e(z.id),
                _e(z.scan_side.value),
                _e(z.frame),
                len(z.walls),
                _f(z.perimeter_m),
                _f(z.area_m2, ".1f"),
                _e(c.summary() if c else "given by coordinates"),
            )
        )
    out = table(("zone", "side", "frame", "walls", "perimeter m", "area m2", "closure"), rows, left=3)
    if o.site.corrections:
        out += "<p>Corrections of printed data:</p>" + table(
            ("zone", "where", "field", "printed", "corrected", "reason"),
            (
                (_e(c.zone), _e(c.target), _e(c.field), f"{c.printed:g}", f"{c.corrected:g}", _e(c.reason))
                for c in o.site.corrections
            ),
            left=3,
        )
    return out


def _stations(o: Outcome, numbering: StationNumbering) -> str:
    """The station table, one row per station by number (its ``data-station-number`` and ``data-station-label``
    on the row), the numbering said under it."""
    per = dict(zip((s.id for s in o.stations), o.coverage.per_station))
    ordered = numbering.ordered(o.stations)
    rows = [
        (
            numbering.number(s.id),
            _e(numbering.label(s.id)),
            _e(s.zone),
            _e(s.side.value),
            _e(s.kind.value),
            _f(s.x),
            _f(s.y),
            _f(st.covered_m, ".1f"),
            _f(st.worst_incidence_deg, ".1f"),
            _f(st.longest_range_m, ".1f"),
            _f(o.tripod_radius_m.get(s.id)),
            _f(st.worst_point_error_m * 1000 if math.isfinite(st.worst_point_error_m) else None, ".2f"),
        )
        for s, st in ((s, per[s.id]) for s in ordered)
    ]
    zero = sum(1 for s in o.stations if o.tripod_radius_m.get(s.id) == 0)
    note = (
        f"<p>Tripod radius 0 ({zero} station(s)): no disc of at least {MIN_RADIUS_M * 100:g} cm keeps everything the "
        f"plan relies on that station for; set it up at the planned point (such discs are not drawn in the "
        f"exports).</p>"
        if zero
        else ""
    )
    return (
        table(
            (
                "no.",
                "id",
                "zone",
                "side",
                "kind",
                "x m",
                "y m",
                "covered wall m",
                "worst incidence deg",
                "longest range m",
                "tripod radius m",
                "predicted worst point error (2.13) mm",
            ),
            rows,
            left=5,
            row_ids=[station_row_id(numbering.number(s.id)) for s in ordered],
            row_data=[{"station-number": numbering.number(s.id), "station-label": s.id} for s in ordered],
        )
        + f'<p class="numbering">No.: {_e(numbering.legend)}; id: the station\'s label in every file.</p>'
        + note
    )


def _comparison(o: Outcome) -> str:
    if not o.comparison:
        return "<p>No comparison was run.</p>"
    rows = (
        (
            _e(r["method"]),
            _e(r.get("backend", "")),
            _f(r.get("stations"), "d"),
            _f(r.get("inside"), "d"),
            _f(r.get("outside"), "d"),
            _bound_cell(r),
            _f(r.get("gap"), ".1%"),
            _e(r.get("status", "")),
            _f(r.get("time_s"), ".2f"),
            _f(r.get("verified_percent"), ".3f"),
            _e("" if "connected" not in r else ("yes" if r["connected"] else "no")),
            _e(r.get("over", "")),
        )
        for r in o.comparison
    )
    threads = (o.meta.get("parameters", {}).get("milp") or {}).get("threads", 1)
    return (
        table(
            (
                "method",
                "backend",
                "stations",
                "inside",
                "outside",
                "bound (scope)",
                "gap",
                "status",
                "solver s",
                "verified %",
                "registration connected",
                "over",
            ),
            rows,
            left=2,
        )
        + f"<p>Bound: no plan has fewer stations; its scope says over what (pool: the candidate pool, connected "
        f"plans when registration is required; plane: any positions). Solver s: the solver alone, "
        f"{threads} thread(s) for the MILP, 1 for the others; coverage build and pricing not included (milp-tiles: "
        f"the whole tiled run, pool and coverage included).</p>"
    )


def _bound_cell(r: dict[str, Any]) -> str:
    """``22 (pool; plane 20)``: the bound, what it is over, and the plane bound beside a pool bound."""
    if not isinstance(r.get("bound"), (int, float)):
        return ""
    scope = r.get("bound_scope") or "pool"
    plane = (
        f"; plane {r['plane_bound']:g}" if scope == "pool" and isinstance(r.get("plane_bound"), (int, float)) else ""
    )
    return f"{r['bound']:g} ({_e(scope)}{plane})"


def _network(o: Outcome) -> str:
    if o.network is None:
        return "<p>The network check was not run.</p>"
    c = o.network.check
    verdict = f'<span class="{"pass" if c["pass"] else "fail"}">{"PASS" if c["pass"] else "FAIL"}</span>'
    rows = (
        (
            _e(z["zone"]),
            _e(z["side"]),
            "pass" if z["pass"] else '<span class="fail">FAIL</span>',
            "untied station" if z["untied"] else _f(z["worst_e_m"] * 1000, ".2f"),
        )
        for z in c["zones"]
    )
    worst = "none finite" if c["worst_e_m"] is None else f"{c['worst_e_m'] * 1000:.2f} mm"
    untied = f"; {c['untied_targets']} pieces seen by untied stations only" if c.get("untied_targets") else ""
    return (
        f"<p>Accuracy check at {c['sigma_req_m'] * 1000:g} mm: {verdict} ({c['failing_targets']} of {c['targets']} seen pieces "
        f"fail; worst point error {worst}{untied}).</p>"
        + table(("zone", "side", "check", "worst e mm"), rows, left=2)
        + _network_notes(o)
    )


def _network_notes(o: Outcome) -> str:
    """The rest of the network check (size, ties, a priori error, notes, the scanner survey) as a list that wraps at the
    page's width; the accuracy check is the table above, not repeated."""
    assert o.network is not None
    lines = [ln.strip() for ln in network_summary(o.network, accuracy=False).splitlines() if ln.strip()]
    return '<ul class="notes">' + "".join(f"<li>{_e(ln)}</li>" for ln in lines) + "</ul>"


def _verification(o: Outcome, numbering: StationNumbering) -> str:
    v = o.verification
    head = (
        f"<p>{'<span class=pass>complete</span>' if v.complete else '<span class=fail>incomplete</span>'}: "
        f"{v.percent:.3f} % of points every {v.spacing_m:g} m covered.</p>"
    )
    rows = ((_e(z.zone), _e(z.side), z.covered, z.points, _f(z.percent, ".3f")) for z in v.zones)
    gaps = "".join(
        f"<li>{_e(g.zone)} {_e(g.side)} wall {g.wall}: {g.from_m:.2f}-{g.to_m:.2f} m</li>" for g in v.gaps[:50]
    )
    mis = "".join(
        f'<li data-station-number="{numbering.number(s)}" data-station-label="{_e(s)}">station no. '
        f"{numbering.number(s)} {_e(s)}: {_e(r)}</li>"
        for s, r in v.misplaced
    )
    return (
        head
        + table(("zone", "side", "covered", "points", "%"), rows, left=2)
        + (f"<ul>{gaps}{mis}</ul>" if gaps or mis else "")
    )


def render_report(o: Outcome, field: str | None = None, field_sheet: Mapping[str, Any] | None = None) -> str:
    """The report as one HTML string; ``field``: the address of the plan's field sheet (field.html) to link;
    ``field_sheet``: that sheet as ``field.json`` holds it, whose route and targets the site map draws."""
    argument(o, Outcome, "outcome")
    numbering = report_numbering(o, field_sheet)  # one number and label per station, in every section below
    how = numbering.legend
    figs = "".join(
        _img(png, f"plan {name}: coverage count and best incidence; {how}") for name, png in plan_pngs(o, numbering)
    )
    if o.network is not None:
        what = "registration links, sight lines, control points and error ellipses"
        figs += _img(png_bytes(network_figure(o, numbering=numbering)), f"{what}; {how}")
    m = o.meta
    title = f"Scanner stations for {o.site.name}"
    what = "Field sheet (visiting order, walking route, field time, targets)"
    sheet = f'<p>{what}: <a href="{_e(field)}">{_e(field)}</a>.</p>' if field else ""
    body = [
        f"<h1>{_e(title)}</h1>",
        f"<p>{len(o.stations)} stations by {_e(m.get('method'))} ({_e(_state(m))}"
        + (f", bound {_bound_cell(m)}" if isinstance(m.get("bound"), (int, float)) else "")
        + f"); {o.coverage.percent_length:.3f} % of wall length covered on "
        f"{_e(m.get('parameters', {}).get('target_spacing_m', 1.0))} m pieces. tls-planner {__version__}.</p>",
        f'<p class="numbering">{_e(how[0].upper() + how[1:])}: each station has one number and one label (its id) '
        "in every figure, map, table and file of this plan.</p>",
        sheet,
        "<h2>Site plan</h2>",
        site_plan_html(o, field_sheet, numbering),
        "<h2>Site map</h2>",
        site_map_html(o, field_sheet, numbering),
        view3d_section(o, numbering),
        "<h2>Inputs and parameters</h2>",
        _parameters(o),
        "<h2>Zones and closure</h2>",
        _closure(o),
        "<h2>Stations</h2>",
        _stations(o, numbering),
        "<h2>Comparison of methods</h2>",
        _comparison(o),
        "<h2>Plans</h2>",
        figs,
        "<h2>Network and accuracy check</h2>",
        _network(o),
        "<h2>Verification</h2>",
        _verification(o, numbering),
        hours_section(o),
        surfaces_section(o),
        replan_section(o.meta, numbering.number),
    ]
    return (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">'
        f'<meta name="viewport" content="width=device-width, initial-scale=1"><title>{_e(title)}</title>'
        f"<style>{CSS}</style><script>{SCRIPT}</script></head>"
        f'<body data-station-numbering="{_e(numbering.basis)}">{"".join(body)}</body></html>\n'
    )


def linked_field_sheet(folder: Path | str, field: Path | str | None = None) -> tuple[str | None, dict[str, Any] | None]:
    """The field sheet a report in ``folder`` links: its address relative to ``folder`` and its ``field.json``
    (None, None: none). ``field``: the folder holding field.html, else ``folder`` itself where one was written
    before."""
    out = Path(folder)
    sheet = Path(field) / "field.html" if field else out / "field.html"
    if not sheet.is_file():
        return None, None
    link = os.path.relpath(sheet.resolve(), out.resolve()).replace(os.sep, "/")
    return link, read_field_sheet(sheet.parent)


def _state(meta: Mapping[str, Any]) -> str:
    """The plan's status in the words of its summary headline (:func:`planner.solve.result.state_words`)."""
    try:
        return state_words(Status(meta.get("status")), meta.get("bound_scope"))
    except ValueError:
        return str(meta.get("status", ""))


def write_report(o: Outcome, folder: Path | str, field: Path | str | None = None) -> Path:
    """Write ``folder/report.html`` and return its path. It links the field sheet ``field`` (a folder holding
    field.html), or ``folder/field.html`` where one was written before (:func:`linked_field_sheet`), and numbers
    the stations in that sheet's walking order, else as the plan records."""
    argument(o, Outcome, "outcome")
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "report.html"
    link, sheet = linked_field_sheet(out, field)
    path.write_text(render_report(o, link, sheet))
    return path
