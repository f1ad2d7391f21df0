"""A :class:`~planner.figures.webmap.model.SiteMap` as one self-contained HTML fragment (:func:`render_site_map`):
inline SVG, a small inline style sheet and script, no external file, library or address.

Frames: one ``<svg>`` holds one group per frame; a selector shows one frame at a time (the one with the most stations
first), so a site of table zones, each in its own local frame, is one map per frame behind the selector rather than a
long stack of maps. Layers are groups that checkboxes switch on and off. Coordinates are written in centimetres with y
turned down (SVG's axis). Markers are drawn in pixels: the script scales them with the zoom. Per station the fragment
holds one group of covered runs (hidden until the station is selected), so its size grows with stations x runs, not with
wall pieces.
"""

from __future__ import annotations

import html
from collections import Counter
from collections.abc import Iterable
from functools import cache
from importlib.resources import files

from planner.figures.webmap.edit import TOGGLE, edit_controls
from planner.figures.webmap.model import MapArea, MapLine, MapPoint, MapStation, Point, SiteMap

#: layers in drawing order (later on top), each named on its checkbox, and the checkbox's tooltip
LAYERS = (
    ("walls", "zones' walls, openings (orange), obstacles, no-go areas, boundary"),
    ("floors", "the floor (blue) and ceiling (purple) the selected station covers"),
    ("coverage", "the wall the selected station covers (green)"),
    ("links", "registration links between stations (selected: red)"),
    (
        "route",
        "the field walking route (dashed) from its start (square); legs through a wall, where the model has no "
        "opening: orange, short dashes",
    ),
    ("traverse", "control traverse legs (total station)"),
    ("control", "control points (proposed: open triangles)"),
    ("targets", "registration targets"),
    ("stations", "stations, numbered as in every table and figure of the plan"),
)
#: layers drawn but switched off at first (dense on large sites)
FIRST_OFF = frozenset({"traverse"})
#: the pixel width the markers are first drawn for, before the script measures the map
FIRST_WIDTH_PX = 900.0
OFF = ' style="display:none"'


@cache
def asset(name: str, package: str = "planner.figures.webmap") -> str:
    """The text of a package data file (``site_map.js``, ``site_map.css``; ``view3d.js`` of the 3-D view's)."""
    return files(package).joinpath(name).read_text(encoding="utf-8")


def _e(v: object) -> str:
    return html.escape(str(v), quote=True)


def _c(v: float) -> str:
    """A coordinate in metres to the centimetre, without trailing zeros."""
    s = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _xy(p: Point) -> str:
    return f"{_c(p[0])},{_c(-p[1])}"


def _line(ln: MapLine, cls: str) -> str:
    pts = " ".join(map(_xy, ln.points))
    tag = "polygon" if ln.closed else "polyline"
    title = f"<title>{_e(ln.label)}</title>" if ln.label else ""
    return f'<{tag} class="{cls}" points="{pts}">{title}</{tag}>'


def _marker(p: MapPoint, scale: float, body: str) -> str:
    return (
        f'<g class="sm-mk sm-{_e(p.kind)}" data-x="{_c(p.x)}" data-y="{_c(p.y)}" '
        f'transform="translate({_xy((p.x, p.y))}) scale({scale:.4g})">{body}<title>{_e(p.label or p.id)}</title></g>'
    )


def _point(p: MapPoint, scale: float) -> str:
    if p.kind in ("control", "proposed"):
        return _marker(p, scale, '<path d="M0,-8L7,5H-7Z"/>')
    if p.kind == "checkerboard":
        return _marker(p, scale, '<rect x="-4" y="-4" width="8" height="8"/>')
    if p.kind == "start":
        return _marker(p, scale, '<path d="M-6,-6H6V6H-6Z" class="sm-start"/>')
    return _marker(p, scale, '<circle r="4"/>')


def _station(s: MapStation, dom_id: str, k: int, scale: float) -> str:
    floors = {"data-fn": sum(a.patches for a in s.areas), "data-fm2": f"{sum(a.area_m2 for a in s.areas):.1f}"}
    attrs = {
        "data-id": s.id,
        "data-frame": s.frame,
        "data-x": _c(s.x),
        "data-y": _c(s.y),
        "data-zone": s.zone,
        "data-side": s.side,
        "data-kind": s.kind,
        "data-n": s.pieces,
        "data-runs": len(s.runs),
        "data-m": f"{s.covered_m:.1f}",
        "data-row": s.row,
        "data-visit": s.visit,
        "data-station-number": s.number or "",
        "data-station-label": s.name,
        **(floors if s.areas else {}),
    }
    a = " ".join(f'{name}="{_e(v)}"' for name, v in attrs.items() if v != "")
    return (
        f'<g class="sm-st sm-mk" id="{_e(dom_id)}-st-{k}" tabindex="0" role="button" {a} '
        f'transform="translate({_xy((s.x, s.y))}) scale({scale:.4g})"><circle class="sm-hit" r="15"/>'
        f'<circle r="7"/><text x="9" y="-8">{_e(s.label)}</text><title>{_e(s.id)}</title></g>'
    )


