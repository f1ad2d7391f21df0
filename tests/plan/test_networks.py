"""Registration networks across storeys (issue 46): the summary's line and plan.json's ``registration.networks``
from a site's stairs and the plan's registration components (planner/plan/networks.py)."""

from __future__ import annotations

from dataclasses import replace

from planner.plan.networks import storey_networks
from tests.coverage.test_stair_links import _site


def test_one_area_across_two_frames() -> None:
    """Hall (F1) and Landing (F2) joined by the stair: area 0 spans F1 and F2; the Study (F2) is area 1 alone."""
    (net,) = storey_networks(_site(), {"area 0 (Hall/inside, Landing/inside)": 1, "area 1 (Study/inside)": 1})
    assert (net.area, net.frames, net.stairs, net.parts) == (0, ("F1", "F2"), ("S1",), 1)
    assert net.line() == "registration network: 2 storeys (F1, F2) linked by stair S1: one connected network"
    assert net.to_dict() == {"area": 0, "storeys": ["F1", "F2"], "stairs": ["S1"], "parts": 1, "connected": True}


def test_parts_and_zone_scope() -> None:
    (net,) = storey_networks(_site(), {"area 0 (Hall/inside, Landing/inside)": 2})
    assert net.line().endswith("NOT connected: 2 parts") and not net.to_dict()["connected"]
    (net,) = storey_networks(_site(), {"Hall/inside": 1, "Landing/inside": 1})  # zone scope: no area keys
    assert net.parts is None and "not checked as one group" in net.line()


def test_no_stairs_nothing() -> None:
    assert storey_networks(replace(_site(), stairs=()), {"area 0 (Hall/inside)": 1}) == ()
