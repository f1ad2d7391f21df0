"""Registration links through a stair: a station of the stair's lower zone and one of its upper zone that see a common
point of the stair's edge, and the storeys joined into one accessible area.

The hand-checked site (two frames, plan coordinates shared):

- frame ``F1``, zone ``Hall``: 0..6 x 0..4 less the stair's notch 1..5 x 3..4 (the stair against the north wall, 4 m
  long, 1 m wide), so its outline is (0,0) (6,0) (6,4) (5,4) (5,3) (1,3) (1,4) (0,4);
- frame ``F2``, zone ``Landing``: 0..6 x 0..3, south of the stairwell (which is the stair's footprint); zone ``Study``:
  7..10 x 0..3 in the same frame, no door between them;
- the stair's edge: the footprint 1..5 x 3..4 moved 0.1 m out, the ring (0.9, 2.9)..(5.1, 4.1), 10.8 m round, a point
  every 10.8 / 44 = 0.245 m (``EDGE_STEP_M`` 0.25).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from planner.core.errors import InputError
from planner.coverage.links import opening_links, registration_groups
from planner.coverage.openings import accessible_areas, space_of
from planner.coverage.stair_links import stair_edge, stair_links
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide, Site, Zone
from planner.site.stairs import Stair

FOOT = ((1.0, 3.0), (5.0, 3.0), (5.0, 4.0), (1.0, 4.0))


def _zone(zid: str, frame: str, ring: list[tuple[float, float]]) -> Zone:
    return Zone(
        id=zid, scan_side=ScanSide.INSIDE, vertices=tuple(ring), vertex_heights_m=(2.5,) * len(ring), frame=frame
    )


def _site(stairs: bool = True) -> Site:
    hall = _zone("Hall", "F1", [(0, 0), (6, 0), (6, 4), (5, 4), (5, 3), (1, 3), (1, 4), (0, 4)])
    landing = _zone("Landing", "F2", [(0, 0), (6, 0), (6, 3), (0, 3)])
    study = _zone("Study", "F2", [(7, 0), (10, 0), (10, 3), (7, 3)])
    stair = Stair(name="S1", lower_zone="Hall", upper_zone="Landing", footprint=FOOT, z_min_m=0.0, z_max_m=3.0)
    return Site(name="two storeys", zones=(hall, landing, study), stairs=(stair,) if stairs else ())


#: (zone, x, y) of the stations
STATIONS = [
    ("Hall", 3.0, 1.0),  # 0: 1.9 m below the edge y = 2.9
    ("Landing", 3.0, 1.5),  # 1: 1.4 m below it
    ("Hall", 3.0, 0.2),  # 2: 2.7 m from the edge: beyond reach 2
    ("Study", 8.0, 1.5),  # 3: upper frame, not the stair's upper zone
]


def _links(site: Site, reach: float) -> np.ndarray:
    xy = np.array([(x, y) for _, x, y in STATIONS])
    spaces = [("in", z) for z, _, _ in STATIONS]
    return stair_links(site, xy, spaces, reach).toarray()


def test_stair_edge_is_the_footprint_moved_out() -> None:
    edge = stair_edge(_site().stairs[0])
    assert len(edge) == 44  # ceil(10.8 / 0.25)
    assert edge[:, 0].min() == pytest.approx(0.9) and edge[:, 0].max() == pytest.approx(5.1)
    assert edge[:, 1].min() == pytest.approx(2.9) and edge[:, 1].max() == pytest.approx(4.1)
    gaps = np.hypot(*np.diff(np.vstack([edge, edge[:1]]), axis=0).T)
    assert gaps.max() <= 0.25


def test_hand_checked_links() -> None:
    """Reach 2 m. Station 0 (Hall, 3, 1) sees the edge y = 2.9 for |x - 3| <= sqrt(4 - 1.9^2) = 0.62, station 1
    (Landing, 3, 1.5) for |x - 3| <= sqrt(4 - 1.4^2) = 1.43: the points are 0.245 m apart, so both see one of them:
    linked. Station 2 (Hall, 3, 0.2) is 2.7 m from the nearest edge point: no link. Station 3 stands in the Study, not
    the stair's upper zone: no link. The link is between storeys only (0-1, symmetric)."""
    got = _links(_site(), 2.0)
    want = np.zeros((4, 4), dtype=bool)
    want[0, 1] = want[1, 0] = True
    assert (got == want).all()
    # with reach 3 station 2 sees the edge too (2.7 m): linked to station 1, whose 1.4 m are within reach
    got = _links(_site(), 3.0)
    assert got[2, 1] and got[1, 2] and not got[2, 0] and not got[3].any()


def test_sight_is_checked_in_each_frame() -> None:
    """A Landing station at (3, 1.5) does not see the stair's north edge y = 4.1: the Landing's north wall y = 3 stands
    between (its own frame). A Hall station in the notch's east corner (5.5, 3.5) sees the east edge x = 5.1 and the
    corner (5.1, 2.9), which the Landing station sees as well: linked (reach 2: 1.4^2 + 2.1^2 = 6.37 > 4, so through the
    corner (5.1, 2.9) only at reach 3: 2.1^2 + 1.4^2 = 6.37 <= 9)."""
    site = _site()
    xy = np.array([(5.5, 3.5), (3.0, 1.5)])
    spaces = [("in", "Hall"), ("in", "Landing")]
    assert not stair_links(site, xy, spaces, 2.0).toarray()[0, 1]
    assert stair_links(site, xy, spaces, 3.0).toarray()[0, 1]


def test_the_stair_joins_the_storeys_into_one_area() -> None:
    areas = accessible_areas(_site())
    assert areas[("in", "Hall")] == areas[("in", "Landing")] != areas[("in", "Study")]
    plain = accessible_areas(_site(stairs=False))
    assert len({plain[("in", z)] for z in ("Hall", "Landing", "Study")}) == 3


def _candidates() -> list[Candidate]:
    return [
        Candidate(
            id=f"c{k}",
            zone=z,
            side=ScanSide.INSIDE,
            frame="F1" if z == "Hall" else "F2",
            x=x,
            y=y,
            kind=CandidateKind.GRID,
        )
        for k, (z, x, y) in enumerate(STATIONS)
    ]


def test_registration_groups_carry_the_stair_links() -> None:
    cands = _candidates()
    labels, links = registration_groups(_site(), cands, "site", 2.0)
    assert labels[0] == labels[1] == labels[2] != labels[3]
    assert links is not None and links[0, 1] and links[1, 0] and links.nnz == 2


def test_no_stairs_no_change() -> None:
    """A site without stairs: the links are exactly the opening links (here none) and stair_links is empty."""
    site = _site(stairs=False)
    cands = _candidates()
    _, links = registration_groups(site, cands, "site", 5.0)
    xy = np.array([c.xy for c in cands])
    spaces = [space_of(site.zone(c.zone), c.side) for c in cands]
    want = opening_links(site, xy, [c.frame for c in cands], spaces, 5.0)
    assert links is not None and (links != want).nnz == 0 and links.nnz == 0
    assert stair_links(site, xy, spaces, 5.0).nnz == 0


def test_a_stair_must_name_zones_of_the_site() -> None:
    with pytest.raises(InputError, match="a stair names a zone the site does not have"):
        replace(_site(), stairs=(Stair(name="S2", lower_zone="Hall", upper_zone="Attic", footprint=FOOT),))
    with pytest.raises(InputError, match="two different zones"):
        Stair(name="S3", lower_zone="Hall", upper_zone="Hall", footprint=FOOT)