def _runs(s: MapStation) -> str:
    lines = "".join(
        f'<line x1="{_c(r.a[0])}" y1="{_c(-r.a[1])}" x2="{_c(r.b[0])}" y2="{_c(-r.b[1])}" data-n="{r.pieces}">'
        f"<title>{_e(r.label)}</title></line>"
        for r in s.runs
    )
    return f'<g class="sm-cv" data-st="{_e(s.id)}">{lines}</g>'


def _area(a: MapArea) -> str:
    d = "".join("M" + " ".join(map(_xy, ring)) + "Z" for ring in a.rings)
    return (
        f'<path class="sm-{_e(a.kind)}" d="{d}" data-n="{a.patches}" data-m2="{a.area_m2:.2f}">'
        f"<title>{_e(a.label)}</title></path>"
    )


def _areas(s: MapStation) -> str:
    return f'<g class="sm-fl" data-st="{_e(s.id)}">{"".join(map(_area, s.areas))}</g>'


def _box(points: Iterable[Point]) -> tuple[float, float, float, float]:
    """The viewBox (in SVG units, y down) of the points with a margin of 4 %."""
    pts = list(points)
    if not pts:
        return (-1.0, -1.0, 2.0, 2.0)
    xs, ys = [p[0] for p in pts], [-p[1] for p in pts]
    w, h = max(xs) - min(xs), max(ys) - min(ys)
    pad = 0.04 * max(w, h, 1.0)
    return (min(xs) - pad, min(ys) - pad, w + 2 * pad, h + 2 * pad)


def _frame(m: SiteMap, frame: str, dom_id: str, shown: bool) -> tuple[str, tuple[float, float, float, float]]:
    """One frame's group (its layers) and its viewBox."""
    walls = [w for w in m.walls if w.frame == frame]
    st = [(k, s) for k, s in enumerate(m.stations, 1) if s.frame == frame]
    ids = {s.id for _, s in st}
    route = [r for r in m.route if r.frame == frame]
    targets = [t for t in m.targets if t.frame == frame]
    control = [c for c in m.control if c.frame == frame]
    traverse = [t for t in m.traverse if t.frame == frame]
    start = [m.start] if m.start is not None and m.start.frame == frame else []
    pts = [p for ln in walls + route + traverse for p in ln.points]
    pts += [(s.x, s.y) for _, s in st] + [(p.x, p.y) for p in targets + control + start]
    box = _box(pts)
    scale = max(box[2], box[3]) / FIRST_WIDTH_PX
    at = {s.id: (s.x, s.y) for _, s in st}
    body = {
        "walls": "".join(_line(w, f"sm-{w.kind}") for w in walls),
        "floors": "".join(_areas(s) for _, s in st if s.areas),
        "coverage": "".join(_runs(s) for _, s in st if s.runs),
        "links": "".join(
            f'<line class="sm-lk{" weak" if lk.weak else ""}" data-a="{_e(lk.a)}" data-b="{_e(lk.b)}"'
            + ("" if lk.shared_m is None else f' data-s="{lk.shared_m:.1f}"' if lk.shared_m > 0 else ' data-o="1"')
            + (f' data-f="{lk.fraction:.2f}"' if lk.fraction is not None else "")
            + f' x1="{_c(at[lk.a][0])}" y1="{_c(-at[lk.a][1])}" x2="{_c(at[lk.b][0])}" y2="{_c(-at[lk.b][1])}"/>'
            for lk in m.links
            if lk.a in ids and lk.b in ids
        ),
        "route": "".join(_line(r, "sm-route" + (" sm-through" if r.kind == "through" else "")) for r in route)
        + "".join(_point(p, scale) for p in start),
        "traverse": "".join(_line(t, "sm-trav") for t in traverse),
        "control": "".join(_point(p, scale) for p in control),
        "targets": "".join(_point(p, scale) for p in targets),
        "stations": "".join(_station(s, dom_id, k, scale) for k, s in st),
    }
    groups = "".join(
        f'<g class="sm-L" data-layer="{name}"{OFF if name in FIRST_OFF else ""}>{body[name]}</g>'
        for name, _ in LAYERS
        if body[name]
    )
    hide = "" if shown else OFF
    return (
        f'<g class="sm-fr" data-frame="{_e(frame)}" data-box="{" ".join(_c(v) for v in box)}"{hide}>{groups}</g>',
        box,
    )


