"""The stretches of an axis line inside coverage regions: one STR-tree of the regions serves every line, with the
stretches each line gets alone; runs and touching points both located along the line."""

from __future__ import annotations

import numpy as np
import shapely

from planner.candidates.axis import intervals


def test_one_tree_for_every_line_gives_each_lines_stretches() -> None:
    regions = [
        shapely.box(1, -1, 3, 1),
        shapely.Point(6, 0).buffer(1.5, quad_segs=32),
        shapely.box(8, 0, 9, 2),  # touches the x axis along a stretch of its bottom edge
        shapely.box(12, 0, 13, 1).union(shapely.box(14, -1, 15, 0)),  # two parts, one touching from above
        shapely.box(20, 5, 21, 6),  # meets no line
    ]
    lines = [shapely.LineString([(0, 0), (16, 0)]), shapely.LineString([(0, 0.5), (4, 0.5), (4, 3), (9, 3)])]
    tree = shapely.STRtree(regions)
    for line in lines:
        alone, shared = intervals(line, regions), intervals(line, regions, tree)
        for x, y in zip(alone, shared):
            assert x.tobytes() == y.tobytes()
    lo, hi = intervals(lines[0], regions, tree)
    assert np.allclose(sorted(zip(lo, hi)), [(1, 3), (4.5, 7.5), (8, 9), (12, 13), (14, 15)], atol=1e-3)
