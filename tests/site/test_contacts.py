"""Zones placed by collinear contacts: a side along part of a placed wall (planner/site/contacts.py)."""

from __future__ import annotations

import numpy as np
import pytest

from planner.site.contacts import place_by_contacts
from planner.site.model import ScanSide, Zone
from planner.site.placement import IDENTITY, Placement

# A strip 10 m wide (the outline, scanned outside; its east end slanted) holds room A (12 x 10 m) at its
# west end; room C, a trapezoid (12,0) (27,0) (26,10) (12,10), fills part of the rest: its sides 1 and 3
# lie along parts of the outline's long sides, its side 4 along A's side 2. Its slanted side 2 touches nothing.
OUTLINE = [(0, 0), (30, 0), (33, 10), (0, 10)]
ROOM_A = [(0, 0), (12, 0), (12, 10), (0, 10)]
ROOM_C = [(12, 0), (27, 0), (26, 10), (12, 10)]
MOVE = Placement((40.0, -3.0), 57.0)


def _zone(zid: str, xy, side: ScanSide, frame: str = "site") -> Zone:
    pts = np.asarray(xy, dtype=float)
    if frame != "site":
        pts = (pts - np.asarray(MOVE.origin)) @ MOVE.matrix
    return Zone(
        id=zid,
        scan_side=side,
        vertices=tuple(map(tuple, pts.tolist())),
        vertex_heights_m=(5.0,) * len(pts),
        frame=frame,
    )


def _zones(outline=OUTLINE):
    return {
        "outline": _zone("outline", outline, ScanSide.OUTSIDE),
        "A": _zone("A", ROOM_A, ScanSide.INSIDE),
        "C": _zone("C", ROOM_C, ScanSide.INSIDE, frame="C"),
    }


def test_three_contacts_in_two_directions_place_the_room_exactly():
    zones = _zones()
    p, contacts, why = place_by_contacts(zones["C"], zones, {"outline": IDENTITY, "A": IDENTITY})
    assert p is not None, why
    assert np.allclose(p.apply(zones["C"].xy), ROOM_C, atol=1e-6)
    assert {c.label for c in contacts} == {
        "C side 1 along outline side 1",
        "C side 3 along outline side 3",
        "C side 4 along A side 2",
    }
    # hand check: C's side 1 (15 m) lies on 15 of the outline's 30 m, its side 4 on all of A's 10 m
    over = {c.label: c.overlap_m for c in contacts}
    assert over["C side 1 along outline side 1"] == pytest.approx(15.0)
    assert over["C side 4 along A side 2"] == pytest.approx(10.0)
    assert max(c.residual_m for c in contacts) < 1e-6


def test_two_parallel_contacts_leave_the_room_unplaced():
    # without A, and with both ends of the strip slanted, C touches only the two long sides: it could
    # slide along the strip, so it is not placed
    zones = _zones([(-3, 0), (30, 0), (33, 10), (0, 10)])
    p, contacts, why = place_by_contacts(zones["C"], zones, {"outline": IDENTITY})
    assert p is None and not contacts
    assert "left in its own frame" in why


def test_a_rival_that_fits_as_well_makes_it_ambiguous():
    # with a square east end, C turned by 180 deg fits there too (its side 4 on the outline's east side),
    # held by three contacts with zero residual like the true place: nothing is guessed
    zones = _zones([(0, 0), (30, 0), (30, 10), (0, 10)])
    p, _, why = place_by_contacts(zones["C"], zones, {"outline": IDENTITY, "A": IDENTITY})
    assert p is None and why.startswith("ambiguous: 2 placements are held by 3 contacts each")
