"""Progress of long steps (coverage build, solving with a time limit) and where a long run stands.

Library code only calls :func:`report` / :func:`ticking` (a step's share done, logged at DEBUG) and
:func:`note` (one line when a tile or a phase ends, with the incumbent and the bound; logged at INFO), which
pass them to a sink, None (nothing shown) unless a front end installs one. The command line installs a
:class:`Bar` on standard error when it is a terminal and ``--quiet`` is not given; :class:`Lines` is the sink for a
standard error that is not a terminal (a log file, a pipe): whole lines, at most one every few seconds, so that a long
run never looks hung and the log stays short. :func:`sink_for` chooses between them.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TextIO

log = logging.getLogger(__name__)

Sink = Callable[[str, float, float], None]  # (step, done, total); done == total closes the step
_sink: Sink | None = None


def set_sink(sink: Sink | None) -> Sink | None:
    """Install ``sink`` (None: show nothing); return the previous one."""
    global _sink
    previous, _sink = _sink, sink
    return previous


def report(step: str, done: float, total: float) -> None:
    """Say that ``done`` of ``total`` units of ``step`` are done."""
    log.debug("%s: %.1f/%.1f", step, done, total)
    if _sink is not None:
        _sink(step, done, total)


def note(text: str) -> None:
    """Say where a long run stands in one line (a tile or a phase ended: its incumbent and bound); the sink
    shows it when it has a ``note`` method (:class:`Bar` does)."""
    log.info("%s", text)
    shown = getattr(_sink, "note", None)
    if shown is not None:
        shown(text)


@contextmanager
def ticking(step: str, limit_s: float | None, every_s: float = 0.25) -> Iterator[None]:
    """Report elapsed time against ``limit_s`` from a background thread while the body runs
    (a solver that gives no progress of its own); closes the step at the end. Without a limit, the elapsed time
    against a total of 0 (unknown): :class:`Lines` says the step is running, :class:`Bar` draws nothing."""
    if _sink is None:
        yield
        return
    stop = threading.Event()
    start = time.monotonic()
    cap = float(limit_s) if limit_s is not None and limit_s > 0 else 0.0

    def tick() -> None:
        while not stop.wait(every_s):
            elapsed = time.monotonic() - start
            report(step, min(elapsed, cap), cap) if cap > 0 else report(step, elapsed, 0.0)

    thread = threading.Thread(target=tick, daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()
        if cap > 0:
            report(step, cap, cap)


class Bar:
    """A one-line text bar redrawn in place (``\\r``), e.g. ``coverage  [#######.....]  58 %``."""

    def __init__(self, stream: TextIO, width: int = 30) -> None:
        self.stream = stream
        self.width = width
        self._closed = ""

    def __call__(self, step: str, done: float, total: float) -> None:
        if total <= 0:
            return  # a step of unknown length (a solve without a time limit): no bar to draw
        frac = max(0.0, min(1.0, done / total))
        if step == self._closed:
            if frac >= 1.0:
                return  # already drawn complete
            self._closed = ""
        fill = round(frac * self.width)
        self.stream.write(f"\r{step[:28]:<28} [{'#' * fill}{'.' * (self.width - fill)}] {frac * 100:3.0f} %")
        if frac >= 1.0:
            self.stream.write("\n")
            self._closed = step
        self.stream.flush()

    def note(self, text: str) -> None:
        """A line of its own above the bar (the bar is redrawn by the next report)."""
        self.stream.write(f"\r{text:<{self.width + 36}}\n")
        self.stream.flush()


class Lines:
    """Progress as whole lines for a stream that is not a terminal, e.g. ``progress: coverage 58 % (41 s)``: nothing
    in the first ``after_s`` seconds of the run (a short run, or a one-line error, writes only what it writes without
    a sink), then a line when at least ``every_s`` seconds have passed since the last one, so that a long run shows it
    is alive and the log stays short; each note (after ``after_s``) on its own line. ``clock``: the time source
    (tests pass their own)."""

    def __init__(
        self,
        stream: TextIO,
        every_s: float = 5.0,
        clock: Callable[[], float] = time.monotonic,
        *,
        after_s: float = 0.0,
    ) -> None:
        self.stream = stream
        self.every_s = every_s
        self.after_s = after_s
        self.clock = clock
        self.start = clock()
        self._last = -float("inf")

    def __call__(self, step: str, done: float, total: float) -> None:
        now = self.clock()
        if now - self.start < self.after_s or now - self._last < self.every_s:
            return
        self._last = now
        share = f"{max(0.0, min(1.0, done / total)) * 100:.0f} %" if total > 0 else "running"
        self.stream.write(f"progress: {step} {share} ({now - self.start:.0f} s)\n")
        self.stream.flush()

    def note(self, text: str) -> None:
        """A line of its own (a phase ended: shown once the run has lasted ``after_s``)."""
        if self.clock() - self.start < self.after_s:
            return
        self.stream.write(f"progress: {text} ({self.clock() - self.start:.0f} s)\n")
        self.stream.flush()


#: a run's lines on a stream that is not a terminal: the first after this many seconds, then at most one as often
LINES_AFTER_S = 30.0


def sink_for(stream: TextIO, quiet: bool = False) -> Sink | None:
    """The progress sink for ``stream``: a :class:`Bar` on a terminal, :class:`Lines` elsewhere (from
    ``LINES_AFTER_S`` into the run, one at most every ``LINES_AFTER_S``), None when ``quiet``."""
    if quiet:
        return None
    isatty = getattr(stream, "isatty", None)
    if isatty is not None and isatty():
        return Bar(stream)
    return Lines(stream, every_s=LINES_AFTER_S, after_s=LINES_AFTER_S)
