"""Read a building model (IFC2X3, IFC4) through IfcOpenShell: one inside zone per IfcSpace.

docs/ifc.md tables what is read from which entity. In short, per selected building storey (``IfcOptions.storey``): each
IfcSpace is an inside zone (outline: the plan footprint of its body; wall height: its height, else the storey height);
walls, columns, stairs and furniture standing in it are cut out (a notch or a hole); doors (windows with
``windows=True``), unfilled wall openings and open boundaries between spaces are openings
(:mod:`planner.io.ifc_passages`); ``exterior=True`` adds the storey's outer outline as an outside zone; stairs between
read storeys join them (:mod:`planner.io.ifc_stairs`). Each space's floor level and ceiling serve the floor and ceiling
targets (:func:`floor_level`).

The file is checked whole before IfcOpenShell reads it, and the model against the file after
(:mod:`planner.io.ifc_check`): IfcOpenShell reads a file cut short, or one with lines lost, without a word. One storey
reads into the site frame; several each into a frame named after the storey. Coordinates are metres from the
file's units and placements; a model without a length unit is read as metres, noted on each zone.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import shapely

from planner.core.errors import InputError, located_in
from planner.io.ifc_check import check_model, spf_instances
from planner.io.ifc_geom import Solid, geometry_settings, largest_polygon, opening_on_wall, solid_of
from planner.io.ifc_passages import open_boundaries, unfilled_openings, wide_enough
from planner.io.ifc_stairs import StoreyZones, read_stairs
from planner.site.model import SITE_FRAME, ScanSide, Site, Zone
from planner.site.params import Parameters

#: elements that stand in rooms and block sight
BLOCKER_TYPES = ("IfcWall", "IfcColumn", "IfcStair", "IfcFurnishingElement", "IfcBuildingElementProxy")
#: gaps narrower than this (m) between a blocker and a room's wall are filled (no station sees into them)
SLOT_M = 0.3
#: outline vertices closer than this (m) to the line of their neighbours are dropped
OUTLINE_TOL_M = 0.02
#: storey height used when neither the space nor the storeys give one (m)
DEFAULT_STOREY_HEIGHT_M = 3.0


@dataclass(frozen=True, kw_only=True)
class IfcOptions:
    """What to read from an IFC file: which storey(s), windows as openings, the exterior outline."""

    storey: str | None = None
    windows: bool = False
    exterior: bool = False


@dataclass(frozen=True)
class _Storey:
    """One building storey: its name, entity, elevation and height (m), the z of its placement, its spaces.

    ``base_z_m`` is the world z (m) of the storey's own placement, or its elevation when it has none (the spaces are
    then placed absolutely).
    """

    name: str
    entity: Any
    elevation_m: float
    height_m: float
    spaces: tuple[Any, ...]
    base_z_m: float = 0.0


def read_ifc_site(path: Path | str, options: IfcOptions | None = None) -> Site:
    """Read the selected storeys of an IFC file as a site (see the module docstring). InputError, one line naming
    the file (and the zone): not an IFC file, no IfcSpace, a space without geometry, an unknown storey, a zone the
    site model refuses (e.g. coordinates beyond 1e8 m)."""
    options = options or IfcOptions()
    path = Path(path)
    model = _open(path)
    storeys = _select(_storeys(model, path), options.storey, path)
    settings = geometry_settings()
    zones: list[Zone] = []
    read: list[StoreyZones] = []
    note = _unit_note(model)
    with located_in(str(path)):  # the zones' own checks name no file
        for st in storeys:
            frame = SITE_FRAME if len(storeys) == 1 else st.name
            prefix = "" if len(storeys) == 1 else f"{st.name}/"
            these = _storey_zones(model, st, frame, prefix, options, settings, str(path))
            read.append(StoreyZones(entity=st.entity, elevation_m=st.elevation_m, zones=tuple(these)))
            zones += these
        if note:
            zones = [replace(z, notes=z.notes + (note,)) for z in zones]
        stairs = read_stairs(read, settings) if len(read) > 1 else ()
        return Site(name=path.stem, zones=tuple(zones), parameters=Parameters(), source=str(path), stairs=stairs)


def _unit_note(model: Any) -> str | None:
    """A zone note when the model gives no length unit (its coordinates are then read as metres)."""
    import ifcopenshell.util.unit as uu

    if uu.get_project_unit(model, "LENGTHUNIT") is None:
        return "no length unit in the model's IfcUnitAssignment: read as metres"
    return None


def _open(path: Path) -> Any:
    import ifcopenshell

    instances = spf_instances(path)  # the file whole, before IfcOpenShell reads it (it reads a damaged one silently)
    try:
        model = ifcopenshell.open(str(path))
    except Exception as exc:  # IfcOpenShell raises plain errors for unreadable files
        raise InputError(
            f"IfcOpenShell cannot read it: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}",
            file=str(path),
        ) from None
    check_model(model, instances, str(path))
    return model


def _storeys(model: Any, path: Path) -> list[_Storey]:
    import ifcopenshell.util.element as ue
    import ifcopenshell.util.unit as uu

    scale = uu.calculate_unit_scale(model)
    raw = sorted(model.by_type("IfcBuildingStorey"), key=lambda s: float(s.Elevation or 0.0))
    out = []
    for k, st in enumerate(raw):
        elev = float(st.Elevation or 0.0) * scale
        nxt = float(raw[k + 1].Elevation or 0.0) * scale if k + 1 < len(raw) else None
        spaces = tuple(
            sorted(
                (e for e in ue.get_decomposition(st) if e.is_a("IfcSpace")),
                key=lambda e: (str(e.LongName or e.Name or ""), e.GlobalId),
            )
        )
        height = nxt - elev if nxt is not None and nxt > elev else DEFAULT_STOREY_HEIGHT_M
        base = _placement_z(st, scale)
        out.append(_Storey(st.Name or f"storey {k + 1}", st, elev, height, spaces, elev if base is None else base))
    if not any(s.spaces for s in out):
        raise InputError(
            "no IfcSpace in any storey: the planner scans rooms; define the rooms as spaces in the authoring tool (e.g. "
            "Revit Rooms, ArchiCAD Zones) and export them to IFC",
            file=str(path),
            field="IfcSpace",
            value=0,
        )
    return out


def _placement_z(entity: Any, scale: float) -> float | None:
    """The world z (m) of ``entity``'s local placement (``scale``: metres per file unit), or None when it has none (or
    one IfcOpenShell cannot read)."""
    import ifcopenshell.util.placement as up

    placement = getattr(entity, "ObjectPlacement", None)
    if placement is None:
        return None
    try:
        return float(up.get_local_placement(placement)[2, 3]) * scale
    except Exception:  # an unusual placement (grid, linear) the utility does not resolve: as if none
        return None


def floor_level(elevation_m: float, base_z_m: float, solid_z_min_m: float) -> float:
    """A space's floor level (m, rounded to 0.1 mm): its storey's ``Elevation`` (the datum) plus its own base offset,
    the bottom of its solid (``solid_z_min_m``, world) less the world z of the storey's placement (``base_z_m``; the
    elevation where the storey has none). The offset is 0 for a space on its storey's base, as every exporter we know
    writes it; a space on a raised floor or in a split level sits that much higher."""
    return round(elevation_m + (solid_z_min_m - base_z_m), 4)


def _select(storeys: list[_Storey], which: str | None, path: Path) -> list[_Storey]:
    if which is None or which == "all":
        return [s for s in storeys if s.spaces]
    if which.isdigit() and 1 <= int(which) <= len(storeys):
        chosen = [storeys[int(which) - 1]]
    else:
        chosen = [s for s in storeys if s.name == which]
    if not chosen:
        names = ", ".join(f"{k} {s.name!r}" for k, s in enumerate(storeys, 1))
        raise InputError(f"no such storey (the file has: {names})", file=str(path), field="--storey", value=which)
    if not chosen[0].spaces:
        raise InputError("the storey holds no IfcSpace", file=str(path), field="--storey", value=which)
    return chosen


def _storey_zones(
    model: Any, st: _Storey, frame: str, prefix: str, options: IfcOptions, settings: Any, file: str
) -> list[Zone]:
    import ifcopenshell.util.element as ue

    contained = [e for e in ue.get_decomposition(st.entity) if not e.is_a("IfcSpace")]
    blockers = [
        (e, s if e.is_a("IfcWall") else replace(s, footprint=s.footprint.convex_hull))
        for e in contained
        if any(e.is_a(t) for t in BLOCKER_TYPES)
        if (s := solid_of(e, settings)) is not None
    ]
    if not any(e.is_a("IfcWall") for e, _ in blockers):
        raise InputError(
            f"{len(st.spaces)} IfcSpace and no IfcWall in the storey: its walls are missing from the model (the spaces"
            " alone would read as one open plan); export the walls with the spaces, contained in their storey",
            file=file,
            field="storey",
            value=st.name,
        )
    kinds = {"IfcDoor": "door"} | ({"IfcWindow": "window"} if options.windows else {})
    openings = [
        (e.Name or e.GlobalId, kinds[k], s)
        for e in contained
        for k in kinds
        if e.is_a(k)
        if (s := solid_of(e, settings)) is not None
    ] + [(name, "passage", s) for name, s in unfilled_openings(model, st.entity, st.base_z_m, settings)]
    zones: list[Zone] = []
    used: set[str] = set()
    for space in st.spaces:
        name = space.LongName or space.Name or space.GlobalId
        zid = _unique(prefix + str(name), used)
        solid = solid_of(space, settings)
        if solid is None:
            where = dict(file=file, zone=zid, field="Representation", value=space.GlobalId)
            raise InputError("the space has no body geometry (IfcOpenShell built no shape for it)", **where)
        height = solid.height_m if solid.height_m > 0 else st.height_m
        zone = replace(
            _space_zone(zid, solid, height, blockers, frame, file),
            floor_level_m=floor_level(st.elevation_m, st.base_z_m, solid.z_min_m),
            ceiling_height_m=round(height, 4),
        )
        ops = sorted(
            (
                op
                for name, kind, s in openings
                for w in zone.walls
                if (op := opening_on_wall(w, s.footprint, kind, name)) is not None
                if kind != "passage" or wide_enough(op)
            ),
            key=lambda o: (o.wall, o.s0_m),
        )
        zones.append(replace(zone, openings=tuple(ops)) if ops else zone)
    zones = _with_open_boundaries(zones, [s.footprint for e, s in blockers if e.is_a("IfcWall")])
    if options.exterior:
        zones.append(_exterior(st, prefix, blockers, zones, frame))
    return zones


def _with_open_boundaries(zones: list[Zone], walls: list[shapely.Geometry]) -> list[Zone]:
    """The zones with a passage wherever two of them touch with no wall between (:mod:`planner.io.ifc_passages`)."""
    extra = open_boundaries(zones, walls)
    return [
        replace(z, openings=tuple(sorted(z.openings + tuple(extra[z.id]), key=lambda o: (o.wall, o.s0_m))))
        if z.id in extra
        else z
        for z in zones
    ]


def _unique(name: str, used: set[str]) -> str:
    out, k = name, 2
    while out in used:
        out, k = f"{name} ({k})", k + 1
    used.add(out)
    return out


def _space_zone(
    zid: str, solid: Solid, height: float, blockers: list[tuple[Any, Solid]], frame: str, file: str
) -> Zone:
    """The zone of one space: its footprint less the blockers that stand in it."""
    room = largest_polygon(solid.footprint)
    inside = [
        (s, min(height, s.height_m))
        for _, s in blockers
        if s.footprint.intersection(room).area > 0.5 * s.footprint.area
    ]
    if inside:
        cut = shapely.union_all([s.footprint for s, _ in inside])
        half = SLOT_M / 2  # an opening (erode, dilate) fills the slots no scanner can see into
        room = room.difference(cut).buffer(-half, join_style="mitre").buffer(half, join_style="mitre")
        room = largest_polygon(shapely.simplify(room.intersection(largest_polygon(solid.footprint)), OUTLINE_TOL_M))
    if room.is_empty or room.area <= 0:
        raise InputError(
            "the space's footprint is empty once walls and columns are cut out", file=file, zone=zid, field="footprint"
        )
    outline = [tuple(map(float, p)) for p in room.exterior.coords[:-1]]
    holes = tuple(tuple((float(p[0]), float(p[1])) for p in r.coords[:-1]) for r in room.interiors)
    hole_h = tuple(tuple(_height_at(p, inside, height) for p in r) for r in holes)
    return Zone(
        id=zid,
        scan_side=ScanSide.INSIDE,
        vertices=tuple(outline),  # type: ignore[arg-type]
        vertex_heights_m=tuple(_height_at(p, inside, height) for p in outline),
        frame=frame,
        holes=holes,
        hole_heights_m=hole_h,
        notes=("from IFC space",),
    )


def _height_at(p: tuple[float, ...], inside: list[tuple[Solid, float]], height: float) -> float:
    """The wall height at a vertex: a blocker's own height where the vertex lies on one, else the room's."""
    pt = shapely.Point(p)
    hs = [h for s, h in inside if s.footprint.distance(pt) < SLOT_M]
    return round(max(hs) if hs else height, 4)


def _exterior(st: _Storey, prefix: str, blockers: list[tuple[Any, Solid]], zones: list[Zone], frame: str) -> Zone:
    """The storey's outer outline (spaces and walls together), scanned from outside."""
    parts = [z.polygon for z in zones] + [s.footprint for e, s in blockers if e.is_a("IfcWall")]
    merged = shapely.union_all(parts).buffer(0.01, join_style="mitre").buffer(-0.01, join_style="mitre")
    outline = largest_polygon(shapely.simplify(merged, 1e-3))
    xy = tuple(tuple(map(float, p)) for p in outline.exterior.coords[:-1])
    return Zone(
        id=f"{prefix}exterior",
        scan_side=ScanSide.OUTSIDE,
        vertices=xy,  # type: ignore[arg-type]
        vertex_heights_m=(round(st.height_m, 4),) * len(xy),
        frame=frame,
        notes=("from IFC outline",),
        floor_level_m=round(st.elevation_m, 4),
    )
