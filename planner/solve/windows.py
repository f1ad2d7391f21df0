"""Fewer stations for a large connected plan: re-solve it exactly inside windows of the site (LNS).

The local search (:mod:`planner.solve.local_search`) changes one or two stations a move; a large plan can still hold a
group of stations that a different group, one smaller, would replace. A *window* is a disc of radius ``radius_m``
around one chosen station c. With S the plan, D the chosen stations inside the window and F = S \\ D the ones kept,

    minimise   |N|
    subject to N covers every target that D sees and F does not          (the window's rows)
               N together with F is connected in each registration group  (the overlap relation)

over the candidates N that see one of those targets or stand inside the window. Each connected part of F (per group)
enters the model as one forced node linked to every candidate linked to one of its stations; the model is the
planner's own connected MILP (:func:`planner.solve.milp.solve`, CP-SAT on one thread, stopped on deterministic work).
D is itself a solution, so the answer is never larger; when it is smaller, F + N replaces S (re-checked). This is
Shaw's large-neighbourhood search ("Using constraint programming and local search methods to solve vehicle routing
problems", CP 1998) with an exact MILP as the repair step.

One pass visits every station of the plan as a centre, in an order drawn by a generator of fixed seed (stations
already removed are skipped). Work limits, not clocks, stop each window, so the result depends only on the input and
the options (a wall-clock cap, ``WALL_CAP`` times the work where one is set, is counted when reached).

With ``run`` (tiled plans on Dask), ``batch`` windows are kept in flight, each for the next centre still in the plan,
and their answers taken in order. At the first answer that removes stations the answers still in flight, made for the
old plan, are dropped and their windows solved again: each answer taken was made for the plan the one-at-a-time search
would have given it, so the result does not depend on ``batch`` or on the number of workers.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Hashable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
import scipy.sparse as sp

from planner.core import progress
from planner.core.errors import UsageError
from planner.coverage.overlap import LINKS_ONLY
from planner.solve.connectivity import components, disconnected_groups, group_members
from planner.solve.instance import CoverInstance
from planner.solve.milp import WALL_CAP, MilpOptions, solve
from planner.solve.result import Status


@dataclass(frozen=True, kw_only=True)
class WindowOptions:
    """``radius_m``: window radius around each centre station; ``work_s``: CP-SAT deterministic seconds per window;
    ``passes``: visits of every station as a centre (0: off); ``seed``: order of the centres; ``batch``: windows in
    flight at a time when a task runner is given."""

    radius_m: float = 60.0
    work_s: float = 3.0
    passes: int = 1
    seed: int = 0
    batch: int = 1

    def __post_init__(self) -> None:
        for name, ok, least in (
            ("radius_m", self.radius_m > 0, "> 0"),
            ("work_s", self.work_s > 0, "> 0"),
            ("passes", self.passes >= 0, ">= 0"),
            ("batch", self.batch >= 1, ">= 1"),
        ):
            if not ok:
                raise UsageError(f"must be {least}", field=name, value=getattr(self, name))


@dataclass(frozen=True)
class Windowed:
    """As :class:`planner.solve.local_search.Shrunk`, by windows: ``windows`` solved, ``proven`` optimal, those whose
    wall-clock cap stopped them instead of their work (``wall_cap_hit``: only those may depend on the load)."""

    selected: tuple[int, ...]
    start: int
    windows: int = 0
    proven: int = 0
    wall_cap_hit: int = 0
    history: tuple[tuple[int, int], ...] = ()
    time_s: float = 0.0

    @property
    def removed(self) -> int:
        return self.start - len(self.selected)


class Handle(Protocol):
    """A window being solved: ``result()`` waits for its answer; ``cancel()`` drops it (a Dask future)."""

    def result(self) -> Any: ...

    def cancel(self) -> Any: ...


class Runner(Protocol):
    """``submit(fn, job, shared)``: start ``fn(**shared, job=job)`` (e.g. as a Dask task) and return its handle."""

    def submit(self, fn: Callable[..., Any], job: Any, shared: dict[str, Any]) -> Handle: ...


class _Later:
    """The answer of ``fn(**shared, job=job)``, computed here when asked for (never, when dropped first)."""

    def __init__(self, fn: Callable[..., Any], job: Any, shared: dict[str, Any]) -> None:
        self._call: Callable[[], Any] | None = lambda: fn(**shared, job=job)
        self._answer: Any = None

    def result(self) -> Any:
        if self._call is not None:
            self._answer, self._call = self._call(), None
        return self._answer

    def cancel(self) -> None:
        self._call = None


def window_search(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: Sequence[Hashable],
    plan: Sequence[int],
    xy: np.ndarray,
    options: WindowOptions | None = None,
    floor: int = 1,
    run: Runner | None = None,
) -> Windowed:
    """The smallest connected cover found by re-solving ``plan`` window by window (module docstring); ``a``, ``adj``
    and ``floor`` as for :func:`planner.solve.local_search.shrink`. ``xy``: C x 2 candidate positions (m); ``run``: a
    :class:`Runner` (e.g. :class:`planner.tiles.engine.TaskRunner` on Dask) that keeps ``options.batch`` windows in
    flight (default: here, one after the other)."""
    o = options or WindowOptions()
    in_flight = o.batch if run is not None else 1
    # without a runner: here, one window at a time, as the answers are taken
    submit: Callable[..., Handle] = run.submit if run is not None else _Later
    start = time.perf_counter()
    a, adj = a.astype(bool).tocsr(), adj.astype(bool).tocsr()
    at = a.T.tocsr()
    plan_s = np.array(sorted({int(i) for i in plan}), dtype=np.int64)
    need = np.asarray(a[plan_s].sum(axis=0)).ravel() > 0
    rng = np.random.default_rng(o.seed)
    shared = {"a": a, "at": at, "adj": adj, "groups": tuple(groups), "xy": xy, "need": need, "o": o}
    history: list[tuple[int, int]] = []
    windows = proven = capped = 0
    for _ in range(o.passes):
        order = [int(c) for c in rng.permutation(plan_s)]
        k = 0
        flight: deque[tuple[int, Handle]] = deque()  # (place in the order, its window), all for plan_s as it is
        while len(plan_s) > max(floor, 1):
            while k < len(order) and len(flight) < in_flight:  # the next centres still in the plan
                if order[k] in plan_s:
                    flight.append((k, submit(_window_task, (plan_s, order[k]), shared)))
                k += 1
            if not flight:
                break
            place, handle = flight.popleft()
            new, status, hit = handle.result()
            windows, proven, capped = windows + 1, proven + (status == Status.OPTIMAL), capped + hit
            progress.report("windows", place + 1, len(order))
            if new is not None and len(new) < len(plan_s) and _valid(a, adj, groups, new, need):
                plan_s = new
                history.append((windows, len(plan_s)))
                for _, later in flight:  # made for the old plan: solve those windows again
                    later.cancel()
                flight.clear()
                k = place + 1
        for _, later in flight:  # the plan reached the floor
            later.cancel()
    selected = tuple(int(i) for i in plan_s)
    return Windowed(selected, len(set(plan)), windows, proven, capped, tuple(history), time.perf_counter() - start)


def _window_task(
    a: sp.csr_matrix,
    at: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: Sequence[Hashable],
    xy: np.ndarray,
    need: np.ndarray,
    o: WindowOptions,
    job: tuple[np.ndarray, int],
) -> tuple[np.ndarray | None, Status, bool]:
    """One window's MILP as a task (``job``: the plan and the centre station): the new plan (None when it found
    none), the MILP's status, and whether the wall clock stopped it."""
    plan, centre = job
    inside = np.hypot(*(xy[plan] - xy[centre]).T) <= o.radius_m
    kept = plan[~inside]
    rows = np.flatnonzero(
        need & (np.asarray(a[plan[inside]].sum(axis=0)).ravel() > 0) & (np.asarray(a[kept].sum(axis=0)).ravel() == 0)
    )
    near = np.flatnonzero(np.hypot(*(xy - xy[centre]).T) <= o.radius_m)
    free = np.setdiff1d(np.union1d(np.unique(at[rows].indices), near), kept)
    chosen, status, hit = connected_cover_within(a, adj, groups, free, rows, kept, o.work_s, o.seed)
    if chosen is None:
        return None, status, hit
    return np.union1d(kept, chosen).astype(np.int64), status, hit


