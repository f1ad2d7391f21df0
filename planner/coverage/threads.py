"""A few threads for geometry: GEOS calls release Python's lock, so independent shapely work (the chunks of a batch of
coverage regions, a medial axis beside them, two buffers of one zone-side) runs side by side on the cores this process
may use and are free (:func:`thread_count`). Each task computes exactly what it computes alone and the results are taken
in their order, so a run gives the same plan with any number of threads; only its wall time changes.

Nothing here prepares or changes a geometry that another task reads: tasks only read shared geometries and make their
own.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterable
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any, TypeVar

T = TypeVar("T")
R = TypeVar("R")

#: threads at most, fewer where this process may use fewer cores (memory grows with the tasks under way)
MAX_THREADS = 4


def thread_count() -> int:
    """The threads to use: the cores this process may run on that are free (less the load average of the last
    minute or the threads running now, whichever is less, this process's own thread counted free), at most
    :data:`MAX_THREADS`, at least 1. On a busy machine the
    work stays on one thread: threads that cannot run side by side only pass Python's lock to and fro."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cores = os.cpu_count() or 1
    try:
        busy = os.getloadavg()[0]
    except (AttributeError, OSError):  # no load average here: take the cores as free
        busy = 0.0
    busy = min(busy, _running_now())
    free = math.floor(cores - busy + 1.0)
    return max(1, min(MAX_THREADS, cores, free))


def _running_now() -> float:
    """The threads running or ready to run on the machine now, this one among them (``/proc/loadavg``'s fourth field):
    the last minute's load average lags by a minute, so that a plan started right after another found the cores busy
    that the other had just left. Infinity where not known (the load average decides alone)."""
    try:
        with open("/proc/loadavg", encoding="ascii") as f:
            return float(f.read().split()[3].split("/")[0])
    except (OSError, IndexError, ValueError):
        return math.inf


def ordered_map(fn: Callable[[T], R], items: Iterable[T]) -> list[R]:
    """``[fn(x) for x in items]``, the calls spread over :func:`thread_count` threads; the first error is raised."""
    todo = list(items)
    workers = min(thread_count(), len(todo))
    if workers <= 1:
        return [fn(x) for x in todo]
    with ThreadPoolExecutor(workers) as pool:
        return list(pool.map(fn, todo))


class Background:
    """Calls started now on threads of their own, to be waited for with their futures' ``result()`` (which raises the
    call's error). Where the process has one core, each call runs at once, when it is started."""

    def __init__(self) -> None:
        n = thread_count()
        self._pool = ThreadPoolExecutor(n - 1) if n > 1 else None

    def start(self, fn: Callable[..., R], *args: Any, **kwargs: Any) -> Future[R]:
        """Start ``fn(*args, **kwargs)``; its future."""
        if self._pool is not None:
            return self._pool.submit(fn, *args, **kwargs)
        done: Future[R] = Future()
        try:
            done.set_result(fn(*args, **kwargs))
        except Exception as err:  # handed to the caller by result(), as the pool does
            done.set_exception(err)
        return done

    def close(self) -> None:
        """Wait for every call started and free the threads."""
        if self._pool is not None:
            self._pool.shutdown(wait=True)

    def __enter__(self) -> Background:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
