"""field.html: the print-ready field sheet as one page: the summary, the interactive site map
(:mod:`planner.field.site_map`; on screen only, not printed), the plan figure embedded as a PNG, one row per
setup (row ``n`` has the id :func:`~planner.field.site_map.setup_row_id` ``(n)``, which the map links to), the
legs that cross a wall and each link's target geometry. No address: the page works from a file, offline."""

from __future__ import annotations

import base64
import html
from collections.abc import Iterable, Sequence
from typing import Any

from planner import __version__
from planner.field.crossing import advice
from planner.field.figure import figure
from planner.field.record import HEADER, rows
from planner.field.run import FieldPlan
from planner.field.site_map import field_map_html, setup_row_id
from planner.field.spread import MIN_ANGLE_DEG, MIN_SPREAD_M
from planner.field.storeys import climbs
from planner.figures.base import png_bytes

CSS = """html{-webkit-text-size-adjust:100%;text-size-adjust:100%}
body{font-family:system-ui,sans-serif;margin:1.5em;color:#111;max-width:1100px}
table{border-collapse:collapse;font-size:0.85em;margin:0.5em 0 1em}th,td{border:1px solid #999;padding:2px 6px;text-align:right}
th{background:#eee}td.l,th.l{text-align:left}img{max-width:100%}h1{font-size:1.4em}h2{font-size:1.1em}
.wide{max-width:100%;overflow-x:auto}p,li,figcaption{overflow-wrap:anywhere}
@media print{body{margin:0;max-width:none}figure{page-break-after:always}tr{page-break-inside:avoid}a{color:#111}
section.site-map{display:none}.wide{overflow:visible}}"""
# On a phone the setup table turns into one card per setup: each cell on its own, after its column's name (the
# names come from the style sheet, so the table's markup stays the same for print, the PDF and the tests).
CARDS = (
    "@media screen and (max-width:640px){body{margin:0.75em}"
    "table.setups,table.setups tbody{display:block;border:0;font-size:0.9em}table.setups tr:first-child{display:none}"
    "table.setups tr{display:grid;grid-template-columns:1fr 1fr;gap:0 0.8em;border:1px solid #999;border-radius:6px;"
    "margin:0 0 0.6em;padding:0.35em 0.55em}"
    "table.setups td,table.setups th{display:block;border:0;padding:1px 0;text-align:left;background:none;"
    "overflow-wrap:anywhere}"
    "table.setups td::before,table.setups th::before{color:#555;font-size:0.85em;font-weight:normal;margin-right:0.4em}"
    "table.setups td:nth-child(2){font-weight:600}table.setups td:nth-child(11),table.setups th:first-child"
    "{grid-column:1/-1}table.setups tr.sm-row{background:#fff2a8}"
    + "".join(f'table.setups td:nth-child({k})::before{{content:"{h}"}}' for k, h in enumerate(HEADER, 1))
    + "".join(
        f'table.setups th:nth-child({k})::before{{content:"{h}"}}'
        for k, h in ((2, HEADER[8]), (3, HEADER[9]), (5, "sessions"))
    )
    + "}"
)
SCRIPT = (
    "window.addEventListener('load',function(){var im=document.images,ok=0;for(var i=0;i<im.length;i++)"
    "{if(im[i].complete&&im[i].naturalWidth>0)ok++;}document.body.setAttribute('data-images-ok',ok+'/'+im.length);});"
)


def _e(v: Any) -> str:
    return html.escape(str(v))