def connected_cover_within(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: Sequence[Hashable],
    free: np.ndarray,
    rows: np.ndarray,
    kept: np.ndarray,
    work_s: float,
    seed: int = 0,
) -> tuple[np.ndarray | None, Status, bool]:
    """The fewest candidates of ``free`` that see every target of ``rows`` and, with the stations ``kept``, leave each
    registration group one connected part (the window's MILP; ``kept`` may be empty): the chosen candidates (site
    indices; None when the MILP found no answer), the MILP's status (``OPTIMAL``: no smaller choice within ``free``)
    and whether its wall-clock cap, not its ``work_s`` of CP-SAT deterministic work, stopped it."""
    parts = [(g, p) for g, members in group_members(groups, kept.tolist()).items() for p in components(adj, members)]
    inst = _model(a, adj, groups, free, rows, parts)
    # the window's links are the site's, given explicitly: no overlap test on the window's partial rows
    milp = MilpOptions(
        overlap=LINKS_ONLY, threads=1, seed=seed, greedy_starts=_GREEDY_STARTS, local_search_moves=_SEARCH_MOVES
    ).with_work_limit(work_s, WALL_CAP)
    r = solve(inst, milp)
    if not r.selected:
        return None, r.status, r.wall_cap_hit
    return np.array(sorted(int(free[i]) for i in r.selected if i < free.size), dtype=np.int64), r.status, r.wall_cap_hit


