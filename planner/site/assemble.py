"""Zones placed together: shared walls found from equal side lengths, and one rigid fit over all of them.

Every table zone lives in a frame of its own. Two faces of one wall have equal length and opposite
scanning normals: two rooms run along a shared wall in opposite directions, a room and the outline that
holds it in the same direction. A match of two such sides places one zone relative to the other; all kept
matches are then fitted by least squares (four endpoint residuals per match), the anchor held fixed.
Equal lengths also occur by coincidence, so a match is never taken on length alone:

- it must place the two zones without their interiors overlapping;
- every match that reaches a zone not yet placed must put it in the same place (within
  ``consistency_m``); else the zone is ambiguous and left unplaced;
- a wall face takes at most one partner.

Nothing is guessed: zones no match reaches stay in their own frame and are listed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from planner.core.errors import InputError
from planner.core.settings import DEFAULTS
from planner.site.model import SITE_FRAME, ScanSide, Site, Wall, Zone
from planner.site.placement import IDENTITY, Placement, interiors_clash, misfit, normal_sign, tangent_normal, wrap_deg


@dataclass(frozen=True)
class WallMatch:
    """Side ``wall_a`` of zone ``zone_a`` and side ``wall_b`` of ``zone_b`` taken as the two faces of one wall."""

    zone_a: str
    wall_a: int
    zone_b: str
    wall_b: int
    length_a_m: float
    length_b_m: float
    same_direction: bool
    residual_m: float = math.nan  # largest endpoint misfit after the fit
    tolerance_m: float = math.nan  # the length tolerance this pair was matched within (see :func:`side_tolerance_m`)

    @property
    def label(self) -> str:
        return f"{self.zone_a} side {self.wall_a} = {self.zone_b} side {self.wall_b}"


@dataclass(frozen=True)
class AssemblyReport:
    """Placements found, the matches used (with residuals), those refused and why, and zones left unplaced."""

    anchor: str
    placements: dict[str, Placement]
    used: tuple[WallMatch, ...]
    refused: tuple[tuple[WallMatch, str], ...]
    unplaced: tuple[tuple[str, str], ...]
    tolerance_m: float
    wall_thickness_m: float
    contacts: tuple = ()  # :class:`planner.site.contacts.Contact` of zones placed by collinear contacts
    sources: dict[str, str] = field(default_factory=dict)  # how each placed zone was placed

    def lines(self) -> list[str]:
        out = [
            f"anchor {self.anchor} (its frame is the site frame); tolerance {self.tolerance_m * 1000:.1f} mm, "
            f"wall thickness {self.wall_thickness_m:.3f} m"
        ]
        out += [
            f"match   {m.label}: lengths {m.length_a_m:.4f} / {m.length_b_m:.4f} m (within {m.tolerance_m * 1000:.0f} mm), "
            f"{'same' if m.same_direction else 'opposite'} direction, residual {m.residual_m * 1000:.1f} mm"
            for m in self.used
        ]
        out += [f"refused {m.label} ({m.length_a_m:.4f} / {m.length_b_m:.4f} m): {why}" for m, why in self.refused]
        out += [
            f"contact {c.label}: overlap {c.overlap_m:.2f} m, residual {c.residual_m * 1000:.1f} mm"
            for c in self.contacts
        ]
        out += [
            f"placed  {z}: origin ({p.origin[0]:.3f}, {p.origin[1]:.3f}) m, rotation {p.rotation_deg:.4f} deg"
            + (f" ({self.sources[z]})" if z in self.sources else "")
            for z, p in self.placements.items()
        ]
        out += [f"unplaced {z}: {why}" for z, why in self.unplaced]
        return out


def side_tolerance_m(za: Zone, wa: Wall, zb: Zone, wb: Wall, tolerance_m: float) -> float:
    """Two sides' lengths are known to within the base tolerance plus what each closure adjustment may have changed
    them: the compass rule moves a side's far end by (its length / the perimeter) x the linear misclosure (nothing for
    a zone that closes exactly or was not given as a traverse)."""
    out = tolerance_m
    for z, w in ((za, wa), (zb, wb)):
        if z.closure is not None and z.closure.perimeter_m > 0:
            out += w.length_m / z.closure.perimeter_m * z.closure.linear_misclosure_m
    return out


def candidate_matches(zones: tuple[Zone, ...], tolerance_m: float) -> list[WallMatch]:
    """Every pair of outline sides of two zones with lengths equal within :func:`side_tolerance_m`, closest first."""
    out = []
    for i, za in enumerate(zones):
        for zb in zones[i + 1 :]:
            sa, sb = normal_sign(za), normal_sign(zb)
            if sa == 0 or sb == 0:
                continue
            for wa in za.outer_walls:
                for wb in zb.outer_walls:
                    tol = side_tolerance_m(za, wa, zb, wb, tolerance_m)
                    if abs(wa.length_m - wb.length_m) <= tol:
                        out.append(
                            WallMatch(
                                za.id, wa.index, zb.id, wb.index, wa.length_m, wb.length_m, sa != sb, tolerance_m=tol
                            )
                        )
    return sorted(out, key=lambda m: (abs(m.length_a_m - m.length_b_m) > tolerance_m, abs(m.length_a_m - m.length_b_m)))


def _face_ends(zone: Zone, w: Wall, p: Placement, thickness_m: float) -> NDArray[np.float64]:
    """Ends of the OTHER face of wall ``w`` (site frame): the scanned face moved back by the thickness."""
    e = p.ends(w)
    return e - thickness_m * tangent_normal(e)[1] * normal_sign(zone)


def _relative(
    m: WallMatch, placed: Zone, pp: Placement, other: Zone, other_wall: int, placed_wall: int, thickness_m: float
) -> Placement:
    """Placement of ``other`` that lays its side on the placed zone's side as the match says."""
    a = _face_ends(placed, placed.outer_walls[placed_wall - 1], pp, thickness_m)
    wb = other.outer_walls[other_wall - 1]
    b = np.array([wb.start, wb.end])
    target = a if m.same_direction else a[::-1]
    ang = math.atan2(*(target[1] - target[0])[::-1]) - math.atan2(*(b[1] - b[0])[::-1])
    rot = Placement((0.0, 0.0), math.degrees(ang))
    origin = target.mean(axis=0) - rot.apply(b.mean(axis=0))[0]
    return Placement((float(origin[0]), float(origin[1])), wrap_deg(math.degrees(ang)))


