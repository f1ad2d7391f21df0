"""Figures: headless, titled, with a scale bar and north arrow; uncovered pieces drawn red; the
comparison figure from benchmark rows."""

from __future__ import annotations

from matplotlib.collections import LineCollection
from matplotlib.colors import to_rgba

import planner
from planner.coverage.relation import Registration
from planner.coverage.visibility import sight_limits
from planner.figures.base import nice_length
from planner.figures.compare import comparison_figure
from planner.figures.plan_fig import plan_figure
from planner.plan.outcome import Outcome
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide


def test_nice_length_is_round_and_near_a_fifth():
    # 100 m wide -> target 20 -> 20 m; 37 m -> 7.4 -> 5 (|2.4| < |2.6| for 10); 0.9 m -> 0.18 -> 0.2
    assert nice_length(100.0) == 20.0
    assert nice_length(37.0) == 5.0
    assert abs(nice_length(0.9) - 0.2) < 1e-12


def square_outcome(stations: list[Candidate], side_m: float = 10.0) -> Outcome:
    """A square room ``side_m`` wide (walls 3 m) with the given stations; S_max 30 m."""
    a = side_m
    zone = planner.Zone("S", ScanSide.INSIDE, ((0, 0), (a, 0), (a, a), (0, a)), (3.0,) * 4)
    site = planner.Site("square", (zone,), planner.Parameters(max_slant_range_m=30.0))
    v = planner.validate_site(site)
    limits = sight_limits(v, False, True)
    sight = planner.Sight(site=site, limits=limits, scanner=v.scanner)
    cov = planner.station_coverage(sight, stations)
    ver = planner.verify_stations(sight, stations)
    return Outcome(
        site=site,
        validation=v,
        limits=limits,
        stations=tuple(stations),
        coverage=cov,
        verification=ver,
        tripod_radius_m={s.id: 0.5 for s in stations},
        meta={"method": "hand"},
        registration=Registration.of(sight),
    )


def test_uncovered_pieces_are_drawn_red():
    # one station 1 m in front of wall 1's middle (x = 5): at theta_max 68 deg it sees wall 1 only within
    # 1 x tan 68 = 2.475 m of x = 5, so of wall 1's ten 1 m pieces only 3-4 .. 6-7 are whole in view and the
    # six pieces 0-1, 1-2, 2-3, 7-8, 8-9, 9-10 are uncovered; walls 2-4 are seen at <= atan(9/5) = 60.9 deg
    st = Candidate("K1", "S", ScanSide.INSIDE, "site", 5.0, 1.0, CandidateKind.WALL)
    o = square_outcome([st])
    assert int((o.coverage.count == 0).sum()) == 6
    fig = plan_figure(o, "S", "inside")
    red = to_rgba("red")
    for ax in fig.axes[:2]:  # the two panels (colour bars come after)
        reds = [
            c
            for c in ax.collections
            if isinstance(c, LineCollection) and len(c.get_colors()) and tuple(c.get_colors()[0]) == red
        ]
        assert len(reds) == 1 and len(reds[0].get_segments()) == 6
    titles = [ax.get_title() for ax in fig.axes]
    assert any("coverage count" in t for t in titles) and any("incidence" in t for t in titles)
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert any(t.endswith(" m") for t in texts)  # scale bar label
    assert any(t.startswith("N") for t in texts)  # north arrow
    assert "square" in fig._suptitle.get_text()


def test_comparison_figure_from_benchmark_rows():
    keys = ("instance", "method", "backend", "overlap", "stations", "time_s", "status")
    rows = [
        dict(zip(keys, row))
        for row in [
            ("a", "closed-form", "", "no", "28", "0.02", "feasible"),
            ("a", "greedy", "", "no", "26", "0.01", "feasible"),
            ("a", "milp", "cpsat", "no", "19", "0.5", "optimal"),
            ("a", "milp", "cbc", "no", "19", "0.6", "optimal"),
        ]
    ]
    fig = comparison_figure(rows)
    ax_counts, ax_times = fig.axes[:2]
    heights = sorted(round(p.get_height()) for p in ax_counts.patches)
    assert heights == [19, 26, 28]  # closed form, greedy, MILP
    assert ax_times.get_yscale() == "log"
    assert len(ax_times.patches) == 2  # one bar per backend
