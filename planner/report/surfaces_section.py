"""Floors and ceilings in report.html: the "Floors and ceilings" section (:func:`surfaces_section`: the verification per
zone and surface, the patches no candidate sees, the rules and what the bound holds over) and the floor and ceiling each
station covers, for the site map's floors layer (:func:`station_areas`).

Both show nothing for a walls-only plan: the section is empty, and the map has no floors layer.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import shapely

from planner.coverage.surfaces import KIND_NAME
from planner.figures.webmap import MapArea
from planner.plan.outcome import Outcome
from planner.plan.surfaces import patch_matrix
from planner.report.markup import esc as _e
from planner.report.markup import table

#: the merged shapes are drawn to this grid (m): the map writes centimetres
GRID_M = 0.01


def surface_meta(o: Outcome) -> Mapping[str, Any] | None:
    """plan.json's ``surfaces`` of the outcome where they go beyond walls (None: walls only)."""
    s = o.meta.get("surfaces")
    if not isinstance(s, Mapping) or not any(t != "walls" for t in s.get("types", ())):
        return None
    return s


def _rules(o: Outcome, s: Mapping[str, Any]) -> str:
    scanner = o.validation.scanner
    nadir, zenith = scanner.nadir_blind_half_angle_deg, scanner.zenith_blind_half_angle_deg
    setup = o.surfaces
    spacing = f"{setup.patches.spacing_m:g} m" if setup is not None else "-"
    rows = [
        ("surfaces", _e(", ".join(s.get("types", ())))),
        ("patches", f"{s.get('patches', 0):,} of at most {spacing} ({float(s.get('patch_area_m2', 0.0)):.1f} m2)"),
        ("instrument height above the floor", f"{float(s.get('instrument_height_m', 0.0)):g} m"),
        ("theta_max_floor (floors and ceilings)", f"{float(s.get('theta_max_floor_deg', 0.0)):g} deg"),
        ("blind cone half angle (nadir)", f"{nadir:g} deg ({_e(scanner.name)})" if nadir else "none"),
        ("blind cone half angle (zenith)", f"{zenith:g} deg" if zenith else "none"),
    ]
    return table(("rule", "value"), rows, left=2)


def surfaces_section(o: Outcome) -> str:
    """The "Floors and ceilings" section (heading included), or "" for a walls-only plan."""
    s = surface_meta(o)
    if s is None:
        return ""
    v = s.get("verification") or {}
    zones = v.get("zones", [])
    ok = bool(v.get("complete")) and bool(zones)
    state = (
        '<span class="pass">complete</span>'
        if ok
        else '<span class="fail">nothing verified</span>'
        if not zones
        else '<span class="fail">incomplete</span>'
    )
    absent = "".join(
        f'<p class="fail">Warning: the site has no {_e(t)}: --surfaces {_e(t)} plans nothing.</p>'
        for t in s.get("absent_types", ())
    )
    head = absent + (
        f"<p>{state}: {float(v.get('percent', 0.0)):.3f} % of floor and ceiling points every "
        f"{float(v.get('spacing_m', 0.0)):g} m covered (a point is covered when a station of its zone sees it within "
        f"S_max and theta_max_floor, outside the blind cone, by a plan-view sight line inside the zone; a point of a "
        f"patch left out of the plan is never counted covered).</p>"
    )
    rows = [(_e(z["zone"]), _e(z["type"]), z["points"], z["covered"], f"{float(z['percent']):.3f}") for z in zones]
    u = s.get("unseen_patches") or {}
    unseen = (
        f"<p>Patches seen by no candidate, NOT covered (left out of the plan): {int(u['count'])}, "
        f"{float(u['area_m2']):.2f} m2 in {_e(', '.join(u.get('zones', [])))}.</p>"
        if u.get("count")
        else "<p>Patches seen by no candidate: none.</p>"
    )
    notes = "".join(f"<li>{_e(n)}</li>" for n in v.get("notes", []))
    plane, cert = o.meta.get("plane_bound"), o.meta.get("certificate") or {}
    scope = str(cert.get("scope", "plane")).removeprefix("plane, ")
    off = str((o.meta.get("solver") or {}).get("plane_off", "no plane bound formed"))
    bound = (
        f"<p>Bound: {plane:g} stations over every position in the plane for {_e(scope)} together "
        f"(scope {_e(str(o.meta.get('bound_scope')))}).</p>"
        if isinstance(plane, (int, float))
        else f"<p>Bound: over the candidate pool only (scope pool): {_e(off)}.</p>"
    )
    return (
        "<h2>Floors and ceilings</h2>"
        + head
        + table(("zone", "surface", "points", "covered", "%"), rows, left=2)
        + unseen
        + (f'<ul class="notes">{notes}</ul>' if notes else "")
        + _rules(o, s)
        + bound
    )


def _rings(geom: shapely.Geometry) -> tuple[tuple[tuple[float, float], ...], ...]:
    """The exterior rings and holes of every polygon of ``geom``."""
    out: list[tuple[tuple[float, float], ...]] = []
    for poly in shapely.get_parts(geom):
        if not isinstance(poly, shapely.Polygon) or poly.is_empty:
            continue
        for ring in (poly.exterior, *poly.interiors):
            out.append(tuple((float(x), float(y)) for x, y in np.asarray(ring.coords)))
    return tuple(out)


def station_areas(o: Outcome) -> list[tuple[MapArea, ...]] | None:
    """Per station, the floor and ceiling patches it sees (:func:`planner.plan.surfaces.patch_matrix`), merged per zone
    and kind, drawn to the centimetre and without collinear vertices; None where the outcome holds no patches (walls
    only)."""
    setup = o.surfaces
    if setup is None or surface_meta(o) is None:
        return None
    p = setup.patches
    seen = patch_matrix(o.site, setup, o.stations)
    out: list[tuple[MapArea, ...]] = []
    for i in range(len(o.stations)):
        cols = np.sort(seen.indices[seen.indptr[i] : seen.indptr[i + 1]])
        areas = []
        for z, k in sorted({(int(p.zone[c]), int(p.kind[c])) for c in cols}):
            mine = cols[(p.zone[cols] == z) & (p.kind[cols] == k)]
            shape = shapely.simplify(shapely.set_precision(shapely.union_all(p.polygon[mine]), GRID_M), 0.0)
            area = float(p.area_m2[mine].sum())
            name = f"{p.zone_ids[z]} {KIND_NAME[k]}"
            label = f"{name}: {mine.size} patch(es), {area:.1f} m2"
            areas.append(MapArea(_rings(shape), KIND_NAME[k], int(mine.size), area, label))
        out.append(tuple(areas))
    return out
