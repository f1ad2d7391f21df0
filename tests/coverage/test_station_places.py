"""station_places looks at each zone only for the points near it; it must classify every point as the plain check of
every point against every zone does (kept here as the reference)."""

from __future__ import annotations

import numpy as np
import shapely

from planner.coverage.matrix import ON_WALL_M, station_places
from planner.io import load_site
from tests.conftest import INSTANCES


def _plain_zones(site, xy, frames):
    """Every point against every zone of its frame: inside, and the first wall reason in zone order."""
    standoff = site.parameters.min_standoff_m
    frames_arr = np.asarray(frames, dtype=object)
    inside = np.zeros((len(xy), len(site.zones)), dtype=bool)
    reason = [""] * len(xy)
    for zi, zone in enumerate(site.zones):
        same = frames_arr == zone.frame
        inside[:, zi] = same & shapely.contains_xy(zone.polygon, xy[:, 0], xy[:, 1])
        dist = shapely.distance(zone.polygon.boundary, shapely.points(xy))
        for k in np.flatnonzero(same):
            if dist[k] <= ON_WALL_M:
                reason[k] = reason[k] or f"on a wall of zone {zone.id}"
            elif dist[k] < standoff:
                reason[k] = reason[k] or f"{dist[k]:.3f} m from a wall of zone {zone.id} (stand-off {standoff:g} m)"
    return inside, reason


def test_station_places_equal_the_plain_check_of_every_zone():
    site = load_site(INSTANCES / "building27.json")  # 28 rooms side by side: many points near several zones
    rng = np.random.default_rng(7)
    b = np.array([z.polygon.bounds for z in site.zones])
    xy = rng.uniform(b[:, :2].min(0) - 2, b[:, 2:].max(0) + 2, size=(3000, 2))
    corners = np.vstack([np.asarray(z.polygon.exterior.coords) for z in site.zones[:6]])
    standoff = site.parameters.min_standoff_m
    # on the walls, just inside the stand-off, exactly at it and just past it
    xy = np.vstack([xy, corners, corners + [0.0, standoff * 0.5], corners + [standoff, 0.0], corners + [0.0, 0.011]])
    frames = [site.zones[int(k)].frame for k in rng.integers(0, len(site.zones), len(xy))]
    got = station_places(site, xy, frames)
    inside, reason = _plain_zones(site, xy, frames)
    assert np.array_equal(got.inside, inside)
    wall = [r if (" from a wall of zone " in r or r.startswith("on a wall")) else "" for r in got.reason]
    assert wall == reason
    assert sum(bool(r) for r in reason) > 100  # the case has points on and near walls
