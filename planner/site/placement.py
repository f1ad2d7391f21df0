"""Where a table zone lies in the site frame: a rigid placement, and zones moved by it."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import shapely
from numpy.typing import NDArray

from planner.core.errors import InputError
from planner.site.model import SITE_FRAME, ScanSide, Site, Wall, Zone


@dataclass(frozen=True)
class Placement:
    """The zone frame in the site frame: site = R(rotation) * local + origin."""

    origin: tuple[float, float]
    rotation_deg: float

    def __post_init__(self) -> None:
        if not all(math.isfinite(v) for v in (*self.origin, self.rotation_deg)):
            raise InputError(
                "placement must be finite numbers", field="placement", value=(*self.origin, self.rotation_deg)
            )

    @property
    def matrix(self) -> NDArray[np.float64]:
        a = math.radians(self.rotation_deg)
        return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])

    def apply(self, xy: NDArray[np.float64] | tuple | list[tuple[float, float]]) -> NDArray[np.float64]:
        """Local points (n, 2) in the site frame."""
        return np.asarray(
            np.asarray(xy, dtype=float).reshape(-1, 2) @ self.matrix.T + np.asarray(self.origin), dtype=np.float64
        )

    def ends(self, w: Wall) -> NDArray[np.float64]:
        """The wall's two ends (2 x 2) in the site frame."""
        return self.apply([w.start, w.end])

    def wrapped(self) -> Placement:
        """The same placement, its rotation in [-180, 180) degrees."""
        return Placement(self.origin, wrap_deg(self.rotation_deg))


def wrap_deg(a: float) -> float:
    return (a + 180.0) % 360.0 - 180.0


def tangent_normal(ends: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The unit direction of a segment (2 x 2 ends) and its left normal."""
    t = (ends[1] - ends[0]) / np.hypot(*(ends[1] - ends[0]))
    return t, np.array([-t[1], t[0]])


IDENTITY = Placement((0.0, 0.0), 0.0)


def place_zone(zone: Zone, p: Placement) -> Zone:
    """The zone moved into the site frame (its walls, openings and heights keep their numbering)."""
    ring = lambda r: tuple((float(x), float(y)) for x, y in p.apply(r))  # noqa: E731
    note = (
        f"placed in the site frame: origin ({p.origin[0]:.3f}, {p.origin[1]:.3f}) m, rotation {p.rotation_deg:.4f} deg"
    )
    return replace(
        zone,
        vertices=ring(zone.vertices),
        holes=tuple(ring(h) for h in zone.holes),
        frame=SITE_FRAME,
        notes=zone.notes + (note,),
    )


def placed_site(site: Site, placements: dict[str, Placement]) -> Site:
    """The site with each placed zone moved into the site frame."""
    return replace(site, zones=tuple(place_zone(z, placements[z.id]) if z.id in placements else z for z in site.zones))


#: interiors may overlap by this share of the smaller area (slivers from printed angles) and still count as disjoint;
#: a coincidental match throws a zone across others, far beyond it
OVERLAP_SHARE = 0.05


def normal_sign(zone: Zone) -> int:
    """+1 when the scanned face looks to the left of the wall (inside), -1 (outside); 0 both sides."""
    return {ScanSide.INSIDE: 1, ScanSide.OUTSIDE: -1}.get(zone.scan_side, 0)


def interiors_clash(za: Zone, pa: Placement, zb: Zone, pb: Placement) -> bool:
    """True when two placed zones cannot both be real: rooms overlapping, or a room outside the outline."""
    a, b = shapely.Polygon(pa.apply(za.xy)), shapely.Polygon(pb.apply(zb.xy))
    small = OVERLAP_SHARE * min(a.area, b.area)
    sa, sb = normal_sign(za), normal_sign(zb)
    if sa == sb:
        return bool(a.intersection(b).area > small)
    room, outline = (a, b) if sa > 0 else (b, a)
    return bool(room.difference(outline).area > small)


def misfit(p: Placement, q: Placement, zone: Zone) -> float:
    return float(np.max(np.hypot(*(p.apply(zone.xy) - q.apply(zone.xy)).T)))
