"""Registration targets spread apart (issue 45 step 5): each weak link's three targets maximise their smallest
pairwise distance among triangles with every angle >= 30 deg (exact: checked against brute force), at least 2 m
apart where the places allow, else the sheet says why; the sheet states each link's target geometry."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from planner.cli import main
from planner.field.run import FieldOptions, field_plan
from planner.field.spread import ANGLE_TOL_DEG, MIN_ANGLE_DEG, MIN_SPREAD_M, spread, spread_triple
from tests.conftest import INSTANCES
from tests.field.test_field import _house_stations


def _sides_angles(p: np.ndarray) -> tuple[float, float]:
    """Smallest side and smallest angle (deg; 0 for a triangle with a side 0) of the triangle ``p``, from the law
    of cosines (not the module's own helper)."""
    a, b, c = (math.dist(p[1], p[2]), math.dist(p[0], p[2]), math.dist(p[0], p[1]))
    if min(a, b, c) == 0:
        return 0.0, 0.0
    angles = [
        math.degrees(math.acos(max(-1.0, min(1.0, (y * y + z * z - x * x) / (2 * y * z)))))
        for x, y, z in ((a, b, c), (b, a, c), (c, a, b))
    ]
    return min(a, b, c), min(angles)


def _brute(p: np.ndarray, min_angle: float) -> float:
    """The largest smallest side over the triples with smallest angle >= ``min_angle`` (all triples where none); an
    angle of exactly ``min_angle`` counts, though the law of cosines may give it a few 1e-15 deg below."""
    triples = [_sides_angles(p[list(t)]) for t in itertools.combinations(range(len(p)), 3)]
    good = [d for d, ang in triples if ang >= min_angle - ANGLE_TOL_DEG]
    return max(good) if good else max(d for d, _ in triples)


points = st.lists(
    st.tuples(st.integers(0, 12), st.integers(0, 12)), min_size=3, max_size=9
)  # a coarse grid: ties, collinear and repeated places


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(points, st.sampled_from([0.0, 20.0, MIN_ANGLE_DEG, 45.0]))
# (0,0) (4,12) (8,4): angles 45, 45, 90 exactly, smallest side sqrt(80) = 8.944, beating (0,1) (4,12) (8,4) (46.5 deg,
# 8.544); the law of cosines gives its 45 as 44.999999999999986, which a brute force without a tolerance refused
@example(pts=[(0, 0), (0, 1), (4, 12), (8, 4)], min_angle=45.0)
def test_spread_triple_is_the_brute_force_optimum(pts, min_angle):
    p = np.asarray(pts, dtype=float)
    chosen = spread_triple(p, min_angle)
    assert len(set(chosen)) == 3
    got, angle = _sides_angles(p[list(chosen)])
    assert got == pytest.approx(_brute(p, min_angle), rel=1e-9, abs=1e-12)
    if any(_sides_angles(p[list(t)])[1] >= min_angle - ANGLE_TOL_DEG for t in itertools.combinations(range(len(p)), 3)):
        assert angle >= min_angle - 1e-6  # where a triangle with that angle exists, the choice is one
    assert spread_triple(p, min_angle) == chosen  # deterministic


def test_a_narrow_room_says_why():
    # a 1 m grid in a room 1.6 m wide and 1.6 m long: places at its four corners 1 m apart, no 2 m
    grid = np.array([(x, y) for x in (0.0, 1.0) for y in (0.0, 1.0)])
    sp = spread(grid)
    assert sp.min_distance_m == pytest.approx(1.0) and sp.min_angle_deg == pytest.approx(45.0)
    assert "1.00 m apart at most" in sp.note and "within 1.0 m x 1.0 m" in sp.note
    # places on one line (a passage one grid row wide): the angle is said
    line = np.array([(x, 0.0) for x in range(9)])
    sp = spread(line)
    assert sp.min_distance_m == pytest.approx(4.0) and sp.min_angle_deg == 0.0
    assert "nearly on one line" in sp.note
    # room enough: no note
    assert spread(np.array([(0.0, 0.0), (5.0, 0.0), (2.5, 4.0), (1.0, 1.0)])).note == ""
    # a smallest angle of the bound to the last bit meets it (computed 29.999999999999993 deg here): no note
    sp = spread(np.array([(0.0, 0.0), (4.0, 0.0), (0.0, 4.0 * math.tan(math.radians(MIN_ANGLE_DEG)))]))
    assert sp.min_angle_deg == pytest.approx(MIN_ANGLE_DEG) and sp.note == ""


def test_house_links_state_their_target_geometry():
    from planner.io import load_site

    house = load_site(INSTANCES / "house_doors.json")
    fp = field_plan(house, _house_stations(), FieldOptions(mode="registration"))
    done = [lk for lk in fp.links if lk.targets]
    assert done
    for lk in done:
        assert len(lk.targets) == 3 and lk.spread_m is not None and lk.min_angle_deg is not None
        assert lk.spread_m >= MIN_SPREAD_M or lk.spread_note
        assert lk.min_angle_deg >= MIN_ANGLE_DEG or lk.spread_note


@pytest.mark.slow
def test_baalbek_doors_targets_stand_apart(tmp_path):
    out = tmp_path / "p"
    args = [
        "plan",
        str(INSTANCES / "baalbek_site_doors.json"),
        "--method",
        "greedy",
        "--out",
        str(out),
        "--field",
        str(out),
        "--set",
        "field-mode=registration",
        "--quiet",
    ]
    assert main(args) == 0
    data = json.loads((out / "field.json").read_text())
    where = {t["id"]: (t["x"], t["y"]) for t in data["targets"]}
    with_targets = [lk for lk in data["links"] if lk["targets"]]
    assert with_targets
    for lk in with_targets:
        p = [where[t] for t in lk["targets"]]
        dmin = min(math.dist(a, b) for a, b in itertools.combinations(p, 2))
        assert dmin == pytest.approx(lk["target_spread_m"])
        assert dmin >= MIN_SPREAD_M or lk["target_geometry_note"], lk
        assert lk["target_min_angle_deg"] >= MIN_ANGLE_DEG or lk["target_geometry_note"], lk
    html = (out / "field.html").read_text()
    assert "smallest distance m" in html and "smallest angle deg" in html
