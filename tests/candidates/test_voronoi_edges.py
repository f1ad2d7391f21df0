"""The Voronoi edges the medial axis is drawn from (:func:`planner.candidates.axis.voronoi_edges`): the same
segments, coordinate for coordinate, as GEOS's ``only_edges`` output wherever an edge lies strictly inside the sampled
area (the only edges the axis keeps), on random polygons' sampled boundaries and on random point clouds."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.candidates.axis import voronoi_edges


def _canonical(lines: np.ndarray) -> set[tuple[float, ...]]:
    out = set()
    for row in shapely.get_coordinates(lines).reshape(-1, 4):
        a, b = (row[0], row[1]), (row[2], row[3])
        out.add((*min(a, b), *max(a, b)))
    return out


def _geos(points: np.ndarray) -> np.ndarray:
    return shapely.get_parts(shapely.voronoi_polygons(shapely.multipoints(points), only_edges=True))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), st.integers(3, 9), st.sampled_from([0.3, 0.5, 1.0]))
def test_the_edges_inside_a_sampled_polygon_are_geos_own(seed: int, corners: int, step: float) -> None:
    rng = np.random.default_rng(seed)
    angles = np.sort(rng.uniform(0, 2 * np.pi, corners))
    radii = rng.uniform(3.0, 10.0, corners)
    area = shapely.Polygon(np.c_[radii * np.cos(angles), radii * np.sin(angles)])
    if not area.is_valid or area.area < 1.0:
        return
    points = shapely.get_coordinates(shapely.segmentize(area.boundary, step))
    ours, theirs = voronoi_edges(points), _geos(points)
    assert set(shapely.get_num_coordinates(ours)) == {2}
    keep = _canonical(ours[shapely.contains_properly(area, ours)])
    assert keep == _canonical(theirs[shapely.contains_properly(area, theirs)])
    assert len(keep) == int(shapely.contains_properly(area, ours).sum())  # each edge once


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(3, 60))
def test_every_edge_of_a_point_cloud_is_geos_own(seed: int, n: int) -> None:
    """Over random points, GEOS's edges are all among ours (ours add the cells' borders on the envelope)."""
    points = np.random.default_rng(seed).uniform(0, 20, (n, 2))
    assert _canonical(_geos(points)) <= _canonical(voronoi_edges(points))
