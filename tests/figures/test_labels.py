"""Labels never overlap: on the network and plan figures of bundled sites, on a crowded synthetic case, and on
random small sets of points (a seeded property test); the same input gives the same placement."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.figure import Figure

from planner.figures.base import decorate_plan
from planner.figures.labels import PAD_PX, Placed, PointLabel, arrange_boxes, place_labels
from planner.figures.network_fig import network_figure
from planner.figures.plan_fig import plan_figure
from planner.figures.storey_fig import storey_figure
from planner.plan.plan_dict import StationNumbering
from tests.figures.overlap import boxes, labels, overlapping


def labelled_points(
    xy: np.ndarray, texts: list[str], marker_pt: float = 5.0, layout: str | None = "constrained"
) -> tuple[Figure, Placed]:
    """A 6 x 5 in figure of the points with their labels placed; also what ``place_labels`` returned."""
    fig = Figure(figsize=(6, 5), layout=layout)
    ax = fig.subplots()
    ax.plot(xy[:, 0], xy[:, 1], "o", ms=marker_pt, ls="none")
    ax.plot([-40, 50], [-40, 50], alpha=0)  # room around the points
    decorate_plan(ax, "site")
    placed = place_labels(ax, [PointLabel(x, y, t, marker_pt=marker_pt) for (x, y), t in zip(xy, texts)])
    return fig, placed


def covered_markers(fig: Figure, xy: np.ndarray, marker_pt: float) -> list[tuple[str, int]]:
    """(label, point) pairs where a label's box meets the marker of a point."""
    ax = fig.axes[0]
    found = labels(fig)
    b = boxes(fig, list(found.values()))
    half = marker_pt / 2 * fig.dpi / 72
    px = ax.transData.transform(xy)
    hits = []
    for (gid, _), (x0, y0, x1, y1) in zip(found.items(), b):
        for k, (x, y) in enumerate(px):
            if x0 < x + half and x1 > x - half and y0 < y + half and y1 > y - half:
                hits.append((gid, k))
    return hits


def test_thirty_points_in_a_small_square_all_labelled_none_overlapping():
    # 30 points within 10 m in axes 90 m wide: ~55 px square, far less than 30 labels need, so most go out on
    # leader lines; every one finds a place, none meets another, a marker, the scale bar or the north arrow
    xy = np.random.default_rng(7).uniform(0.0, 10.0, (30, 2))
    fig, placed = labelled_points(xy, [f"S{k + 1}" for k in range(30)])
    assert placed.omitted == () and len(placed.texts) == 30
    assert len(placed.leaders) > 0  # the crowd needs leader lines
    assert overlapping(fig) == []
    assert covered_markers(fig, xy, 5.0) == []


def test_same_input_same_placement():
    xy = np.random.default_rng(3).uniform(0.0, 10.0, (20, 2))
    texts = [f"point-{k}" for k in range(20)]
    first = [t.xyann for t in labelled_points(xy, texts)[1].texts]
    second = [t.xyann for t in labelled_points(xy, texts)[1].texts]
    assert first == second


def test_arrange_boxes_keeps_apart_stays_inside_and_leaves_out_what_cannot_fit():
    # two labels 20 x 10 px on one point in a 100 x 100 frame: the first takes NE next to the marker (gap 1 px
    # beyond marker 3 + pad 2), the second NW; neither needs a leader
    anchors = np.array([[50.0, 50.0], [50.0, 50.0]])
    sizes = np.array([[20.0, 10.0], [20.0, 10.0]])
    centres, leader = arrange_boxes(anchors, sizes, (0.0, 0.0, 100.0, 100.0), None, np.array([3.0, 3.0]))
    g, reach = np.sqrt(0.5), 3.0 + PAD_PX  # the near gap 1 px along the diagonal, beyond marker and pad
    assert np.allclose(centres[0], [50 + g + reach + 10, 50 + g + reach + 5])
    assert np.allclose(centres[1], [50 - g - reach - 10, 50 + g + reach + 5])
    assert not leader.any()
    # a label wider than the frame cannot be placed: left out (NaN), never drawn over the edge
    centres, _ = arrange_boxes(anchors[:1], np.array([[120.0, 10.0]]), (0.0, 0.0, 100.0, 100.0))
    assert np.isnan(centres).all()
    # a point whose near rings are all taken by an obstacle box gets a far place with a leader line
    block = np.array([[20.0, 20.0, 80.0, 80.0]])
    centres, leader = arrange_boxes(np.array([[50.0, 50.0]]), sizes[:1], (0.0, 0.0, 100.0, 100.0), block)
    assert leader[0] and not (20 - PAD_PX < centres[0, 0] < 80 + PAD_PX and 20 - PAD_PX < centres[0, 1] < 80 + PAD_PX)