def _present(m: SiteMap) -> list[tuple[str, str]]:
    has = {
        "walls": bool(m.walls),
        "floors": any(s.areas for s in m.stations),
        "coverage": any(s.runs for s in m.stations),
        "links": bool(m.links),
        "route": bool(m.route),
        "traverse": bool(m.traverse),
        "control": bool(m.control),
        "targets": bool(m.targets),
        "stations": True,
    }
    return [layer for layer in LAYERS if has[layer[0]]]


def render_site_map(m: SiteMap, dom_id: str = "site-map", table: str = "station table", edit: bool = False) -> str:
    """The interactive map of ``m`` as an HTML fragment (a ``<div class="smap">`` holding its style sheet, the controls,
    the SVG, the station panel and the script), for any page's ``<body>``.

    ``dom_id``: the fragment's HTML id (station elements are ``{dom_id}-st-{k}``, k the station's 1-based place in
    ``m.stations``); give each map of a page its own. The fragment contains no URL: it works from a file, offline, and
    in a mail attachment. A page's own script can select a station with
    ``document.getElementById(dom_id).smapSelect(station_id)``; a station whose ``row`` names an element of the page
    marks it (class ``sm-row``) when selected, and a click on that element selects the station; ``table``: what the help
    line and the station panel call the page's table of those rows; ``edit``: add the field sheet's edit mode (an
    "edit" toggle and its panel under the map, :mod:`~planner.figures.webmap.edit`), which saves ``edits.json``.
    """
    per_frame = Counter(s.frame for s in m.stations)
    first = max(m.frames, key=lambda f: per_frame.get(f, 0)) if m.frames else ""
    parts = {f: _frame(m, f, dom_id, f == first) for f in m.frames}
    frames = "".join(g for g, _ in parts.values())
    box = parts[first][1] if first in parts else _box([])
    view = " ".join(_c(v) for v in box)
    select = ""
    if len(m.frames) > 1:
        opts = "".join(
            f'<option value="{_e(f)}"{" selected" if f == first else ""}>{_e(f)} ({per_frame.get(f, 0)} stations)'
            "</option>"
            for f in m.frames
        )
        select = f'<label>frame <select class="sm-frame">{opts}</select></label>'
    boxes = "".join(
        f'<label title="{_e(tip)}"><input type="checkbox" data-layer="{name}"'
        f"{'' if name in FIRST_OFF else ' checked'}> {_e(name)}</label>"
        for name, tip in _present(m)
    )
    zoom = (
        '<span class="sm-zoom"><button type="button" data-zoom="in" title="zoom in">+</button>'
        '<button type="button" data-zoom="out" title="zoom out">&minus;</button>'
        '<button type="button" data-zoom="fit" title="whole frame">fit</button></span>'
    )
    floors = ", the floor and ceiling it covers" if any(s.areas for s in m.stations) else ""
    shows = f"the wall it covers{floors}, its links" + (
        f" and its row in the {table} (a click on a row shows its station here)"
        if any(s.row for s in m.stations)
        else ""
    )
    label = _e(f"site map of {m.title}")
    tool, panel, help_edit, style, script = "", "", "", "", ""
    if edit:
        tool, panel = TOGGLE, edit_controls(m)
        help_edit = " Edit: mark what changed on site and save edits.json for planner replan."
        style, script = asset("site_map_edit.css"), f"<script>{asset('site_map_edit.js')}</script>"
    numbering = (
        f'<span class="sm-numbering">{_e(m.numbering[0].upper() + m.numbering[1:])}. </span>' if m.numbering else ""
    )
    return (
        f'<div class="smap" id="{_e(dom_id)}" data-first="{_e(first)}" data-table="{_e(table)}">'
        f"<style>{asset('site_map.css')}{style}</style>"
        f'<div class="sm-bar">{select}{boxes}{zoom}{tool}</div><div class="sm-wrap">'
        f'<svg class="sm-svg" style="aspect-ratio:{_c(box[2])}/{_c(box[3])}" aria-label="{label}" '
        f'viewBox="{view}" preserveAspectRatio="xMidYMid meet">{frames}</svg>'
        f'<div class="sm-panel" hidden></div></div>{panel}'
        f'<p class="sm-help">{numbering}Drag to pan; wheel, pinch or +/&minus; to zoom. Tap a station: {shows}.'
        f"{help_edit}</p><script>{asset('site_map.js')}</script>{script}</div>"
    )
