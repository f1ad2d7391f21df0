"""The site-wide plan figure: one marker per station, numbers in the walking order given, the registration
links (the network's, or the plan's relation afresh), control points, scale bar and north arrow, one panel per
frame, and labels that never overlap, down to a large site."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

import planner
from planner.figures.site_fig import site_figure
from planner.plan.plan_dict import StationNumbering
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide
from tests.conftest import square_rows
from tests.figures.overlap import labels, overlapping
from tests.figures.test_figures import square_outcome


def station_markers(fig: Figure) -> list[Line2D]:
    return [ln for ax in fig.axes for ln in ax.lines if ln.get_gid() == "stations"]


def link_segments(fig: Figure) -> int:
    return sum(len(c.get_segments()) for ax in fig.axes for c in ax.collections if c.get_gid() == "links")


def check_site_figure(fig: Figure, order: list[str]) -> None:
    """One marker per station, every station numbered k + 1 for ``order[k]``, scale bar and north arrow, no
    overlap."""
    assert sum(len(m.get_xdata()) for m in station_markers(fig)) == len(order)
    found = labels(fig, "label:station:")
    assert {gid.split(":", 2)[2]: t.get_text() for gid, t in found.items()} == {
        sid: str(k) for k, sid in enumerate(order, 1)
    }
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert any(t.endswith(" m") for t in texts)  # scale bar
    assert any(t.startswith("N") for t in texts)  # north arrow
    assert overlapping(fig) == []


@pytest.mark.slow
def test_house_with_network_in_walking_order(house_network):
    order = [s.id for s in house_network.stations][::-1]  # any walk: here the plan order reversed
    fig = site_figure(house_network, StationNumbering.walking(house_network.stations, order))
    check_site_figure(fig, order)
    assert "walking order" in fig.get_suptitle()
    g = house_network.network.graph
    assert link_segments(fig) == sum(1 for *_, d in g.edges(data=True) if "registration" in d["kinds"])
    control = {n for n, d in g.nodes(data=True) if d["kind"] == "control"}
    assert {gid.split(":", 2)[2] for gid in labels(fig, "label:control:")} == control


def test_house_without_network_links_from_the_plan(house_plain, house_network):
    # without a network the links are the plan's registration relation, the same pairs the network holds
    fig = site_figure(house_plain)
    check_site_figure(fig, [s.id for s in house_plain.stations])
    assert "plan order" in fig.get_suptitle()
    assert link_segments(fig) > 0 and labels(fig, "label:control:") == {}
    assert len(fig.axes) == 1  # one frame, one panel


def test_order_must_name_the_plans_stations(house_plain):
    ids = [s.id for s in house_plain.stations]
    with pytest.raises(ValueError, match="does not have: nowhere"):
        StationNumbering.walking(house_plain.stations, ["nowhere"])
    with pytest.raises(ValueError, match="more than once"):
        StationNumbering.walking(house_plain.stations, [ids[0], ids[0]])
    # stations the order leaves out follow it in plan order
    numbers = StationNumbering.walking(house_plain.stations, [ids[2]]).numbers
    assert numbers[ids[2]] == 1 and [numbers[i] for i in ids if i != ids[2]] == list(range(2, len(ids) + 1))


def test_zones_in_separate_frames_get_a_panel_each(write_csv):
    # a table site: each zone in its own frame (as instances/baalbek.json), numbered on across the panels
    site = planner.load_site(write_csv(square_rows("A") + square_rows("B", length=6.0)))
    plan = planner.plan_site(site, planner.PlanOptions(method="greedy"))
    o = planner.outcome_from_plan(plan)
    fig = site_figure(o)
    shown = [ax for ax in fig.axes if ax.get_visible()]
    assert sorted(ax.get_title().split(":")[0] for ax in shown) == ["frame A", "frame B"]
    check_site_figure(fig, [s.id for s in o.stations])


def test_a_hundred_stations_stay_readable():
    # 100 stations on a 10 x 10 grid 2 m apart in a 20 m room: the numbers that fit are placed without
    # overlap, next to their station or on a short leader line; those left out are counted under the panel
    st = [
        Candidate(
            f"S{k}", "S", ScanSide.INSIDE, "site", 1.0 + 2.0 * (k % 10), 1.0 + 2.0 * (k // 10), CandidateKind.GRID
        )
        for k in range(100)
    ]
    o = square_outcome(st, side_m=20.0)
    fig = site_figure(o)
    assert sum(len(m.get_xdata()) for m in station_markers(fig)) == 100
    assert station_markers(fig)[0].get_markersize() < 4  # small markers for a large site
    assert overlapping(fig) == []
    found = labels(fig, "label:station:")
    assert len(found) >= 60
    left_out = 100 - len(found)
    assert (f"{left_out} labels left out" in fig.axes[0].get_xlabel()) == (left_out > 0)
    numbers = {f"S{k}": str(k + 1) for k in range(100)}
    assert all(t.get_text() == numbers[g.split(":", 2)[2]] for g, t in found.items())
    assert np.isfinite([t.xyann for t in found.values()]).all()
    # nearly every station registers to every other in one open room (4,948 of the 4,950 pairs): a spanning tree
    assert link_segments(fig) == 99
    assert "spanning forest (99 of 49" in " ".join(t.get_text() for t in fig.legends[0].get_texts())


def test_a_walking_order_given_by_ids_numbers_as_its_numbering(house_plain):
    # site_figure(outcome, order=ids), as docs/library.md writes it, is StationNumbering.walking(stations, ids)
    order = [s.id for s in house_plain.stations][::-1]
    check_site_figure(site_figure(house_plain, order=order), order)