def assemble(
    site: Site,
    tolerance_m: float = DEFAULTS["assemble.tolerance_m"],
    wall_thickness_m: float = DEFAULTS["assemble.wall_thickness_m"],
    anchor: str | None = None,
    consistency_m: float = 0.10,
) -> AssemblyReport:
    """Place the table zones of a site from their shared walls (see the module text)."""
    if not tolerance_m > 0 or not wall_thickness_m >= 0:
        raise InputError("tolerance must be > 0 and wall thickness >= 0", field="tolerance", value=tolerance_m)
    zones = {z.id: z for z in site.zones}
    fixed = {z.id: IDENTITY for z in site.zones if z.frame == SITE_FRAME}
    anchor = anchor or (next(iter(fixed), None) or _default_anchor(site))
    if anchor not in zones:
        raise InputError("anchor names no zone of the site", file=site.source or None, field="anchor", value=anchor)
    placed: dict[str, Placement] = dict(fixed) or {anchor: IDENTITY}
    matches = candidate_matches(site.zones, tolerance_m)
    used, refused, ambiguous = _grow(matches, zones, placed, wall_thickness_m, consistency_m)
    used += _closing_matches(matches, used, refused, zones, placed, wall_thickness_m, consistency_m)
    used, refused = _one_partner(used, refused)
    fitted = _fit_in_order(zones, placed, set(fixed) or {anchor}, used, wall_thickness_m)
    used = [replace(m, residual_m=_residual(m, zones, fitted, wall_thickness_m)) for m in used]
    sources = {z: _match_source(z, used, zones) for z in fitted if z not in fixed and z != anchor}
    from planner.site.contacts import place_unmatched

    more, contacts, why_not = place_unmatched(
        zones, fitted, [z for z in zones if z not in fitted and z not in ambiguous]
    )
    fitted.update({z: p for z, (p, _) in more.items()})
    sources.update({z: why for z, (_, why) in more.items()})
    unplaced = [
        (z, ambiguous.get(z) or f"no wall of it matches a placed zone; by contacts: {why_not[z]}")
        for z in zones
        if z not in fitted
    ]
    return AssemblyReport(
        anchor,
        {z: fitted[z] for z in zones if z in fitted and z not in fixed},
        tuple(used),
        tuple(refused),
        tuple(unplaced),
        tolerance_m,
        wall_thickness_m,
        tuple(contacts),
        sources,
    )