def _random_points_never_overlap(points):
    xy = np.array([(x, y) for x, y, _ in points], dtype=float)
    texts = ["W" * n for *_, n in points]
    fig, placed = labelled_points(xy, texts, layout=None)  # no layout engine: quicker draws
    assert overlapping(fig) == []
    assert covered_markers(fig, xy, 5.0) == []
    assert len(placed.texts) + len(placed.omitted) == len(points)


# 3 examples in the quick tier; the slow twin below runs 10
@settings(max_examples=3, deadline=None, derandomize=True)
@given(
    st.lists(
        st.tuples(st.floats(0.0, 10.0), st.floats(0.0, 10.0), st.integers(1, 12)),
        min_size=1,
        max_size=12,
    )
)
def test_random_points_never_overlap(points):
    _random_points_never_overlap(points)


@pytest.mark.slow
@settings(max_examples=10, deadline=None, derandomize=True)
@given(
    st.lists(
        st.tuples(st.floats(0.0, 10.0), st.floats(0.0, 10.0), st.integers(1, 12)),
        min_size=1,
        max_size=12,
    )
)
def test_random_points_never_overlap_at_full_strength(points):
    _random_points_never_overlap(points)


@pytest.mark.slow
def test_network_figure_of_house_doors_labels_never_overlap(house_network):
    # 7 stations and 10 control points (proposed) with long names ("TPR1.1.1", "house-out-G865")
    fig = network_figure(house_network)
    assert overlapping(fig) == []
    found = labels(fig)
    names = {n for n, d in house_network.network.graph.nodes(data=True)}
    assert {g.split(":", 2)[2] for g in found} == names  # every station and control point labelled
    # stations by their one number (the plan's numbering, as every output), control points by name
    numbering = StationNumbering.recorded(house_network.meta, house_network.stations)
    kinds = dict(house_network.network.graph.nodes(data="kind"))
    text = {n: str(numbering.number(n)) if kinds[n] == "station" else n for n in names}
    assert {g.split(":", 2)[2]: t.get_text() for g, t in found.items()} == text


@pytest.mark.slow
def test_plan_figure_of_polygon_b_labels_never_overlap(polygon_b):
    # both sides of polygon B: each panel of each figure labels its stations without overlap
    for side in ("inside", "outside"):
        fig = plan_figure(polygon_b, "B", side)
        assert overlapping(fig) == []
        n = sum(1 for s in polygon_b.stations if s.side.value == side)
        both = [t for ax in fig.axes for t in ax.texts if (t.get_gid() or "").startswith("label:station:")]
        assert len(both) == 2 * n  # both panels


def test_storey_figure_names_rooms_and_stations_without_overlap(house_plain):
    # house_doors: the outline's name used to sit on room R2's; now names and station ids are placed together
    fig = storey_figure(house_plain.site, house_plain.stations, "site")
    assert overlapping(fig) == []
    found = labels(fig)
    assert {g for g in found if g.startswith("label:room:")} == {f"label:room:{z.id}" for z in house_plain.site.zones}
    assert len([g for g in found if g.startswith("label:station:")]) == len(house_plain.stations)
