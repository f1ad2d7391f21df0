"""The blockers of a frame are made once per site (every coverage build of a plan asks for them), and a site that is
another object, even one equal to it, gets its own."""

from __future__ import annotations

import dataclasses

import numpy as np

from planner.coverage.matrix import blockers_for, zone_side_blockers
from planner.io.load import load_site
from tests.conftest import INSTANCES


def test_the_same_site_and_frame_give_the_same_blockers():
    site = load_site(INSTANCES / "house_doors.json")
    frame = site.zones[0].frame
    assert blockers_for(site, frame) is blockers_for(site, frame)
    assert zone_side_blockers(site, frame) is zone_side_blockers(site, frame)
    assert zone_side_blockers(site, frame).all is blockers_for(site, frame)


def test_another_site_object_gets_its_own_equal_blockers():
    site = load_site(INSTANCES / "house_doors.json")
    frame = site.zones[0].frame
    copy = dataclasses.replace(site)
    mine, theirs = blockers_for(site, frame), blockers_for(copy, frame)
    assert mine is not theirs
    for name in ("a", "b", "key", "vertices"):
        assert np.array_equal(getattr(mine, name), getattr(theirs, name))