def _grow(
    matches: list[WallMatch],
    zones: dict[str, Zone],
    placed: dict[str, Placement],
    thickness_m: float,
    consistency_m: float,
) -> tuple[list[WallMatch], list[tuple[WallMatch, str]], dict[str, str]]:
    """Place zones (into ``placed``) one ring of matches at a time, from the zones already placed: a match
    that would make interiors overlap is refused, a zone whose matches disagree is ambiguous. Returns the
    matches used, those refused with why, and the ambiguous zones with why."""
    used: list[WallMatch] = []
    refused: list[tuple[WallMatch, str]] = []
    ambiguous: dict[str, str] = {}
    progress = True
    while progress:
        progress = False
        reach: dict[str, list[tuple[WallMatch, Placement]]] = {}
        for m in matches:
            if m in used or any(m is r for r, _ in refused) or (m.zone_a in placed) == (m.zone_b in placed):
                continue
            sides = ((m.zone_a, m.wall_a), (m.zone_b, m.wall_b))
            (pz, pw), (oz, ow) = sides if m.zone_a in placed else sides[::-1]
            cand = _relative(m, zones[pz], placed[pz], zones[oz], ow, pw, thickness_m)
            clash = next((z for z, p in placed.items() if interiors_clash(zones[oz], cand, zones[z], p)), None)
            if clash is not None:
                refused.append((m, f"coincidence: it would make {oz} overlap {clash}"))
                continue
            reach.setdefault(oz, []).append((m, cand))
        for oz, options in reach.items():
            if oz in ambiguous:
                continue
            spread = max(misfit(options[0][1], c, zones[oz]) for _, c in options)
            if spread > consistency_m:
                ambiguous[oz] = (
                    f"ambiguous: {', '.join(m.label for m, _ in options)} place it up to {spread:.3f} m apart"
                )
                refused += [(m, f"ambiguous placement of {oz}") for m, _ in options]
                continue
            placed[oz] = options[0][1]
            used += [m for m, _ in options]
            progress = True
    return used, refused, ambiguous


def _fit_in_order(
    zones: dict[str, Zone], placed: dict[str, Placement], held: set[str], used: list[WallMatch], thickness_m: float
) -> dict[str, Placement]:
    """The least-squares fit of the placements, ``held`` fixed; zones with an accepted misclosure are fitted
    after the others (those held then), which they must not pull."""
    loose = {z for z in placed if zones[z].misclosed and z not in held}
    first = [m for m in used if m.zone_a not in loose and m.zone_b not in loose]
    fitted = _fit(zones, {z: p for z, p in placed.items() if z not in loose}, held, first, thickness_m)
    rest = [m for m in used if m not in first]
    return _fit(zones, {**fitted, **{z: placed[z] for z in loose}}, set(fitted), rest, thickness_m)


def _match_source(z: str, used: list[WallMatch], zones: dict[str, Zone]) -> str:
    mine = [m for m in used if z in (m.zone_a, m.zone_b)]
    text = f"matched walls: {', '.join(m.label for m in mine)}"
    if zones[z].misclosed:
        text += (
            f"; its table misses by {zones[z].closure.linear_misclosure_m:.2f} m (accepted), so its sides "  # type: ignore[union-attr]
            "match within their closure adjustment's change and it was fitted after the others (held fixed), so it pulls none of them"
        )
    return text


