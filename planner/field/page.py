"""field.html: the print-ready field sheet as one page: the summary, the interactive site map
(:mod:`planner.field.site_map`; on screen only, not printed), the plan figure embedded as a PNG, one row per
setup (row ``n`` has the id :func:`~planner.field.site_map.setup_row_id` ``(n)``, which the map links to), the
legs that cross a wall and each link's target geometry. No address: the page works from a file, offline."""

from __future__ import annotations

import base64
import html
from typing import Any

from planner import __version__
from planner.field.crossing import advice
from planner.field.figure import figure
from planner.field.run import FieldPlan
from planner.field.site_map import field_map_html, setup_row_id
from planner.field.spread import MIN_ANGLE_DEG, MIN_SPREAD_M
from planner.field.tables import HEADER, rows
from planner.figures.base import png_bytes

CSS = """body{font-family:system-ui,sans-serif;margin:1.5em;color:#111;max-width:1100px}
table{border-collapse:collapse;font-size:0.85em;margin:0.5em 0 1em}th,td{border:1px solid #999;padding:2px 6px;text-align:right}
th{background:#eee}td.l,th.l{text-align:left}img{max-width:100%}h1{font-size:1.4em}h2{font-size:1.1em}
@media print{body{margin:0;max-width:none}figure{page-break-after:always}tr{page-break-inside:avoid}a{color:#111}
section.site-map{display:none}}"""
SCRIPT = (
    "window.addEventListener('load',function(){var im=document.images,ok=0;for(var i=0;i<im.length;i++)"
    "{if(im[i].complete&&im[i].naturalWidth>0)ok++;}document.body.setAttribute('data-images-ok',ok+'/'+im.length);});"
)


def _e(v: Any) -> str:
    return html.escape(str(v))


def render_html(fp: FieldPlan, png: bytes | None = None, site_map: str | None = None) -> str:
    """field.html as one string.

    Parameters
    ----------
    fp
        The field sheet.
    png
        The plan figure as PNG bytes; None: drawn here (:func:`planner.field.figure.figure`).
    site_map
        The site map fragment; None: made here (:func:`planner.field.site_map.field_map_html`).
    """
    png = png if png is not None else png_bytes(figure(fp))
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
    sessions = "".join(
        f"<li>session {s.number}: setups {s.setups[0]}-{s.setups[-1]}, {s.duration_s / 60:.0f} min</li>"
        for s in t.sessions
    )
    targets = "".join(
        f"<tr><td class=l>{_e(x.id)}</td><td class=l>{_e(x.kind)}</td><td>{x.x:.2f}</td><td>{x.y:.2f}</td>"
        f"<td class=l>{_e(x.where)}</td><td class=l>{_e(' '.join(x.seen_by))}</td></tr>"
        for x in fp.targets
    )
    weak = [lk for lk in fp.links if lk.weak]
    note = (
        f"<p>{len(weak)} weak link(s) left without 3 common targets:</p><ul>"
        + "".join(f"<li>{_e(lk.a)} - {_e(lk.b)}: {_e(lk.reason)}</li>" for lk in weak)
        + "</ul>"
        if weak
        else ""
    )
    title = f"Field sheet: {fp.site.name}"
    walls = _walls_html(fp)
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
        f"<table><tr>{head}</tr>{body}{totals}</table>",
        f"<ul>{sessions}</ul>",
        walls,
        _storeys_html(fp),
        "<h2>Registration targets</h2>",
        (
            f"<table><tr><th class=l>target</th><th class=l>kind</th><th>x m</th><th>y m</th><th class=l>where</th>"
            f"<th class=l>seen by</th></tr>{targets}</table>"
            if targets
            else "<p>No targets needed.</p>"
        ),
        _geometry_html(fp),
        note,
    ]
    return (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>{_e(title)}</title>'
        f"<style>{CSS}</style><script>{SCRIPT}</script></head><body>{''.join(parts)}</body></html>\n"
    )


def _storeys_html(fp: FieldPlan) -> str:
    """Across storeys: the frames walked through and one row per stair leg of the route; "" for one frame."""
    if not fp.spaces:
        return ""
    from planner.field.storeys import climbs

    body = "".join(
        f"<tr><td>{k + 1 if k < len(fp.order) else 'back to the start'}</td><td class=l>{_e(f.stair)}</td>"
        f"<td class=l>{_e(climbs(f, fp.leg_frames[k]))}</td><td class=l>{_e(f.lower)}</td><td class=l>{_e(f.upper)}</td>"
        f"<td>{f.run_m:.1f}</td><td>{f.rise_m:.1f}</td><td>{f.length_m:.1f}</td></tr>"
        for k, f in fp.stair_legs
    )
    names = ", ".join(sp.frame for sp in fp.spaces)
    table = (
        f"<table><tr><th>to setup</th><th class=l>stair</th><th class=l>way</th><th class=l>lower storey</th>"
        f"<th class=l>upper storey</th><th>run m</th><th>rise m</th><th>m</th></tr>{body}</table>"
        if body
        else "<p>The route takes no stair.</p>"
    )
    return (
        f"<h2>Across storeys</h2><p>The route walks through {len(fp.spaces)} storeys ({_e(names)}); a stair leg goes "
        f"from the stair's foot to its head, its length the run in plan plus the rise (counted in the route and the "
        f"walking time). One plan panel per storey.</p>{table}"
    )


def _walls_html(fp: FieldPlan) -> str:
    """The legs that cross a wall (no opening in the model), with the advice; "" where none does."""
    if not fp.crossings:
        return ""
    body = "".join(
        f"<tr><td>{_e(c.setup if c.setup is not None else '')}</td><td class=l>{_e(c.start)}</td>"
        f"<td class=l>{_e(c.end)}</td><td>{c.length_m:.1f}</td><td class=l>{_e(', '.join(c.zones))}</td>"
        f"<td class=l>{_e(' | '.join(c.parts))}</td></tr>"
        for c in fp.crossings
    )
    return (
        f"<h2>Legs that cross a wall</h2><p>{_e(advice(fp.crossings))}. Each is a straight line (dashed on the "
        f"plan); its length counts in the route.</p><table><tr><th>to setup</th><th class=l>from</th>"
        f"<th class=l>to</th><th>m</th><th class=l>walls of zones</th><th class=l>parts joined</th></tr>{body}</table>"
    )


def _geometry_html(fp: FieldPlan) -> str:
    """Each link with targets: its targets' smallest pairwise distance and smallest triangle angle."""
    done = [lk for lk in fp.links if lk.targets]
    if not done:
        return ""
    body = "".join(
        f"<tr><td class=l>{_e(lk.a)} - {_e(lk.b)}</td><td class=l>{_e(' '.join(lk.targets))}</td>"
        f"<td>{'' if lk.spread_m is None else f'{lk.spread_m:.2f}'}</td>"
        f"<td>{'' if lk.min_angle_deg is None else f'{lk.min_angle_deg:.0f}'}</td><td class=l>{_e(lk.spread_note)}</td></tr>"
        for lk in done
    )
    return (
        f"<p>Target geometry per link (three targets spread: the largest smallest distance with every angle of "
        f"their triangle at least {MIN_ANGLE_DEG:g} deg; at least {MIN_SPREAD_M:g} m apart where the places "
        f"allow):</p><table><tr><th class=l>link</th><th class=l>targets</th><th>smallest distance m</th>"
        f"<th>smallest angle deg</th><th class=l>note</th></tr>{body}</table>"
    )
