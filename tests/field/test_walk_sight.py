"""The corners' visibility of a walkable area is tested once however many point sets are walked in it
(:func:`planner.field.walking.walk_graph`): the graphs are those tested afresh."""

from __future__ import annotations

import numpy as np

from planner.field import walking
from planner.io import load_site
from tests.conftest import INSTANCES


def _same(a: walking.WalkGraph, b: walking.WalkGraph) -> None:
    assert np.array_equal(a.nodes, b.nodes)
    assert np.array_equal(a.dist, b.dist)
    assert np.array_equal(a.predecessors, b.predecessors)
    assert np.array_equal(a.component, b.component)


def test_a_second_point_set_walks_as_if_tested_afresh():
    site = load_site(INSTANCES / "house_doors.json")
    first = [(-5.0, -5.0), (35.0, 12.0), (5.0, 4.0)]
    second = [(35.0, 12.0), (-5.0, -5.0), (20.0, -10.0), (5.0, 4.0)]
    space = walking.walk_space(site, "site", first + second)
    walking.walk_graph(space, first)  # the corners' sight kept for the space
    assert space in walking._CORNER_SIGHT
    kept = walking.walk_graph(space, second)
    walking._CORNER_SIGHT.clear()
    _same(kept, walking.walk_graph(space, second))
    assert np.isfinite(kept.dist).all() and kept.dist[0, 1] >= np.hypot(40.0, 17.0) - 1e-9
