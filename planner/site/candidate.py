"""Candidate stations: where a scanner could stand, and why it was proposed."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Any

from planner.core.checks import article, no_repeats, shown
from planner.core.errors import ArgumentTypeError
from planner.site.model import ScanSide


class CandidateKind(str, Enum):
    """Where a candidate comes from (the ``kind`` of a station in plan.json)."""

    VERTEX = "vertex"  # K^B, on the bisector of a corner
    WALL = "wall"  # K^C, in front of a wall
    CIRCLE = "circle"  # one station in the intersection of the vertex circles
    FIELD = "field"  # sampled inside a closed-form candidate's movement field
    GRID = "grid"  # on a grid over the accessible area
    REGION = "region"  # in the common part of a zone-side's coverage regions (one station sees it all)
    AXIS = "axis"  # in a cell of the coverage arrangement along a room's medial axis
    PRICED = "priced"  # a face of the coverage-region arrangement found by geometric pricing


@dataclass(frozen=True)
class Candidate:
    """One candidate station in the frame of its zone, proposed for the face ``zone``/``side`` (it may see other
    faces of the frame too). The closed-form figures (``alpha_deg`` ... ``field_height_m``) are set for vertex
    and wall candidates, for the reproduction tables; ``field``: the movement field polygon, if any."""

    id: str
    zone: str
    side: ScanSide
    frame: str
    x: float
    y: float
    kind: CandidateKind
    vertex: int | None = None
    wall: int | None = None
    alpha_deg: float | None = None
    hd_m: float | None = None
    gamma_deg: float | None = None
    covered_m: float | None = None
    local_x_m: float | None = None
    local_y_m: float | None = None
    field_half_base_m: float | None = None
    field_height_m: float | None = None
    field: tuple[tuple[float, float], ...] | None = None

    @property
    def xy(self) -> tuple[float, float]:
        return (self.x, self.y)


def check_unique_ids(stations: Sequence[Candidate], row: str = "station {}", file: str | None = None) -> None:
    """Stations are keyed by id in the network, the report and the exports: two with one id would merge."""
    no_repeats((s.id for s in stations), what="station id", field="id", row=row, file=file)


def stations_argument(stations: Any) -> None:
    """``stations``: a sequence of candidates (``plan.stations``), not a Plan, a path or one candidate."""
    got = type(stations).__name__
    if not isinstance(stations, (str, bytes)) and isinstance(stations, Iterable):
        if not isinstance(stations, Sequence):  # a generator is left unread
            return
        bad = next((k for k, s in enumerate(stations, 1) if not isinstance(s, Candidate)), None)
        if bad is None:
            return
        got = f"{got} whose item {bad} is {article(type(stations[bad - 1]).__name__)}"
    raise ArgumentTypeError(
        f"must be a sequence of stations (Candidate objects, e.g. plan.stations), not {article(got)}"
        + (" (use plan.stations)" if got == "Plan" else ""),
        field="stations",
        value=shown(stations),
    )