#: a window's MILP: starts of its connected greedy and moves of its block local search (fewer than the single
#: model's defaults: in a window they cost much of the pass and gave the same plan)
_GREEDY_STARTS, _SEARCH_MOVES = 5, 100


def _model(
    a: sp.csr_matrix,
    adj: sp.csr_matrix,
    groups: Sequence[Hashable],
    free: np.ndarray,
    rows: np.ndarray,
    parts: list[tuple[Hashable, list[int]]],
) -> CoverInstance:
    """The window's cover instance: the free candidates on the window's rows, then one forced node per kept part (a
    private row only it sees), linked to the free candidates linked to one of its stations."""
    nf, nk, nt = free.size, len(parts), rows.size
    cover = sp.bmat([[a[free][:, rows], None], [None, sp.identity(nk, dtype=bool, format="csr")]], format="csr")
    stations = np.concatenate([p for _, p in parts]).astype(np.int64) if parts else np.zeros(0, np.int64)
    part_of = np.repeat(np.arange(nk), [len(p) for _, p in parts])
    member = sp.csr_matrix((np.ones(stations.size), (stations, part_of)), shape=(a.shape[0], nk))
    to_parts = sp.csr_matrix((adj[free].astype(np.float64) @ member) > 0)
    links = sp.bmat([[adj[free][:, free], to_parts], [to_parts.T, None]], format="csr").astype(bool)
    labels = tuple([groups[int(i)] for i in free] + [g for g, _ in parts])
    return CoverInstance(
        by_candidate=cover.astype(bool),
        cost=np.ones(nf + nk),
        name="window",
        groups=labels,
        target_length_m=np.ones(nt + nk),
        links=links,
    )


def _valid(
    a: sp.csr_matrix, adj: sp.csr_matrix, groups: Sequence[Hashable], plan: np.ndarray, need: np.ndarray
) -> bool:
    """``plan`` sees every needed target and each of its groups is one part."""
    seen = np.asarray(a[plan].sum(axis=0)).ravel() > 0
    return bool(seen[need].all()) and not disconnected_groups(adj, groups, plan.tolist())
