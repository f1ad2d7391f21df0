"""The connected plane bound's walks done ahead (:mod:`planner.bounds.ring_ahead`): a walk searched all the way gives
every target's ring part (:func:`planner.bounds.plane_ring.ring_of`), and the bound with walks done ahead in a forked
process equals the bound done alone, under counts the walks ahead were not told, when the process fails, and where
no second core is free (then nothing is forked)."""

from __future__ import annotations

import numpy as np
import pytest

import planner
import planner.bounds.ring_ahead as ahead_mod
from planner.bounds.outer import OuterRegions
from planner.bounds.plane_ring import connected_plane_bound, farley_shares
from planner.bounds.ring_ahead import WalksAhead, ahead_order, one_station_sides
from planner.bounds.ring_walks import RingWalks, ring_of, side_graph, side_ring_bound, walked_sides
from planner.plan import PlanOptions, coverage_problem, plan_limits, resolve
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters
from planner.site.validate import validate_site
from planner.solve.milp import MilpOptions

SHARE = 0.3
WORK = 130_000  # level 0 of both zone-sides and level 1 of one (20,000 patches, then 80,000)


def _box(x0: float, y0: float, x1: float, y1: float) -> tuple[tuple[float, float], ...]:
    return ((x0, y0), (x1, y0), (x1, y1), (x0, y1))


@pytest.fixture(scope="module")
def room() -> tuple[Site, object, object]:
    """An L-shaped room and its outside: two zone-sides that both walk rings."""
    inside = ((0, 0), (9, 0), (9, 4), (4, 4), (4, 8), (0, 8))
    zones = (
        Zone("A", ScanSide.INSIDE, inside, (3.0,) * 6),
        Zone("O", ScanSide.OUTSIDE, _box(-3, -3, 14, 12), (3.0,) * 4),
    )
    site = Site("ahead", zones, parameters=Parameters(theta_max_deg=70.0, max_slant_range_m=20.0, overlap=SHARE))
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=planner.OverlapRule(SHARE)))
    problem, _unseen, _ = coverage_problem(resolve(site, options))
    return site, problem, plan_limits(validate_site(site), options)


def _walks(site: Site, problem, limits) -> RingWalks:  # type: ignore[no-untyped-def]
    seen = problem.by_target.getnnz(axis=1) > 0
    return RingWalks(site, problem.targets, limits, SHARE, seen, cache={}, spaces={}, outer_regions=OuterRegions())


def _bound(site: Site, problem, limits, counts: dict[int, int], ahead: WalksAhead | None = None):  # type: ignore[no-untyped-def]
    duals = np.zeros(len(problem.targets))
    return connected_plane_bound(
        site, problem, limits, SHARE, duals, counts, work_patches=WORK, outer_regions=OuterRegions(), ahead=ahead
    )


def _keys(problem) -> list[int]:  # type: ignore[no-untyped-def]
    t = problem.targets
    return [int(k) for k in np.unique(t.zone.astype(np.int64) * 2 + t.side)]


def test_ring_of_caps_the_walk_at_the_target() -> None:
    assert [ring_of(True, 5, t) for t in (3, 5, 6, 9)] == [3, 5, 5, 5]
    assert ring_of(True, None, 4) == 4 and ring_of(False, None, 4) is None and ring_of(False, 3, 4) is None


@pytest.mark.slow
def test_a_walk_searched_all_the_way_gives_every_targets_ring(room) -> None:  # type: ignore[no-untyped-def]
    site, problem, limits = room
    walks = _walks(site, problem, limits)
    for key in _keys(problem):
        pieces, h = walks.side(key), walks.levels(key)[0]
        graph, fam, _cap = side_graph(pieces, SHARE, h)
        assert graph is not None
        walk = graph.unit_walk()  # all the way
        assert walk is not None
        for target in (1, walk - 1, walk, walk + 1, walk + 5):
            assert graph.unit_walk(limit=target - 1.5) in (None, walk) or target <= walk  # the reach of a target
            assert side_ring_bound(pieces, SHARE, h, target) == (ring_of(True, walk, target), fam)


def test_the_order_ahead_starts_with_the_largest_zone_side_and_keeps_to_the_work(room) -> None:  # type: ignore[no-untyped-def]
    site, problem, limits = room
    walks = _walks(site, problem, limits)
    keys = _keys(problem)
    order = ahead_order(walks, keys, WORK)
    sizes = {k: int(np.count_nonzero(walks.key == k)) for k in keys}
    assert order[0][0] == max(keys, key=lambda k: (sizes[k], -k))
    assert [level for _, level in order] == [0, 1] * len(keys)  # 20,000 + 80,000 patches, then 320,000 more