def _table(heads: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """A table: ``heads`` (HTML; a leading "<" marks a left-aligned text column) over ``rows`` (escaped here)."""
    left = [h.startswith("<") for h in heads]
    head = "".join(f"<th class=l>{h[1:]}</th>" if lf else f"<th>{h}</th>" for h, lf in zip(heads, left))
    body = "".join(
        "<tr>" + "".join(f"<td class=l>{_e(v)}</td>" if lf else f"<td>{_e(v)}</td>" for v, lf in zip(r, left)) + "</tr>"
        for r in rows
    )
    return f'<div class="wide"><table><tr>{head}</tr>{body}</table></div>'


def render_html(fp: FieldPlan, png: bytes | None = None, site_map: str | None = None) -> str:
    """field.html as one string; ``png`` (the plan figure) and ``site_map`` (the map fragment) are made here
    where None (:func:`planner.field.figure.figure`, :func:`planner.field.site_map.field_map_html`)."""
    png = png if png is not None else png_bytes(figure(fp))
    title = f"Field sheet: {fp.site.name}"
    targets = [(x.id, x.kind, f"{x.x:.2f}", f"{x.y:.2f}", x.where, " ".join(x.seen_by)) for x in fp.targets]
    t = fp.time
    parts = [
        f"<h1>{_e(title)}</h1>",
        (
            f"<p>{_e(fp.options.mode)} order from {_e(fp.start_label)}; route {fp.route_length_m:.1f} m, lower bound "
            f"{fp.lower_bound_m:.1f} m ({_e(fp.bound_method)}), gap {100 * fp.gap:.2f} %; nearest-neighbour order "
            f"{fp.nearest_neighbour_m:.1f} m. Registration order honoured: {'yes' if fp.registration_ok else 'no'}. "
            f"Field time {t.total_s / 3600:.2f} h ({t.walking_s / 60:.0f} min walking, {t.station_s / 60:.0f} min at "
            f"stations; scan setting {_e(t.setting)}). tls-planner {__version__}.</p>"
        ),
        (
            '<section class="site-map"><h2>Site map</h2>'
            f"{field_map_html(fp) if site_map is None else site_map}</section>"
        ),
        (
            f'<figure><img alt="plan with route" src="data:image/png;base64,{base64.b64encode(png).decode()}">'
            f"<figcaption>Stations numbered in visiting order, the walking route, targets (T).</figcaption></figure>"
        ),
        "<h2>Setups</h2>",
        _setups_html(fp),
        _walls_html(fp),
        _storeys_html(fp),
        "<h2>Registration targets</h2>",
        _table(("<target", "<kind", "x m", "y m", "<where", "<seen by"), targets)
        if targets
        else "<p>No targets needed.</p>",
        _geometry_html(fp),
        _weak_html(fp),
    ]
    return (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">'
        f'<meta name="viewport" content="width=device-width, initial-scale=1"><title>{_e(title)}</title>'
        f"<style>{CSS}{CARDS}</style><script>{SCRIPT}</script></head><body>{''.join(parts)}</body></html>\n"
    )


def _setups_html(fp: FieldPlan) -> str:
    """The setup table (row ``n`` with the id the site map links to), its totals and the sessions."""
    head = "".join(
        f'<th class="{"l" if c in ("station", "zone", "side", "scan setting", "targets seen") else ""}">{_e(c)}</th>'
        for c in HEADER
    )
    body = "".join(
        f'<tr id="{setup_row_id(n)}">'
        + "".join(f'<td class="{"l" if isinstance(v, str) else ""}">{_e(v)}</td>' for v in r)
        + "</tr>"
        for n, r in enumerate(rows(fp), 1)
    )
    t = fp.time
    totals = (
        f"<tr><th class=l colspan=8>total: {len(fp.order)} setups</th><th>{fp.route_length_m:.1f}</th>"
        f"<th>{t.total_s / 60:.1f}</th><th class=l>{len(fp.targets)} targets</th><th>{len(t.sessions)}</th></tr>"
    )
    sessions = "".join(f"<li>{s.label}</li>" for s in t.sessions)
    return f'<div class="wide"><table class="setups"><tr>{head}</tr>{body}{totals}</table></div><ul>{sessions}</ul>'


def _weak_html(fp: FieldPlan) -> str:
    """The links left without three common targets, with the reason; "" where none is."""
    weak = [lk for lk in fp.links if lk.weak]
    if not weak:
        return ""
    items = "".join(f"<li>{_e(lk.a)} - {_e(lk.b)}: {_e(lk.reason)}</li>" for lk in weak)
    return f"<p>{len(weak)} weak link(s) left without 3 common targets:</p><ul>{items}</ul>"


def _storeys_html(fp: FieldPlan) -> str:
    """Across storeys: the frames walked through and one row per stair leg of the route; "" for one frame."""
    if not fp.spaces:
        return ""
    legs = [
        (k + 1 if k < len(fp.order) else "back to the start", f.stair, climbs(f, fp.leg_frames[k]), f.lower, f.upper)
        + (f"{f.run_m:.1f}", f"{f.rise_m:.1f}", f"{f.length_m:.1f}")
        for k, f in fp.stair_legs
    ]
    heads = ("to setup", "<stair", "<way", "<lower storey", "<upper storey", "run m", "rise m", "m")
    names = ", ".join(sp.frame for sp in fp.spaces)
    return (
        f"<h2>Across storeys</h2><p>The route walks through {len(fp.spaces)} storeys ({_e(names)}); a stair leg goes "
        f"from the stair's foot to its head, its length the run in plan plus the rise (counted in the route and the "
        f"walking time). One plan panel per storey.</p>"
        + (_table(heads, legs) if legs else "<p>The route takes no stair.</p>")
    )


def _walls_html(fp: FieldPlan) -> str:
    """The legs that cross a wall (no opening in the model), with the advice; "" where none does."""
    if not fp.crossings:
        return ""
    legs = [
        (
            "" if c.setup is None else c.setup,
            c.start,
            c.end,
            f"{c.length_m:.1f}",
            ", ".join(c.zones),
            " | ".join(c.parts),
        )
        for c in fp.crossings
    ]
    return (
        f"<h2>Legs that cross a wall</h2><p>{_e(advice(fp.crossings))}. Each is a straight line (dashed on the "
        f"plan); its length counts in the route.</p>"
        + _table(("to setup", "<from", "<to", "m", "<walls of zones", "<parts joined"), legs)
    )


def _geometry_html(fp: FieldPlan) -> str:
    """Each link with targets: its targets' smallest pairwise distance and smallest triangle angle."""
    links = [
        (
            f"{lk.a} - {lk.b}",
            " ".join(lk.targets),
            "" if lk.spread_m is None else f"{lk.spread_m:.2f}",
            "" if lk.min_angle_deg is None else f"{lk.min_angle_deg:.0f}",
            lk.spread_note,
        )
        for lk in fp.links
        if lk.targets
    ]
    if not links:
        return ""
    return (
        f"<p>Target geometry per link (three targets spread: the largest smallest distance with every angle of "
        f"their triangle at least {MIN_ANGLE_DEG:g} deg; at least {MIN_SPREAD_M:g} m apart where the places "
        f"allow):</p>" + _table(("<link", "<targets", "smallest distance m", "smallest angle deg", "<note"), links)
    )
