"""AGPLIB .pol polygons: exact fractions, holes, scaling; and the art-gallery runs with the limits off."""

from __future__ import annotations

import pytest

import planner
from planner.cli import main
from tests.conftest import ROOT

#: three small AGPLIB polygons copied from ../shared/benchmarks/agplib (provenance: tests/data/README.md)
AGP = ROOT / "tests" / "data" / "agplib"
LIMITS_OFF = [
    "--max-range",
    "10000",
    "--theta-max",
    "89.99",
    "--set",
    "no-precision",
    "--no-overlap",
    "--grid-spacing",
    "2",
    "--quiet",
]


def test_pol_with_a_hole_is_scaled_and_oriented(tmp_path):
    # a 4 x 2 rectangle (exact fractions) with a 1 x 1 square hole given counter-clockwise;
    # scaled to a 100 m extent: factor 25, area (8 - 1) x 25^2 = 4375 m2
    path = tmp_path / "r.pol"
    path.write_text("4 0/1 0/1 4/1 0/1 4/1 2/1 0/1 2/1 1 4 3/2 1/2 5/2 1/2 5/2 3/2 3/2 3/2")
    z = planner.load_site(path).zones[0]
    assert z.area_m2 == pytest.approx(4375.0)
    assert len(z.walls) == 8 and len(z.holes) == 1
    assert "scaled by 25" in z.notes[0]


@pytest.mark.slow
@pytest.mark.parametrize(
    "rel", ["randsimple-20-1.pol", "random-20-1.pol", pytest.param("spike60n14.pol", marks=pytest.mark.heavy)]
)
def test_art_gallery_polygon_with_limits_off_plans_and_verifies(rel, capsys, tmp_path):
    code = main(["plan", str(AGP / rel), *LIMITS_OFF, "--out", str(tmp_path)])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "verification at 0.1 m: 100.000 % covered" in out
    assert "milp: optimal" in out
