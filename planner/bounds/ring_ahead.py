"""The connected plane bound's ring walks started ahead, on a second core, while the plan is still being made.

The walks (:mod:`planner.bounds.ring_walks`) need no duals and no plan: a zone-side walked at a patch side all the way
serves any counts later (:func:`planner.bounds.ring_walks.ring_of`). Only *which* walks the bound takes depends on the
plan's counts per zone-side. So a forked process draws the zone-sides' regions, forms their ring graphs and walks them,
the largest zone-side first and each level in turn, while this process prices and solves. When the plan is known,
:meth:`WalksAhead.walked` sends it the shares of Farley's bound and the counts; it finishes the bound exactly as
:func:`planner.bounds.ring_walks.walked_sides` does alone (the walks it has not done yet it does then) and sends back
the zone-sides' parts. The bound is the same, with or without it.

A process, not a thread: the walks are numpy and shapely work in many short calls, and a thread beside the solver's
Python work would pass the interpreter's lock to and fro. It is forked only where this process may use a second core
that is free (:func:`planner.coverage.threads.thread_count`), from the main thread, on a platform that forks; where
it fails in any way, the walks are done in this process.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import signal
import sys
import threading
from multiprocessing.connection import Connection
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.bounds.connected_result import SideBound
from planner.bounds.plane_patches import FIRST_PATCHES
from planner.bounds.ring_walks import FarleyShares, RingWalks, walked_sides
from planner.core import progress
from planner.coverage.matrix import CoverageProblem
from planner.coverage.threads import thread_count

#: seconds between checks that the process walking ahead is still alive, while its answer is awaited
_POLL_S = 0.05


class WalksAhead:
    """A forked process walking the zone-sides of ``walks`` ahead (module docstring); :meth:`walked` takes its result,
    :meth:`close` ends it."""

    def __init__(self, process: Any, conn: Connection) -> None:
        self._process, self._conn = process, conn

    @classmethod
    def start(cls, walks: RingWalks, work_patches: int, regions_later: bool = False) -> WalksAhead | None:
        """Fork the process walking ``walks`` ahead; None (nothing started) where no free second core, not the main
        thread, or no fork. ``regions_later``: the caller draws the inner regions of every piece now and sends them
        (:meth:`share`); the process draws the outer ones meanwhile, then takes them (each region drawn once)."""
        if thread_count() < 2 or threading.current_thread() is not threading.main_thread():
            return None
        if "fork" not in multiprocessing.get_all_start_methods():
            return None
        try:
            for stream in (sys.stdout, sys.stderr):  # nothing buffered is written twice
                stream.flush()
        except (OSError, ValueError, AttributeError):  # a closed or missing stream: no fork, the walks are done here
            return None
        ctx = multiprocessing.get_context("fork")
        here, there = ctx.Pipe()
        process = ctx.Process(target=_walk_ahead, args=(there, walks, work_patches, regions_later), daemon=True)
        try:
            process.start()
        except OSError:
            return None
        finally:
            there.close()
        return cls(process, here)

    def share(self, regions: dict[int, Any]) -> None:
        """Send the inner regions drawn here (piece -> geometry) to a process started with ``regions_later``. Nothing
        is awaited; a broken pipe is left to :meth:`walked`."""
        try:
            self._conn.send(("regions", regions))
        except Exception:  # the process gone: walked() finds it so and the caller walks them itself
            pass

    def skip(self, keys: list[int]) -> None:
        """Tell the process that the zone-sides ``keys`` need no walk ahead (:func:`one_station_sides`); it walks them
        later only if the plan's counts ask for them. Nothing is awaited; a broken pipe is left to :meth:`walked`."""
        if keys:
            try:
                self._conn.send(("skip", [int(k) for k in keys]))
            except Exception:  # the process gone: walked() finds it so and the caller walks them itself
                pass

    def walked(
        self,
        head: FarleyShares,
        counts: dict[int, int],
        required: NDArray[np.bool_],
        work_patches: int,
        refine_steps: int,
    ) -> tuple[SideBound, ...] | None:
        """The zone-sides' parts (:func:`planner.bounds.ring_walks.walked_sides` of ``head`` under ``counts``), from
        the process; None where it failed (then the caller walks them itself)."""
        try:
            self._conn.send((head, counts, np.asarray(required, dtype=bool), work_patches, refine_steps))
            while not self._conn.poll(_POLL_S):
                if not self._process.is_alive() and not self._conn.poll():
                    return None
            kind, got = self._conn.recv()
        except Exception:  # the pipe broken or the answer unreadable: the caller walks them itself
            return None
        finally:
            self.close()
        return got if kind == "sides" else None

    def close(self) -> None:
        """End the process (it walks nothing more) and free its pipe."""
        if self._process.is_alive():
            self._process.terminate()
        self._process.join(timeout=5)
        self._conn.close()


