"""The edit mode of the field sheet's map (:func:`edit_controls`): the controls that turn the interactive map into a
form for what the site changed since the plan (stations done, blocked or moved, closed areas, obstacles, closed
zones, where the crew stands, hours left today), saved by the page itself as ``edits.json`` (the re-plan's input,
format ``planner-edits/1``) with a download: no server, no address, so it works from a file, offline, on a phone.

The behaviour is the package data ``site_map_edit.js`` (and its style sheet ``site_map_edit.css``), inlined after the
map's own script, which it reaches through the hooks the map sets on its root element (``smapTap``, ``smapToFrame``,
``smapMark``). Only pages that ask for it (:func:`~planner.figures.webmap.render.render_site_map` with ``edit``) carry
it: report.html's map has none.

Positions are taken in the site's frame only (the coordinates of the edits file and of plan.json: the site's own
frame, or the only frame of a site drawn in one, :attr:`SiteMap.site_frame
<planner.figures.webmap.model.SiteMap.site_frame>`), through the inverse of the screen matrix the map draws with,
rounded to the centimetre the map is written in; in a zone's local frame among several the mode still marks stations
(by number) but takes no point.
"""

from __future__ import annotations

import hashlib
import html

from planner.figures.webmap.model import SiteMap

#: the format tag the saved file carries (the re-plan's reader checks it)
EDITS_FORMAT = "planner-edits/1"
#: the toggle, in the map's bar
TOGGLE = (
    '<button type="button" class="sm-edit" data-act="edit" aria-pressed="false" '
    'title="mark stations done, blocked or moved; draw closed areas and obstacles; save edits.json">edit</button>'
)


def _e(v: object) -> str:
    return html.escape(str(v), quote=True)


def _b(act: str, text: str, title: str = "", attr: str = "data-act") -> str:
    tip = f' title="{_e(title)}"' if title else ""
    return f'<button type="button" {attr}="{_e(act)}"{tip}>{_e(text)}</button>'


def page_key(m: SiteMap) -> str:
    """A short digest of the map's stations (ids and positions): the key under which the page keeps its edits in the
    browser between visits, so that a sheet of another plan of the same site starts empty."""
    text = "\n".join(f"{s.id} {s.frame} {s.x:.2f} {s.y:.2f}" for s in m.stations)
    return hashlib.sha256(f"{m.title}\n{text}".encode()).hexdigest()[:12]


def edit_controls(m: SiteMap) -> str:
    """The edit panel of the map ``m`` (hidden until the toggle :data:`TOGGLE` opens it): the tools, the picked
    station's actions, the drawing's, the zones to close, the hours left, the list of edits with undo, and the save
    button. The saved file names its plan by ``m.title`` (the site's name, which plan.json records as its
    ``instance``), so that the re-plan refuses edits made on another site's sheet."""
    tools = "".join(
        _b(t, text, tip, "data-tool")
        for t, text, tip in (
            ("station", "stations", "tap a station to mark it done, blocked or moved"),
            ("closed", "closed area", "tap the corners of an area closed today, then finish"),
            ("obstacle", "obstacle", "tap the corners of an obstacle, then finish"),
            ("crew", "crew", "tap where the crew stands, or a station"),
        )
    )
    station = (
        '<p class="sm-ed-st" hidden><strong class="sm-ed-name"></strong>'
        + _b("done", "done", "scanned where planned")
        + _b("blocked", "blocked", "cannot stand there today")
        + '<label>radius m <input type="number" class="sm-ed-r" min="0" step="0.1" inputmode="decimal" '
        'placeholder="tripod disc" title="blank: the station\'s tripod disc (at least 0.5 m); 0: the point only">'
        "</label>"
        + _b("moved", "moved", "scanned elsewhere: then tap where it stood")
        + _b("crew-here", "crew here", "the crew stands at this station")
        + "</p>"
    )
    draw = (
        '<p class="sm-ed-draw" hidden><span class="sm-ed-count"></span>'
        '<label>note <input type="text" class="sm-ed-note" maxlength="80"></label>'
        + _b("finish", "finish")
        + _b("drop-vertex", "undo vertex")
        + _b("cancel", "cancel")
        + "</p>"
    )
    zones = ""
    if m.zones:
        opts = "".join(f'<option value="{_e(z)}">{_e(z)}</option>' for z in m.zones)
        zones = f'<p><label>zone <select class="sm-ed-zone">{opts}</select></label>{_b("zone", "close zone")}</p>'
    return (
        f'<div class="sm-ed" hidden data-site-frame="{_e(m.site_frame)}" data-format="{EDITS_FORMAT}" '
        f'data-instance="{_e(m.title)}" '
        f'data-key="{page_key(m)}"><p class="sm-ed-tools" role="group" aria-label="edit tool">{tools}</p>'
        '<p class="sm-ed-hint" role="status"></p>'
        f"{station}{draw}{zones}"
        '<p><label>hours left today <input type="number" class="sm-ed-hours" min="0" step="0.25" '
        'inputmode="decimal"></label></p>'
        '<ol class="sm-ed-list"></ol><p class="sm-ed-none">No edits yet.</p>'
        f"<p>{_b('undo', 'undo last')}{_b('save', 'Save edits.json', 'download the edits for planner replan')}</p>"
        "</div>"
    )
