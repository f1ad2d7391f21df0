"""The floor probe (which candidates a plan of the bound's size can use; a refuted floor lifts the bound), the stall
rule (a block stops after a whole slice of work without a better plan or bound) and the gap's reason in words."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pytest
import scipy.sparse as sp

from planner.coverage.overlap import OverlapRule
from planner.solve.floor import floor_candidates
from planner.solve.milp import MilpOptions, _run, solve
from planner.solve.result import MilpStats, RingStats, WorkStats, gap_reason
from tests.solve.test_milp import instance


def _matrix(cover: list[set[int]], n_targets: int) -> sp.csr_matrix:
    rows = [i for i, c in enumerate(cover) for _ in c]
    cols = [t for c in cover for t in sorted(c)]
    return sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(cover), n_targets))


def test_floor_keeps_only_the_candidates_of_a_plain_cover_of_the_floors_size():
    # room 1 (targets 0-3): c0 sees it all, c1 and c2 halves; room 2 (targets 4-7): c3 + c4 or c5 + c6 (no one
    # station sees it all), c7 a third of it that no pair completes; c8 sees nothing (a doorway bridge)
    cover = [{0, 1, 2, 3}, {0, 1}, {2, 3}, {4, 5}, {6, 7}, {4, 5, 6}, {7}, {4}, set()]
    floor = floor_candidates(_matrix(cover, 8), 0.0)
    assert floor is not None and (floor.level, floor.lower) == (3, 3)  # one station in room 1, two in room 2
    assert floor.keep.tolist() == [0, 3, 4, 5, 6]
    # one station higher: every candidate of a cover of 2 in room 1 or 3 in room 2, and the bridge
    wider = floor_candidates(_matrix(cover, 8), 4.0)
    assert wider is not None and wider.level == 4 and wider.keep.tolist() == list(range(9))


# two rooms seen apart, registered through a door: c0 sees room 1 whole (targets 0-3), c1 its far part {2, 3}
# (linked to c0 by 2 m of shared wall), c2 room 2 whole (targets 4-7); only c1 sees through the door to c2
ROOMS = [{0, 1, 2, 3}, {2, 3}, {4, 5, 6, 7}]


def _rooms() -> object:
    from dataclasses import replace

    door = sp.csr_matrix((np.ones(2, dtype=bool), ([1, 2], [2, 1])), shape=(3, 3))
    return replace(instance(ROOMS, 8), links=door)


@pytest.mark.parametrize("probe", [True, False])
def test_a_refuted_floor_lifts_the_bound_to_the_connected_optimum(probe):
    # the plain cover {c0, c2} (2 stations, the cover LP) is not registered: the probe keeps c0 and c2 alone (2 of
    # the 3 candidates), finds them unlinked and proves 3; without it the cut loop proves the same
    opts = MilpOptions(overlap=OverlapRule(0.3), ring_bound=False, floor_probe=probe, time_limit_s=30)
    r = solve(_rooms(), opts)
    assert r.status.value == "optimal" and r.selected == (0, 1, 2) and r.bound == 3
    probes = r.info["floor"]
    assert [(p["level"], p["candidates"], p["outcome"]) for p in probes] == ([(2, 2, "refuted")] if probe else [])


@dataclass
class _Block:
    """A stand-in for a block: each round of its loop spends ``step`` work (or what is left), up to ``o.max_rounds``
    rounds a call, and the plan improves at the end of the rounds that pass the works in ``better``."""

    better: list[float]
    step: float = 1.0
    work_used: float = 0.0
    rounds: int = 0
    done: bool = False
    bound: float = 5.0
    o: MilpOptions = field(default_factory=MilpOptions)
    incumbent: list[int] = field(default_factory=lambda: list(range(9)))
    cost: np.ndarray = field(default_factory=lambda: np.ones(10))

    def run(self, deadline: float, work_until: float) -> None:
        while self.work_used < work_until - 1e-9 and self.rounds < self.o.max_rounds:
            self.work_used = min(work_until, self.work_used + self.step)
            self.rounds += 1
            if self.better and self.work_used >= self.better[0]:
                self.better.pop(0)
                self.incumbent = self.incumbent[:-1]


def test_the_stall_rule_stops_at_the_end_of_a_round_long_enough_after_the_last_progress():
    # rounds of 1 work-s; better plans at 1, 3 and 6: with a stall of 3 the block stops after the round ending at 9
    block = _Block(better=[1.0, 3.0, 6.0])
    assert _run(block, np.inf, 25.0, 3.0) is True  # type: ignore[arg-type]
    assert (block.work_used, block.rounds, len(block.incumbent)) == (9.0, 9, 6)
    assert block.o.max_rounds == MilpOptions().max_rounds  # its options as they were
    # a round longer than the stall is never cut: rounds of 5 work-s, progress in the first, a stall of 2
    long = _Block(better=[5.0], step=5.0)
    assert _run(long, np.inf, 25.0, 2.0) is True and long.work_used == 10.0  # type: ignore[arg-type]
    # without the rule, or when the work limit comes first, it runs to the limit and does not say it stalled
    assert _run(_Block(better=[1.0]), np.inf, 25.0, None) is False  # type: ignore[arg-type]
    late = _Block(better=[1.0, 3.0, 6.0])
    assert _run(late, np.inf, 7.0, 3.0) is False and late.work_used == 7.0  # type: ignore[arg-type]


def _stats(stop: str, floor: tuple = ()) -> MilpStats:
    return MilpStats(
        rounds=3,
        cuts=1500,
        connected=True,
        local_search_moves=500,
        ring_bound=RingStats(blocks=0, closed_before_search=0, lagrange_steps=0, work_capped_blocks=0),
        connectivity="loop",
        plain_start=None,
        work=WorkStats(25.0, 6.3, None, None, False, 4.0, stop == "stalled"),
        floor=floor,
        stop=stop,
    )


def test_the_gap_is_said_in_words():
    probe = {"level": 20, "candidates": 831, "of": 1869, "outcome": "refuted", "work": 2.3, "rounds": 4, "cuts": 1526}
    words = gap_reason(_stats("stalled", (probe,)), 22.0, 21.0)
    assert words is not None
    assert words.startswith("gap 1 station: the solver stopped after 6.3 work-s (seconds of counted solver work, the")
    assert "the same on any machine): no better plan or bound in its last 4 work-s; bound 21" in words
    assert "bound 21 from the floor probe: no registered plan of 20 stations among the 831 of 1,869 candidates" in words
    assert "no plan of 21 stations found by the connected greedy, 7 rounds of the cut loop (3,026 registration" in words
    limit = gap_reason(_stats("work_limit"), 25.0, 22.5)
    assert limit is not None and limit.startswith("gap 2 stations: the solver stopped at its work limit of 25")
    assert "from the cover LP" in limit and "no plan of 23 to 24 stations" in limit
    assert gap_reason(_stats("stalled"), 21.0, 20.2) is None  # the bound's ceiling is the plan: no gap in stations


def _corridor_of_rooms(n: int):
    """``n`` rooms in a row, seen apart: room r's targets 4r..4r+3, one candidate sees it whole, two see its halves
    (each linked to the whole by 2 m of shared wall); the doors link room r's right half to room r+1's left half."""
    from dataclasses import replace

    cover = [
        s
        for r in range(n)
        for s in ({4 * r, 4 * r + 1, 4 * r + 2, 4 * r + 3}, {4 * r, 4 * r + 1}, {4 * r + 2, 4 * r + 3})
    ]
    doors = [(3 * r + 2, 3 * (r + 1) + 1) for r in range(n - 1)]
    rows, cols = [i for i, j in doors] + [j for i, j in doors], [j for i, j in doors] + [i for i, j in doors]
    links = sp.csr_matrix((np.ones(len(rows), dtype=bool), (rows, cols)), shape=(len(cover), len(cover)))
    return replace(instance(cover, 4 * n), links=links)


@pytest.mark.slow
def test_the_probe_agrees_with_the_cut_loop_on_a_row_of_rooms():
    # the plain optimum (every room's whole view, 5 stations) is not registered: the probe refutes 5 on the 5 whole
    # views alone; the plan and its proof are those of the cut loop without the probe
    site = _corridor_of_rooms(5)
    opts = MilpOptions(overlap=OverlapRule(0.3), ring_bound=False, time_limit_s=60)
    with_probe, without = solve(site, opts), solve(site, opts, floor_probe=False)
    assert with_probe.status.value == without.status.value == "optimal"
    assert with_probe.objective == without.objective and with_probe.bound == without.bound
    first = with_probe.info["floor"][0]
    assert (first["level"], first["candidates"], first["outcome"]) == (5, 5, "refuted")
    chosen = site.by_candidate[list(with_probe.selected)]
    assert np.all(chosen.sum(axis=0) >= 1)  # a cover