def _default_anchor(site: Site) -> str:
    outside = [z.id for z in site.zones if z.scan_side is ScanSide.OUTSIDE]
    return outside[0] if len(outside) == 1 else max(site.zones, key=lambda z: z.area_m2).id


def _closing_matches(
    matches: list[WallMatch],
    used: list[WallMatch],
    refused: list[tuple[WallMatch, str]],
    zones: dict[str, Zone],
    placed: dict[str, Placement],
    thickness_m: float,
    consistency_m: float,
) -> list[WallMatch]:
    """Matches between two zones placed by other matches: kept (they close loops) when they agree."""
    out = []
    for m in matches:
        if m in used or any(m is r for r, _ in refused) or m.zone_a not in placed or m.zone_b not in placed:
            continue
        cand = _relative(m, zones[m.zone_a], placed[m.zone_a], zones[m.zone_b], m.wall_b, m.wall_a, thickness_m)
        miss = misfit(cand, placed[m.zone_b], zones[m.zone_b])
        if miss <= consistency_m:
            out.append(m)
        else:
            refused.append((m, f"coincidence: disagrees with the placement by {miss:.3f} m"))
    return out


def _one_partner(
    used: list[WallMatch], refused: list[tuple[WallMatch, str]]
) -> tuple[list[WallMatch], list[tuple[WallMatch, str]]]:
    """A wall face takes one partner: faces claimed twice keep neither claim out of the fit."""
    count: dict[tuple[str, int], int] = {}
    for m in used:
        for k in ((m.zone_a, m.wall_a), (m.zone_b, m.wall_b)):
            count[k] = count.get(k, 0) + 1
    twice = {k for k, n in count.items() if n > 1}
    keep = [m for m in used if (m.zone_a, m.wall_a) not in twice and (m.zone_b, m.wall_b) not in twice]
    return keep, refused + [(m, "its wall face has two partners") for m in used if m not in keep]


def _match_residuals(
    m: WallMatch, zones: dict[str, Zone], pl: dict[str, Placement], thickness_m: float
) -> NDArray[np.float64]:
    wa, wb = zones[m.zone_a].outer_walls[m.wall_a - 1], zones[m.zone_b].outer_walls[m.wall_b - 1]
    a = _face_ends(zones[m.zone_a], wa, pl[m.zone_a], thickness_m)
    b = pl[m.zone_b].ends(wb)
    return (a - (b if m.same_direction else b[::-1])).ravel()


def _residual(m: WallMatch, zones: dict[str, Zone], pl: dict[str, Placement], thickness_m: float) -> float:
    r = _match_residuals(m, zones, pl, thickness_m).reshape(2, 2)
    return float(np.max(np.hypot(r[:, 0], r[:, 1])))


def _fit(
    zones: dict[str, Zone], start: dict[str, Placement], fixed: set[str], used: list[WallMatch], thickness_m: float
) -> dict[str, Placement]:
    """Least squares over the placements of every zone reached (fixed ones held)."""
    free = [z for z in start if z not in fixed]
    if not free or not used:
        return dict(start)

    def unpack(v: NDArray[np.float64]) -> dict[str, Placement]:
        pl = dict(start)
        for k, z in enumerate(free):
            pl[z] = Placement((float(v[3 * k]), float(v[3 * k + 1])), float(np.degrees(v[3 * k + 2])))
        return pl

    x0 = np.array([c for z in free for c in (*start[z].origin, math.radians(start[z].rotation_deg))])
    res = least_squares(
        lambda v: np.concatenate([_match_residuals(m, zones, unpack(v), thickness_m) for m in used]),
        x0,
        method="lm" if 4 * len(used) >= len(x0) else "trf",
        xtol=1e-12,
        ftol=1e-12,
    )
    return {z: p.wrapped() for z, p in unpack(res.x).items()}
