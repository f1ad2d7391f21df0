"""The one error hierarchy of the planner, and the exit codes the CLI maps it to.

Every error renders as ONE line naming where the problem is (file, zone, row, field) and the offending value, so a
surveyor can find it in the input. Positions count from 1, as a surveyor counts rows and entries:
``control_points[4]`` is the fourth entry of that JSON list, ``row 2`` the second data row of a table.
Exit codes: :class:`ExitCode`.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from enum import IntEnum
from typing import Any


class ExitCode(IntEnum):
    """Process exit codes of the ``planner`` command."""

    OK = 0
    INTERNAL = 1
    USAGE = 2
    INVALID_INPUT = 3
    INFEASIBLE = 4
    UNREACHABLE = 5
    #: standard output closed by its reader (``planner ... | head``): 128 + SIGPIPE, as a shell reports it
    BROKEN_PIPE = 141


def _fmt_value(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.10g}"
    return repr(value) if isinstance(value, str) else str(value)


class PlannerError(Exception):
    """Base of every error the planner raises on purpose: ``message`` says what is wrong (no location);
    ``file``, ``zone``, ``row``, ``field`` and ``value`` where, and what was found there (each optional;
    ``value`` quoted as found, None left out)."""

    exit_code: ExitCode = ExitCode.INTERNAL

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        zone: str | None = None,
        row: int | str | None = None,
        field: str | None = None,
        value: Any = None,
    ) -> None:
        self.message = message
        self.file = file
        self.zone = zone
        self.row = row
        self.field = field
        self.value = value
        super().__init__(self.one_line())

    def one_line(self) -> str:
        """The error as a single line: ``file: zone Z row R: field = value: message``."""
        parts: list[str] = []
        if self.file:
            parts.append(str(self.file))
        where = []
        if self.zone is not None:
            where.append(f"zone {self.zone}")
        if self.row is not None:
            # a bare number is a table row; text such as "line 3" or "vertex 2" speaks for itself
            where.append(f"row {self.row}" if str(self.row).isdigit() else str(self.row))
        if where:
            parts.append(" ".join(where))
        if self.field is not None:
            if self.value is not None:
                parts.append(f"{self.field} = {_fmt_value(self.value)}")
            else:
                parts.append(self.field)
        parts.append(self.message)
        return ": ".join(parts).replace("\n", " ")

    def __str__(self) -> str:
        return self.one_line()

    def located(self, file: str) -> PlannerError:
        """Return the same error with ``file`` filled in where it was missing."""
        if self.file is None:
            self.file = file
            self.args = (self.one_line(),)
        return self


class UsageError(PlannerError, ValueError):
    """The command line or an API call was used wrongly (exit 2)."""

    exit_code = ExitCode.USAGE


class ArgumentTypeError(UsageError, TypeError):
    """A library function was given an object of another kind than it takes (a Plan where an Outcome is
    expected, a path where a Site is): a usage error that is also a TypeError."""


class InputError(PlannerError, ValueError):
    """An input file or value is invalid (exit 3)."""

    exit_code = ExitCode.INVALID_INPUT


class ClosureError(InputError):
    """A zone's traverse does not close within tolerance and was not accepted."""


class InfeasibleError(PlannerError, RuntimeError):
    """The problem as posed has no solution (exit 4): e.g. no instrument error
    budget is left, or some target is seen by no candidate."""

    exit_code = ExitCode.INFEASIBLE


class UnreachableError(PlannerError, RuntimeError):
    """A service the run needs does not answer, e.g. no Dask scheduler at the address given (exit 5):
    nothing is wrong with the input, and the same command may work once the service is up."""

    exit_code = ExitCode.UNREACHABLE


class InternalError(PlannerError, RuntimeError):
    """A bug or an unexpected state inside the planner (exit 1)."""

    exit_code = ExitCode.INTERNAL


@contextmanager
def located_in(file: str | None) -> Iterator[None]:
    """Errors raised inside carry ``file`` where they name none (e.g. a value checked after reading)."""
    try:
        yield
    except PlannerError as exc:
        raise (exc.located(file) if file else exc) from None