@pytest.mark.slow
@pytest.mark.parametrize("counts", [(9, 9), (1, 9), (9, 1), (30, 30)])
def test_the_bound_with_walks_ahead_is_the_bound_alone(room, counts, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    site, problem, limits = room
    want = dict(zip(_keys(problem), counts))
    alone = _bound(site, problem, limits, want)
    monkeypatch.setattr(ahead_mod, "thread_count", lambda: 2)
    started = WalksAhead.start(_walks(site, problem, limits), WORK)
    assert started is not None
    from_process = started.walked(*_asked(site, problem, limits, want))
    assert from_process is not None and from_process == alone.sides  # the process answered, the same parts
    started = WalksAhead.start(_walks(site, problem, limits), WORK)
    with_ahead = _bound(site, problem, limits, want, started)
    assert with_ahead.sides == alone.sides and with_ahead.bound == alone.bound
    assert any(s.ring is not None for s in alone.sides) or max(counts) == 1


@pytest.mark.slow
def test_a_failed_process_leaves_the_walks_to_this_one(room, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    site, problem, limits = room
    want = dict.fromkeys(_keys(problem), 9)
    alone = _bound(site, problem, limits, want)
    monkeypatch.setattr(ahead_mod, "thread_count", lambda: 2)
    started = WalksAhead.start(_walks(site, problem, limits), WORK)
    assert started is not None
    started._process.kill()
    started._process.join()
    assert started.walked(*_asked(site, problem, limits, want)) is None
    started = WalksAhead.start(_walks(site, problem, limits), WORK)
    started._process.kill()
    assert _bound(site, problem, limits, want, started).sides == alone.sides


def _asked(site: Site, problem, limits, counts):  # type: ignore[no-untyped-def]
    head = farley_shares(site, problem, limits, np.zeros(len(problem.targets)), OuterRegions())
    return head, counts, problem.by_target.getnnz(axis=1) > 0, WORK, 0


def test_nothing_is_forked_without_a_free_core(room, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    site, problem, limits = room
    monkeypatch.setattr(ahead_mod, "thread_count", lambda: 1)
    assert WalksAhead.start(_walks(site, problem, limits), WORK) is None


def test_a_failure_in_the_process_is_quiet_and_leaves_the_walks_here(room, monkeypatch, capfd) -> None:  # type: ignore[no-untyped-def]
    site, problem, limits = room

    def broken(self, *args: int) -> bool:  # type: ignore[no-untyped-def]
        raise RuntimeError("broken walk")

    monkeypatch.setattr(ahead_mod, "thread_count", lambda: 2)
    for name in ("prepare", "walk"):  # ahead and when asked, in the forked copy too
        monkeypatch.setattr(RingWalks, name, broken)
    started = WalksAhead.start(_walks(site, problem, limits), WORK)
    assert started is not None
    assert started.walked(*_asked(site, problem, limits, dict.fromkeys(_keys(problem), 9))) is None
    assert capfd.readouterr().err == ""  # no traceback from the process


@pytest.mark.slow
@pytest.mark.parametrize("how", ["walked ahead", "graphs ahead"])
def test_walks_kept_ahead_give_the_parts_of_walks_done_now(room, how) -> None:  # type: ignore[no-untyped-def]
    site, problem, limits = room
    keys = _keys(problem)
    kept = _walks(site, problem, limits)
    for k, level in ahead_order(kept, keys, WORK):  # what the forked process does, here
        if level < len(kept.levels(k)):
            kept.ahead(k, level) if how == "walked ahead" else kept.prepare(k, level)
    for counts in [(9, 9), (1, 9), (9, 1), (30, 30)]:
        want = dict(zip(keys, counts))
        head = _asked(site, problem, limits, want)[0]
        now = walked_sides(head, _walks(site, problem, limits), want, WORK, 0)
        assert walked_sides(head, kept, want, WORK, 0) == now
        if how == "graphs ahead":  # each graph walked once: the next counts form them again
            kept = _walks(site, problem, limits)
            for k, level in ahead_order(kept, keys, WORK):
                if level < len(kept.levels(k)):
                    kept.prepare(k, level)


def test_zone_sides_told_to_be_skipped_are_still_walked_when_the_counts_ask(room, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    site, problem, limits = room
    want = dict.fromkeys(_keys(problem), 9)
    alone = _bound(site, problem, limits, want)
    monkeypatch.setattr(ahead_mod, "thread_count", lambda: 2)
    started = WalksAhead.start(_walks(site, problem, limits), WORK)
    assert started is not None
    started.skip(_keys(problem))  # none walked ahead: every walk is done when asked
    assert started.walked(*_asked(site, problem, limits, want)) == alone.sides


def test_regions_sent_by_the_parent_give_the_parts_of_regions_drawn_there(room, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """A process started with ``regions_later`` draws the outer regions, takes the inner ones the parent sends (a
    skip sent before them is kept) and answers as the walks done alone; sent none, it draws them itself."""
    from planner.coverage.regions import coverage_regions

    site, problem, limits = room
    want = dict.fromkeys(_keys(problem), 9)
    alone = _bound(site, problem, limits, want)
    monkeypatch.setattr(ahead_mod, "thread_count", lambda: 2)
    started = WalksAhead.start(_walks(site, problem, limits), WORK, regions_later=True)
    assert started is not None
    started.skip(_keys(problem)[:1])
    started.share(coverage_regions(site, problem.targets, limits, None, {}))
    assert started.walked(*_asked(site, problem, limits, want)) == alone.sides
    started = WalksAhead.start(_walks(site, problem, limits), WORK, regions_later=True)
    assert started is not None
    started.share({})  # no region sent: the process draws them itself
    assert started.walked(*_asked(site, problem, limits, want)) == alone.sides


@pytest.mark.parametrize("above", [0, 1, 3, 30])
def test_quick_covers_begun_ahead_are_the_covers_made_for_the_count(room, above) -> None:  # type: ignore[no-untyped-def]
    """A quick cover begun with no goal and told the count while (or after) it runs gives what the cover made for that
    count gives (:func:`planner.bounds.plane_refine.quick_bound`), on both zone-sides, for every count a plan can
    have (at least the bound itself: ``above`` it; at the bound, the cover for the count stops early); a cover ended
    early is not used, and one taken by the caller first is not begun."""
    from planner.bounds.plane_refine import quick_bound

    site, problem, limits = room
    keys = _keys(problem)
    walks = _walks(site, problem, limits)
    for k in keys:
        walks.levels(k)
    target = {k: quick_bound(walks.side(k), SHARE, 1 << 40).bound + above for k in keys}
    want = {k: quick_bound(walks.side(k), SHARE, target[k]) for k in keys}
    ahead = _walks(site, problem, limits)
    for k in keys:
        ahead.levels(k)
    ahead.cover_ahead(keys)
    got = {k: ahead.quick(k, target[k]) for k in keys}
    assert any(g is not None for g in got.values())
    assert all(g is None or g == want[k] for k, g in got.items())  # None: every patch sees one run (not begun)
    ended = _walks(site, problem, limits)
    for k in keys:
        ended.levels(k)
    ended.cover_ahead(keys).join()
    ended.end_covers_ahead([])
    assert all(ended.quick(k, target[k]) is None for k in keys)  # ended early: the caller makes its own
    taken = _walks(site, problem, limits)
    taken.levels(keys[0])
    assert taken.quick(keys[0], target[keys[0]]) is None
    taken.cover_ahead(keys).join()
    assert taken.quick(keys[0], target[keys[0]]) is None  # taken by the caller first: never begun ahead


def test_one_station_sides_are_the_zone_sides_one_candidate_covers() -> None:
    """A 4 x 4 m room seen whole from its centre (the corners 45 deg off the normal, theta_max 70) needs one station;
    the outside of a box needs two at least (a point outside sees at most two of its sides): only the room's inside."""
    zones = (
        Zone("R", ScanSide.INSIDE, _box(0, 0, 4, 4), (3.0,) * 4),
        Zone("O", ScanSide.OUTSIDE, _box(20, 0, 24, 4), (3.0,) * 4),
    )
    site = Site("one", zones, parameters=Parameters(theta_max_deg=70.0, max_slant_range_m=20.0, overlap=SHARE))
    options = PlanOptions(method="milp", precision=False, milp=MilpOptions(overlap=planner.OverlapRule(SHARE)))
    problem, _unseen, _ = coverage_problem(resolve(site, options))
    t = problem.targets
    key = t.zone.astype(np.int64) * 2 + t.side
    seen = problem.by_target.getnnz(axis=1) > 0
    brute = []  # every candidate's row against each zone-side's seen pieces, as sets
    rows = [set(problem.by_candidate[i].indices.tolist()) for i in range(problem.shape[0])]
    for k in sorted({int(x) for x in key[seen]}):
        need = set(np.flatnonzero(seen & (key == k)).tolist())
        if any(need <= r for r in rows):
            brute.append(k)
    assert one_station_sides(problem) == brute == [2 * t.zone_ids.index("R")]
