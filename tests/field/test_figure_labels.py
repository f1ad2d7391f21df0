"""The field sheet's plan figure labels its setups and targets without overlap (issue 45): every text box of the
drawn figure (setup numbers, target names, scale bar, north arrow) apart from every other, for a plan of
house_doors in shortest order and in registration order (with its registration targets), at field.html's size and
at field.pdf's A3, and for 64 setups on a tight grid."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure

import planner
from planner.field.figure import SIZE, figure
from planner.field.pdf import A3
from planner.field.run import FieldOptions, FieldPlan, field_plan
from planner.io import load_site
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide
from tests.conftest import INSTANCES
from tests.figures.overlap import boxes, drawn_texts, labels, overlapping


@pytest.fixture(scope="module")
def house_plan(house_doors_greedy) -> planner.Plan:
    return house_doors_greedy[1]


def check_labels(fig: Figure, fp: FieldPlan) -> None:
    """No two texts overlap; each setup numbered in visiting order and each target named, none left out; every
    label inside the axes; scale bar and north arrow drawn."""
    assert overlapping(fig) == []
    found = labels(fig)
    numbers = {gid.split(":", 2)[2]: t.get_text() for gid, t in found.items() if gid.startswith("label:station:")}
    assert numbers == {fp.stations[k].id: str(n) for n, k in enumerate(fp.order, 1)}
    names = {gid.split(":", 2)[2]: t.get_text() for gid, t in found.items() if gid.startswith("label:target:")}
    assert names == {t.id: t.id for t in fp.targets}
    assert "left out" not in fig.axes[0].get_xlabel()
    texts = drawn_texts(fig)
    within = np.asarray(fig.axes[0].bbox.extents)
    placed = boxes(fig, [t for t in texts if (t.get_gid() or "").startswith("label:")])
    assert (placed[:, :2] >= within[:2] - 0.5).all() and (placed[:, 2:] <= within[2:] + 0.5).all()
    said = [t.get_text() for t in texts]
    assert any(s.endswith(" m") for s in said) and any(s.startswith("N") for s in said)  # scale bar, north arrow


@pytest.mark.parametrize("mode", ["shortest", pytest.param("registration", marks=pytest.mark.slow)])
def test_no_two_labels_of_the_field_figure_overlap(house_plan, mode):
    # registration: the order of field-mode=registration, with the targets each link gets
    fp = field_plan(house_plan.problem.sight, house_plan.stations, FieldOptions(mode=mode))
    assert len(fp.order) == len(house_plan.stations) > 1
    if mode == "registration":
        assert fp.targets
    fig = figure(fp)
    assert tuple(fig.get_size_inches()) == pytest.approx(SIZE)
    check_labels(fig, fp)
    red = {t.get_color() for gid, t in labels(fig, "label:target:").items()}
    assert red <= {"tab:red"}  # target names in the targets' colour
    a3 = figure(fp, A3)  # field.pdf's plan page: the labels placed for the paper's size
    assert tuple(a3.get_size_inches()) == pytest.approx(A3)
    check_labels(a3, fp)


def _grid_setups(rows: int) -> None:
    """``rows`` rows of 16 stations 4.4 m x 5 m apart in front of the house: numbers crowd along the rows."""
    site = load_site(INSTANCES / "house_doors.json")
    grid = [(-20.0 + 4.4 * i, -20.0 + 5.0 * j) for j in range(rows) for i in range(16)]
    stations = [
        Candidate(f"F{k:02d}", "house", ScanSide.OUTSIDE, "site", x, y, CandidateKind.GRID)
        for k, (x, y) in enumerate(grid)
    ]
    fp = field_plan(site, stations, FieldOptions(solution_limit=20))
    check_labels(figure(fp), fp)


def test_thirty_two_setups_on_a_grid():
    _grid_setups(2)


@pytest.mark.slow
def test_sixty_four_setups_on_a_grid():
    # four rows: the order's bound on 64 stations (Held-Karp, then branch-and-cut) takes 5-12 s on 2 cores
    _grid_setups(4)
