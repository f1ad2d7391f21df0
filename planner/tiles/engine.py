"""Running tile tasks: in this process, or as tasks on Dask (an embedded ``LocalCluster`` or a
cluster the caller already has, passed as a ``dask.distributed.Client``).

Each worker of the embedded cluster is one process with one thread and a memory limit
(``memory_per_worker``, default 1.5 GiB): Dask pauses a worker at 80 % of it and restarts one that
passes 95 %. The site, pool and targets are scattered to the workers once; a task returns its
tile's coverage pairs and plan. Results are put back in tile order, so the stitched plan does not
depend on which tile finished first.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from planner.core import progress
from planner.core.errors import UnreachableError, UsageError
from planner.core.settings import DEFAULTS

#: seconds to wait for an existing scheduler to answer
CONNECT_TIMEOUT_S = 10.0
#: a server that accepts the connection gets this many times CONNECT_TIMEOUT_S to complete Dask's handshake
HANDSHAKE_WAITS = 3

#: memory limit of each embedded worker
MEMORY_PER_WORKER: int = DEFAULTS["strategy.worker_memory"]  # bytes


@contextmanager
def dask_client(
    workers: int = 0, scheduler: str | None = None, memory_per_worker: int | str = MEMORY_PER_WORKER
) -> Iterator[Any]:
    """A Dask client: connected to ``scheduler`` (``tcp://HOST:PORT``) when given, else to an embedded
    ``LocalCluster`` of ``workers`` processes (one thread each). Closed on exit."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        client = _connect(scheduler)
        try:
            yield client
        finally:
            client.close()
        return
    if workers < 1:
        raise UsageError("needs at least 1 worker", field="workers", value=workers)
    _memory_bytes(memory_per_worker)
    with (
        LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            memory_limit=memory_per_worker,
            dashboard_address=":0",
            silence_logs=40,
            scheduler_kwargs={"dashboard": False},
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client


def _memory_bytes(size: int | str) -> int:
    """``size`` (bytes, or a text such as ``1.5GiB``) in bytes; a usage error naming it when Dask cannot read it or it is not > 0."""
    from dask.utils import parse_bytes

    try:
        n = int(parse_bytes(size))
    except (ValueError, TypeError) as exc:
        raise UsageError(f"not a memory size such as 1.5GiB ({exc})", field="worker memory", value=size) from None
    if n <= 0:
        raise UsageError("must be > 0 (a memory limit per worker)", field="worker memory", value=size)
    return n


def _connect(scheduler: str) -> Any:
    """``Client(scheduler)``; a malformed address is a usage error, one where no scheduler answers within
    ``CONNECT_TIMEOUT_S`` (or another server answers) an :class:`UnreachableError`, each naming the address."""
    from dask.distributed import Client

    _listens(scheduler)
    try:
        return _within(lambda: Client(scheduler, timeout=CONNECT_TIMEOUT_S), HANDSHAKE_WAITS * CONNECT_TIMEOUT_S)
    except ValueError as exc:  # e.g. "missing port number in address 'host'"
        raise UsageError(
            f"not a scheduler address of the form tcp://HOST:PORT ({exc})", field="scheduler", value=scheduler
        ) from None
    except (OSError, TimeoutError) as exc:
        raise UnreachableError(
            f"no Dask scheduler answers there within {CONNECT_TIMEOUT_S:g} s ({exc})",
            field="scheduler",
            value=scheduler,
        ) from None
    except _Silent:
        raise UnreachableError(
            f"something accepts the connection there, but no Dask scheduler replies within "
            f"{HANDSHAKE_WAITS * CONNECT_TIMEOUT_S:g} s",
            field="scheduler",
            value=scheduler,
        ) from None
    except (AssertionError, MemoryError, KeyError, TypeError) as exc:
        # another server took the handshake: Dask reads its bytes as a frame length (MemoryError) or a reply
        raise UnreachableError(
            f"something answers there, but not as a Dask scheduler ({type(exc).__name__}: {exc})",
            field="scheduler",
            value=scheduler,
        ) from None


class _Silent(Exception):
    """:func:`_within`'s call did not return in time."""


def _within(make: Callable[[], Any], seconds: float) -> Any:
    """``make()`` on a daemon thread, its result or its exception; :class:`_Silent` where it has not returned within
    ``seconds``. Dask's client waits without end for the handshake of a server that accepts and never replies (its
    own timeout covers the connection, not that), and a plan must not hang on a wrong address; the thread left
    waiting is a daemon, so the process still ends."""
    import threading

    box: dict[str, Any] = {}

    def run() -> None:
        try:
            box["got"] = make()
        except BaseException as exc:  # re-raised in the caller's thread
            box["error"] = exc

    thread = threading.Thread(target=run, name="dask client", daemon=True)
    thread.start()
    thread.join(seconds)
    if thread.is_alive():
        raise _Silent
    if "error" in box:
        raise box["error"]
    return box["got"]


def _listens(scheduler: str) -> None:
    """Whether anything accepts a TCP connection at a ``tcp://HOST:PORT`` address within ``CONNECT_TIMEOUT_S``, asked
    before Dask is: where nothing does, :class:`UnreachableError` says so. Dask's own client, meeting a refused or
    silent address under load, can end in its own assertions instead of a timeout (a CI run did), which would then
    read as a server that answers wrongly. Other addresses (no ``tcp://``, no port) are left to Dask."""
    import socket
    from urllib.parse import urlsplit

    if not scheduler.startswith("tcp://"):
        return
    try:
        parts = urlsplit(scheduler)
        host, port = parts.hostname, parts.port
    except ValueError:
        return  # Dask names what is wrong with it
    if not host or port is None:
        return
    try:
        socket.create_connection((host, port), timeout=CONNECT_TIMEOUT_S).close()
    except OSError as exc:  # refused, unreachable, timed out (socket.timeout is an OSError)
        raise UnreachableError(
            f"no Dask scheduler answers there within {CONNECT_TIMEOUT_S:g} s ({exc})",
            field="scheduler",
            value=scheduler,
        ) from None


def run_tasks(
    fn: Callable[..., Any],
    jobs: Sequence[Any],
    shared: dict[str, Any],
    client: Any = None,
    step: str = "tiles",
    describe: Callable[[int, Any], str] | None = None,
) -> list[Any]:
    """``fn(**shared, job=job)`` for every job, in job order; on ``client`` when one is given.

    Progress (jobs done of all) is reported per finished job under ``step``; with ``describe``, each
    finished job's line too (:func:`planner.core.progress.note` of ``describe(index, result)``).
    """
    total = len(jobs)
    if client is None:
        out = []
        for k, job in enumerate(jobs):
            out.append(fn(**shared, job=job))
            if describe is not None:
                progress.note(describe(k, out[-1]))
            progress.report(step, k + 1, total)
        return out
    return _on_client(fn, jobs, _scatter(client, shared), client, step, describe)


class TaskRunner:
    """``submit(fn, job, shared)``: ``fn(**shared, job=job)`` as a task on ``client``, its future returned, for
    a caller that keeps many small tasks in flight with the same ``shared`` dict (the window re-solves): its
    values are sent to the workers once, when a new dict (by identity) comes, not once per task."""

    def __init__(self, client: Any) -> None:
        self.client = client
        self._shared: dict[str, Any] | None = None
        self._scattered: dict[str, Any] = {}

    def submit(self, fn: Callable[..., Any], job: Any, shared: dict[str, Any]) -> Any:
        if shared is not self._shared:
            self._shared, self._scattered = shared, _scatter(self.client, shared)
        return self.client.submit(fn, **self._scattered, job=job, pure=False)


def _scatter(client: Any, shared: dict[str, Any]) -> dict[str, Any]:
    """Each shared value sent to every worker as one object, one future each: ``scatter(v)`` of a list would
    send every element as a key of its own (a key per candidate of a large pool swamps the scheduler until it
    closes the client's connection)."""
    return {k: client.scatter([v], broadcast=True, hash=False)[0] for k, v in shared.items()}


def _on_client(
    fn: Callable[..., Any],
    jobs: Sequence[Any],
    scattered: dict[str, Any],
    client: Any,
    step: str,
    describe: Callable[[int, Any], str] | None = None,
) -> list[Any]:
    from dask.distributed import as_completed

    total = len(jobs)
    futures = [client.submit(fn, **scattered, job=job, pure=False) for job in jobs]
    index = {f.key: k for k, f in enumerate(futures)}
    results: list[Any] = [None] * total
    for done, fut in enumerate(as_completed(futures), 1):
        k = index[fut.key]
        results[k] = fut.result()
        if describe is not None:
            progress.note(describe(k, results[k]))
        progress.report(step, done, total)
    return results