def ahead_order(walks: RingWalks, keys: list[int], work_patches: int) -> list[tuple[int, int]]:
    """The walks to do ahead, in turn: the zone-sides with the most pieces first, each at its patch sides while their
    cost alone stays within ``work_patches`` (no schedule under any counts walks one beyond)."""
    sizes = {k: int(np.count_nonzero(walks.key == k)) for k in keys}
    order = []
    for k in sorted(keys, key=lambda k: (-sizes[k], k)):
        spent = 0
        for level in range(32):
            spent += FIRST_PATCHES * 4**level
            if spent > work_patches:
                break
            order.append((k, level))
    return order


def _second_core() -> None:
    """Keep the walks ahead to one core and behind the parent's own work: the parent may draw regions on threads of
    its own meanwhile (:func:`planner.coverage.threads.thread_count`), and its work is the run's."""
    try:
        os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})
        os.nice(5)
    except (AttributeError, OSError):  # not on Linux, or not allowed: the walks run as they are
        pass


def _walk_ahead(conn: Connection, walks: RingWalks, work_patches: int, regions_later: bool = False) -> None:
    """The forked process: ring graphs and walks ahead until asked (:func:`_until_asked`), then the bound's parts under
    the counts sent. It writes nothing: any failure ends it quietly, and the parent then walks them itself."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # an interrupt is the parent's to handle (it ends this process)
    logging.disable(logging.CRITICAL)
    progress.set_sink(None)  # the run's progress is this process's parent's to show
    _second_core()
    try:
        head, counts, required, spent, refine_steps = _until_asked(conn, walks, work_patches, regions_later)
        if not np.array_equal(required, walks.required):  # other pieces to cover: walks done ahead do not serve
            walks = RingWalks(
                walks.site,
                walks.targets,
                walks.limits,
                walks.share,
                required,
                cache=walks.cache,
                spaces=walks.spaces,
                outer_regions=walks.outer_regions,
            )
        conn.send(("sides", walked_sides(head, walks, counts, spent, refine_steps)))
    except BaseException:  # the parent gone, or a failure here: the parent walks them itself
        return


def _until_asked(conn: Connection, walks: RingWalks, work_patches: int, regions_later: bool = False) -> Any:
    """The walks of :func:`ahead_order` until the parent asks, then its request: each ring graph formed, then walked
    all the way and let go before the next is formed (one graph held at a time: a zone-side's finer graph runs to
    hundreds of megabytes). Zone-sides the parent says need none (:meth:`WalksAhead.skip`) are passed over. With
    ``regions_later``, the outer regions of every zone-side to walk are drawn first and the inner ones then taken
    from the parent (:meth:`WalksAhead.share`)."""
    keys = [int(k) for k in np.unique(walks.key[walks.required])] if walks.share > 0 else []
    closed: set[int] = set()
    skipped: set[int] = set()  # the zone-sides the parent said need no walk (closed too)

    def asked(wait: bool = False) -> Any:
        while wait or conn.poll():
            message = conn.recv()
            if message[0] == "regions":
                walks.cache.update(message[1])
                return None
            if message[0] != "skip":
                return message
            closed.update(message[1])
            skipped.update(message[1])
        return None

    if regions_later:
        pieces = np.flatnonzero(np.isin(walks.key, keys))
        walks.outer_regions.of(walks.site, walks.targets, walks.limits, pieces)
        if (got := asked(wait=True)) is not None:
            return got

    for k, level in ahead_order(walks, keys, work_patches):
        if (got := asked()) is not None:
            return got
        if k in closed:
            continue
        sides = len(walks.levels(k))  # the zone-side's pieces drawn first: a skip may come meanwhile
        if (got := asked()) is not None:
            return got
        if k in closed or level >= sides:
            continue
        if not walks.prepare(k, level):
            closed.add(k)  # not formed: no walk at a finer side is taken either
            continue
        if (got := asked()) is not None:
            return got
        if k not in closed:
            walks.ahead(k, level)
    # the walks done: the two largest zone-sides' quick covers begun while the plan is still made (where the counts ask
    # for it, they wait on it); the smaller ones cost little when asked, and begun here they would take the core the
    # plan's own threads may be using
    walks.cover_ahead([k for k, level in ahead_order(walks, keys, work_patches) if level == 0 and k not in skipped][:2])
    while (got := asked()) is None:
        conn.poll(None)
    return got


def one_station_sides(problem: CoverageProblem) -> list[int]:
    """The zone-sides (keys ``2 zone + side``) whose every seen piece one candidate of the pool covers: no plan needs
    more than one station there, so no walk of theirs can raise the bound above one (the ring walk is at most the
    pool's optimum), and walking them ahead is wasted."""
    t, by = problem.targets, problem.by_candidate
    seen = problem.by_target.getnnz(axis=1) > 0
    key = t.zone.astype(np.int64) * 2 + t.side
    keys, col = np.unique(key[seen], return_inverse=True)
    if keys.size == 0:
        return []
    onehot = sp.csr_matrix((np.ones(col.size), (np.flatnonzero(seen), col)), shape=(len(t), keys.size))
    per = (by.astype(np.float64) @ onehot).toarray()  # candidates x zone-sides: pieces seen there
    need = np.bincount(col, minlength=keys.size)
    return [int(k) for k in keys[(per >= need[None, :]).any(axis=0)]]
