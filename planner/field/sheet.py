"""The field sheet's files: ``field.html`` (print-ready: the plan with numbered stations and the route, one
row per setup, totals), ``field.csv`` (the same rows), ``field.geojson`` (stations in order, the route
line, the targets; frame coordinates in metres) and ``field.json`` (order, route, bound, gap, mode,
field time, sessions, targets, links)."""

from __future__ import annotations

import base64
import csv
import html
import io
from pathlib import Path
from typing import Any

from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from planner import __version__
from planner.core.text import dumps
from planner.field.run import FieldPlan
from planner.figures.base import decorate_plan, png_bytes

HEADER = (
    "no.",
    "station",
    "x m",
    "y m",
    "zone",
    "side",
    "instrument height m",
    "scan setting",
    "walk m",
    "minutes",
    "targets seen",
    "session",
)
CSS = """body{font-family:system-ui,sans-serif;margin:1.5em;color:#111;max-width:1100px}
table{border-collapse:collapse;font-size:0.85em;margin:0.5em 0 1em}th,td{border:1px solid #999;padding:2px 6px;text-align:right}
th{background:#eee}td.l,th.l{text-align:left}img{max-width:100%}h1{font-size:1.4em}h2{font-size:1.1em}
@media print{body{margin:0;max-width:none}figure{page-break-after:always}tr{page-break-inside:avoid}a{color:#111}}"""
SCRIPT = (
    "window.addEventListener('load',function(){var im=document.images,ok=0;for(var i=0;i<im.length;i++)"
    "{if(im[i].complete&&im[i].naturalWidth>0)ok++;}document.body.setAttribute('data-images-ok',ok+'/'+im.length);});"
)


def rows(fp: FieldPlan) -> list[list[Any]]:
    """One row per setup in visiting order (the columns of :data:`HEADER`)."""
    out = []
    for setup, k in zip(fp.time.setups, fp.order):
        s = fp.stations[k]
        out.append(
            [
                setup.number,
                s.id,
                round(s.x, 3),
                round(s.y, 3),
                s.zone,
                s.side.value,
                fp.instrument_height_m,
                fp.time.setting,
                round(setup.walk_m, 1),
                round(setup.total_s / 60.0, 1),
                " ".join(fp.targets_of(s.id)),
                setup.session,
            ]
        )
    return out


def to_dict(fp: FieldPlan) -> dict[str, Any]:
    """field.json."""
    o = fp.options
    return {
        "instance": fp.site.name,
        "mode": o.mode,
        "closed": o.closed,
        "start": fp.start_label,
        "start_xy": list(fp.start_xy),
        "order": [fp.stations[k].id for k in fp.order],
        "route_length_m": fp.route_length_m,
        "lower_bound_m": fp.lower_bound_m,
        "bound_method": fp.bound_method,
        "bound_scope": fp.certified.scope if fp.certified else "shortest route",
        "bounds": {m: b for m, b in fp.certified.bounds} if fp.certified else {},
        "gap": fp.gap,
        "nearest_neighbour_m": fp.nearest_neighbour_m,
        "registration_order_honoured": fp.registration_ok,
        "search_capped": fp.capped,
        "legs": [[list(p) for p in leg] for leg in fp.legs],
        "field_time_s": fp.time.total_s,
        "time": fp.time.to_dict(),
        "sessions": fp.time.to_dict()["sessions"],
        "setups": [dict(zip(HEADER, r)) for r in rows(fp)],
        "targets": [
            {
                "id": t.id,
                "kind": t.kind,
                "x": t.x,
                "y": t.y,
                "where": t.where,
                "seen_by": list(t.seen_by),
                "links": [list(p) for p in t.links],
            }
            for t in fp.targets
        ],
        "links": [
            {
                "a": lk.a,
                "b": lk.b,
                "shared_m": lk.shared_m,
                "fraction": lk.fraction,
                "weak": lk.weak,
                "targets": list(lk.targets),
                "target_places": lk.places,
                "apart_m": lk.apart_m,
                "weak_reason": lk.reason,
            }
            for lk in fp.links
        ],
        "instrument_height_m": fp.instrument_height_m,
        "solve_s": fp.solve_s,
        "version": __version__,
    }


