"""The default registration scope: site-wide wherever the zones share one frame or openings are given, per zone-side for
one zone or zones in their own frames, and the reason the summary prints."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.coverage.links import RegistrationDefault, default_registration
from planner.io.load import load_site
from planner.site import ScanSide
from planner.site.model import SITE_FRAME, Site, Zone
from tests.conftest import INSTANCES

SHARE = "zones share one frame (site coordinates): one bundle per accessible area"
OWN = "zones in its own frame: one bundle per zone-side, as the dissertation plans"
OPENINGS = "openings given: one bundle per accessible area"

#: every bundled instance: (file, mode, words of the reason)
BUNDLED = [
    ("polygon_a.json", "zone", "one zone"),
    ("polygon_b.json", "zone", "one zone"),
    ("polygon_c.json", "zone", "one zone"),
    ("polygon_a.csv", "zone", "one zone"),
    ("baalbek.json", "zone", f"each of the 12 {OWN}"),
    ("baalbek_site.json", "site", f"the 12 {SHARE}"),
    ("baalbek_site_doors.json", "site", OPENINGS),
    ("building27.json", "site", f"the 28 {SHARE}"),
    ("house_doors.json", "site", OPENINGS),
    ("house2.ifc", "site", OPENINGS),
    # a court and a hall in site coordinates, a room from a table in its own frame, nothing placed: as before
    ("courtyard.json", "zone", "the 3 zones in 2 frames, none placed: one bundle per zone-side"),
    ("plant_1ha.json", "site", f"the 9 {SHARE}"),
    ("plant_4ha.json", "site", f"the 36 {SHARE}"),
    ("plant_16ha.json", "site", f"the 144 {SHARE}"),
    ("plant_64ha.json", "site", f"the 576 {SHARE}"),
]


@pytest.mark.parametrize(
    ("name", "mode", "reason"),
    [pytest.param(*b, id=b[0], marks=[pytest.mark.slow] if b[0] == "plant_64ha.json" else []) for b in BUNDLED],
)
def test_default_registration_of_every_bundled_instance(name, mode, reason):
    got = default_registration(load_site(INSTANCES / name))
    assert isinstance(got, RegistrationDefault)
    assert got.mode == mode
    assert reason in got.reason


def _square(zid: str, x: float, y: float, side: ScanSide, frame: str = SITE_FRAME, size: float = 8.0) -> Zone:
    xy = ((x, y), (x + size, y), (x + size, y + size), (x, y + size))
    return Zone(zid, side, xy, (5.0,) * 4, frame=frame)


def test_table_zones_in_own_frames_stay_per_zone_side():
    # two rooms given by tables, each starting at 0,0 in its own frame, never placed
    site = Site("two tables", (_square("R1", 0, 0, ScanSide.INSIDE, "R1"), _square("R2", 0, 0, ScanSide.INSIDE, "R2")))
    got = default_registration(site)
    assert got.mode == "zone" and got.reason.startswith("each of the 2 zones in its own frame")


def test_one_frame_outdoors_is_site_wide():
    # objects scanned from outside on open ground in one frame: one area, stations link across objects
    zones = tuple(_square(f"T{k}", 20.0 * k, 0, ScanSide.OUTSIDE) for k in range(3))
    got = default_registration(Site("yard", zones))
    assert got == RegistrationDefault("site", f"the 3 {SHARE}")


def test_one_frame_read_from_a_model_names_the_frame():
    zones = (
        _square("R1", 0, 0, ScanSide.INSIDE, "Ground floor"),
        _square("R2", 10, 0, ScanSide.INSIDE, "Ground floor"),
    )
    got = default_registration(Site("storey", zones))
    assert got.mode == "site" and "share one frame (frame 'Ground floor')" in got.reason


def _rotated(zone: Zone, angle_rad: float, dx: float, dy: float) -> Zone:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    xy = tuple((c * x - s * y + dx, s * x + c * y + dy) for x, y in zone.vertices)
    return replace(zone, vertices=xy)


@settings(max_examples=40, deadline=None, derandomize=True, database=None)
@given(
    n=st.integers(min_value=2, max_value=6),
    sides=st.lists(st.sampled_from([ScanSide.INSIDE, ScanSide.OUTSIDE]), min_size=6, max_size=6),
    angle=st.floats(min_value=-math.pi, max_value=math.pi),
    dx=st.floats(min_value=-1e5, max_value=1e5),
    dy=st.floats(min_value=-1e5, max_value=1e5),
)
def test_moving_a_one_frame_site_keeps_its_registration(n, sides, angle, dx, dy):
    zones = tuple(_square(f"Z{k}", 12.0 * k, 3.0 * k, sides[k]) for k in range(n))
    before = default_registration(Site("one frame", zones))
    after = default_registration(Site("moved", tuple(_rotated(z, angle, dx, dy) for z in zones)))
    assert before.mode == after.mode == "site"
    assert before.reason == after.reason
