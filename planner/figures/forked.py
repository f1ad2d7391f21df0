"""Figures rendered on two cores: the later half of a list drawn in a forked process while this one draws the rest.

A report's plan figures are independent once the first has set the layout the others take
(:mod:`planner.figures.layout`), and each costs most of a second of matplotlib work in Python: a thread would hold the
interpreter's lock against this one, so a process draws half. It is forked only where a second core is free
(:func:`planner.coverage.threads.thread_count`), from the main thread, on a platform that forks; where that fails in any
way, this process draws them all. The bytes are the same either way: each item is drawn from the same state.
"""

from __future__ import annotations

import logging
import multiprocessing
import signal
import sys
import threading
from collections.abc import Callable, Sequence
from multiprocessing.connection import Connection
from typing import TypeVar

from planner.core import progress
from planner.coverage.threads import thread_count

T = TypeVar("T")


def drawn(draw: Callable[[T], bytes], items: Sequence[T]) -> list[bytes]:
    """``[draw(x) for x in items]``, the later half drawn in a forked process where a core is free (module
    docstring). ``draw`` must not depend on what the items before it changed."""
    half = len(items) // 2
    conn = _forked(draw, items[len(items) - half :]) if half else None
    mine = [draw(x) for x in items[: len(items) - half]]
    theirs = _answer(conn, half) if conn is not None else None
    if theirs is None:
        theirs = [draw(x) for x in items[len(items) - half :]]
    return mine + theirs


def _forked(draw: Callable[[T], bytes], items: Sequence[T]) -> Connection | None:
    if thread_count() < 2 or threading.current_thread() is not threading.main_thread():
        return None
    if "fork" not in multiprocessing.get_all_start_methods():
        return None
    try:
        for stream in (sys.stdout, sys.stderr):  # nothing buffered is written twice
            stream.flush()
    except (OSError, ValueError, AttributeError):
        return None
    ctx = multiprocessing.get_context("fork")
    here, there = ctx.Pipe(duplex=False)
    process = ctx.Process(target=_draw_there, args=(there, draw, items), daemon=True)
    try:
        process.start()
    except OSError:
        return None
    finally:
        there.close()
    return here


def _answer(conn: Connection, count: int) -> list[bytes] | None:
    """The forked process's images; None where it failed (then this process draws them)."""
    try:
        got = conn.recv()
    except Exception:  # the process gone or its answer unreadable
        return None
    finally:
        conn.close()
    ok = isinstance(got, list) and len(got) == count and all(isinstance(b, bytes) for b in got)
    return got if ok else None


def _draw_there(conn: Connection, draw: Callable[[T], bytes], items: Sequence[T]) -> None:
    """The forked process: the items drawn and sent; any failure ends it quietly (nothing sent)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # an interrupt is the parent's to handle
    logging.disable(logging.CRITICAL)
    progress.set_sink(None)
    try:
        conn.send([draw(x) for x in items])
    except BaseException:
        return
    finally:
        conn.close()
