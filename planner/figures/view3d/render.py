"""A :class:`~planner.figures.view3d.model.Scene3D` as one self-contained HTML fragment (:func:`render_view3d`): a
``<canvas>``, its controls, the scene as JSON in a ``<script type="application/json">`` element and ``view3d.js``
(package data) inlined; no library, no address.

The JSON is compact (arrays, not objects; metres to the centimetre): ``zones`` [id, frame, side, floor], ``walls``
[zone, wall, x0, y0, x1, y1, floor, top at start, top at end], ``surfaces`` [zone, "f"|"c", level, [flat x, y ring,
...]], ``stations`` [id, label, zone, x, y, floor, z, [[wall, s0, s1, pieces], ...]], ``views`` [name, [zones]],
``covered`` [[wall, s0, s1, pieces], ...] (the union, shown while no station is selected).
"""

from __future__ import annotations

import html
import json
from typing import Any

from planner.figures.view3d.model import Covered, Scene3D
from planner.figures.webmap.render import asset

CSS = (
    ".v3d{margin:0.5em 0 1.5em}.v3d canvas{width:100%;height:560px;max-height:75vh;border:1px solid #ccc;"
    "touch-action:none;cursor:grab;display:block;background:#fbfbf8}.v3-bar{display:flex;flex-wrap:wrap;gap:0.4em 1em;"
    "align-items:center;font-size:0.9em;margin:0.3em 0}.v3-bar button{min-width:2.2em}.v3-info{font-size:0.9em;"
    "margin:0.3em 0}.v3-help{font-size:0.85em;color:#555;margin:0.2em 0}"
)


def _m(v: float) -> float | int:
    """Metres to the centimetre, an integer where it is one (shorter JSON)."""
    r = round(float(v), 2)
    return int(r) if r == int(r) else r


def _cov(c: Covered) -> list[Any]:
    return [c.wall, _m(c.s0_m), _m(c.s1_m), c.pieces]


def scene_json(s: Scene3D) -> str:
    """The scene as the compact JSON the script reads (see the module's doc), safe inside a ``<script>``."""
    data = {
        "title": s.title,
        "ih": s.instrument_height_m,
        "zones": [[z.id, z.frame, z.side, _m(z.floor_m)] for z in s.zones],
        "walls": [[w.zone, w.wall, *map(_m, (*w.a, *w.b, w.floor_m, w.top_a_m, w.top_b_m))] for w in s.walls],
        "surfaces": [
            [f.zone, f.kind[0], _m(f.level_m), [[_m(v) for p in r for v in p] for r in f.rings]] for f in s.surfaces
        ],
        "stations": [
            [t.id, t.label, t.zone, _m(t.x), _m(t.y), _m(t.floor_m), _m(t.z_m), [_cov(c) for c in t.covered]]
            for t in s.stations
        ],
        "views": [[v.name, list(v.zones)] for v in s.views],
        "covered": [_cov(c) for c in s.covered],
    }
    text = json.dumps(data, separators=(",", ":"), ensure_ascii=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def render_view3d(s: Scene3D, dom_id: str = "view-3d") -> str:
    """The 3-D view of ``s`` as an HTML fragment (a ``<div class="v3d">``: style, controls, canvas, a line that says
    what is highlighted (its ``data-pieces``: the wall pieces shown green), the scene and the script).

    The fragment contains no URL. A page's script can select a station with
    ``document.getElementById(dom_id).v3dSelect(station_id)`` (an unknown id: all stations)."""
    label = html.escape(f"3-D view of {s.title}", quote=True)
    ceilings = any(f.kind == "ceiling" for f in s.surfaces)
    ceil = f'<label{"" if ceilings else " hidden"}><input type="checkbox" class="v3-ceil" checked> ceilings</label>'
    return (
        f'<div class="v3d" id="{html.escape(dom_id, quote=True)}"><style>{CSS}</style><div class="v3-bar">'
        '<label>storey <select class="v3-view"></select></label>'
        '<label>station <select class="v3-station"></select></label>'
        f"{ceil}"
        '<span><button type="button" data-v3="in" title="zoom in">+</button>'
        '<button type="button" data-v3="out" title="zoom out">&minus;</button>'
        '<button type="button" data-v3="top" title="plan view from above">top</button>'
        '<button type="button" data-v3="reset" title="first view">reset</button></span></div>'
        f'<canvas width="900" height="560" role="img" aria-label="{label}"></canvas>'
        '<p class="v3-info" aria-live="polite"></p>'
        '<p class="v3-help">Drag to rotate; wheel or +/&minus; to zoom. Walls grey, floors beige, ceilings dashed '
        "purple; green: the wall the stations cover, or the selected station's (pick it in the list or click it); "
        "stations stand at instrument height above their floor.</p>"
        f'<script type="application/json" class="v3-data">{scene_json(s)}</script>'
        f"<script>{asset('view3d.js', 'planner.figures.view3d')}</script></div>"
    )