def figure(fp: FieldPlan) -> Figure:
    """The plan: walls (solid parts), obstacles, no-go areas, the route, numbered stations and the targets."""
    fig = Figure(figsize=(11, 8), layout="constrained")
    ax = fig.subplots()
    walls = [list(w) for w in fp.space.solid_walls]
    ax.add_collection(LineCollection(walls, colors="black", linewidths=1.2, label="wall"))
    site = fp.site
    if fp.space.frame == "site":
        for ob in site.obstacles:
            ax.add_patch(Polygon(ob.vertices, closed=True, fc="0.6", ec="0.3", alpha=0.6))
        for a in site.no_go_areas:
            ax.add_patch(Polygon(a.vertices, closed=True, fc="mistyrose", ec="red", hatch="//", alpha=0.5))
    for k, leg in enumerate(fp.legs):
        if len(leg) > 1:
            xs, ys = zip(*leg)
            ax.plot(xs, ys, color="tab:blue", lw=1.4, alpha=0.8, label="route" if k == 1 or len(fp.legs) == 1 else None)
    ax.plot(*fp.start_xy, marker="*", ms=14, color="tab:green", ls="none", label=f"start: {fp.start_label}")
    for n, k in enumerate(fp.order, 1):
        s = fp.stations[k]
        ax.plot(s.x, s.y, "o", ms=13, mfc="white", mec="black", ls="none")
        ax.annotate(str(n), (s.x, s.y), ha="center", va="center", fontsize=7, fontweight="bold")
    for t in fp.targets:
        ax.plot(t.x, t.y, marker="x" if t.kind != "control" else "^", color="tab:red", ms=6, ls="none")
        ax.annotate(t.id, (t.x, t.y), xytext=(3, -8), textcoords="offset points", fontsize=6, color="tab:red")
    decorate_plan(ax, fp.space.frame)
    ax.legend(loc="lower right", fontsize=7, framealpha=0.8)
    ax.set_title(
        f"{site.name}: {len(fp.order)} setups, {fp.options.mode} order, route {fp.route_length_m:.0f} m "
        f"(bound {fp.lower_bound_m:.0f} m, gap {100 * fp.gap:.1f} %)"
    )
    return fig


def _e(v: Any) -> str:
    return html.escape(str(v))


def render_html(fp: FieldPlan, png: bytes | None = None) -> str:
    """field.html as one string (the figure embedded)."""
    png = png if png is not None else png_bytes(figure(fp))
    head = "".join(
        f'<th class="{"l" if c in ("station", "zone", "side", "scan setting", "targets seen") else ""}">{_e(c)}</th>'
        for c in HEADER
    )
    body = "".join(
        "<tr>" + "".join(f'<td class="{"l" if isinstance(v, str) else ""}">{_e(v)}</td>' for v in r) + "</tr>"
        for r in rows(fp)
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
            f'<figure><img alt="plan with route" src="data:image/png;base64,{base64.b64encode(png).decode()}">'
            f"<figcaption>Stations numbered in visiting order, the walking route, targets (T).</figcaption></figure>"
        ),
        "<h2>Setups</h2>",
        f"<table><tr>{head}</tr>{body}{totals}</table>",
        f"<ul>{sessions}</ul>",
        "<h2>Registration targets</h2>",
        (
            f"<table><tr><th class=l>target</th><th class=l>kind</th><th>x m</th><th>y m</th><th class=l>where</th>"
            f"<th class=l>seen by</th></tr>{targets}</table>"
            if targets
            else "<p>No targets needed.</p>"
        ),
        note,
    ]
    return (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>{_e(title)}</title>'
        f"<style>{CSS}</style><script>{SCRIPT}</script></head><body>{''.join(parts)}</body></html>\n"
    )


def geojson(fp: FieldPlan) -> dict[str, Any]:
    """Stations in order (Points), the route (LineString) and targets, in the frame's metres."""
    feats: list[dict[str, Any]] = []
    for n, k in enumerate(fp.order, 1):
        s = fp.stations[k]
        feats.append(
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [s.x, s.y]},
                "properties": {
                    "role": "station",
                    "number": n,
                    "id": s.id,
                    "zone": s.zone,
                    "side": s.side.value,
                    "targets": fp.targets_of(s.id),
                },
            }
        )
    line: list[list[float]] = []
    for leg in fp.legs:
        for p in leg:
            if not line or line[-1] != list(p):
                line.append(list(p))
    feats.append(
        {
            "type": "Feature",
            "geometry": {"type": "LineString", "coordinates": line},
            "properties": {"role": "route", "length_m": fp.route_length_m, "mode": fp.options.mode},
        }
    )
    for t in fp.targets:
        feats.append(
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [t.x, t.y]},
                "properties": {"role": "target", "id": t.id, "kind": t.kind, "seen_by": list(t.seen_by)},
            }
        )
    return {
        "type": "FeatureCollection",
        "name": f"{fp.site.name} field sheet",
        "frame": fp.space.frame,
        "features": feats,
    }


def write_sheet(fp: FieldPlan, folder: Path | str) -> list[Path]:
    """Write field.html, field.csv, field.geojson and field.json into ``folder``; return their paths."""
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / f"field.{ext}" for ext in ("html", "csv", "geojson", "json")]
    paths[0].write_text(render_html(fp))
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(HEADER)
    w.writerows(rows(fp))
    paths[1].write_text(buf.getvalue())
    paths[2].write_text(dumps(geojson(fp)))
    paths[3].write_text(dumps(to_dict(fp)))
    return paths
