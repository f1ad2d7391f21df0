"""What a site holds beside its zones: openings in walls, obstacles, no-go areas, control points and
corrections of printed data. Frozen and validated on construction, like :mod:`planner.site.model`."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.core.errors import InputError
from planner.site.geometry import MAX_COORDINATE_M, check_simple_polygon
from planner.site.params import HEIGHT_RULE, height_ok

#: the frame of zones given by coordinates, obstacles, no-go areas, boundary and control points
SITE_FRAME = "site"


#: ``passage``: a gap one walks through that no door fills (an unfilled wall opening, two rooms open to each other)
OPENING_KINDS = ("door", "gate", "window", "passage")


@dataclass(frozen=True)
class Opening:
    """A gap in one wall of a zone (door, gate, window, passage): ``s0_m``..``s1_m`` along wall ``wall``
    (1-based, the zone's numbering: outline first, then holes). What it does for sight and
    targets is decided downstream (coverage); this object only holds where it is."""

    wall: int
    s0_m: float
    s1_m: float
    kind: str = "door"
    name: str = ""

    def __post_init__(self) -> None:
        name = self.name or None
        if self.kind not in OPENING_KINDS:
            raise InputError(
                f"must be one of {', '.join(OPENING_KINDS)}", zone=name, field="opening kind", value=self.kind
            )
        if not (math.isfinite(self.s0_m) and math.isfinite(self.s1_m) and 0.0 <= self.s0_m < self.s1_m):
            raise InputError("needs 0 <= s0_m < s1_m", zone=name, field="opening", value=f"{self.s0_m}..{self.s1_m}")


@dataclass(frozen=True)
class Obstacle:
    """Something that blocks sight and where no station can stand (a column, a crane)."""

    name: str
    vertices: tuple[tuple[float, float], ...]
    height_m: float

    def __post_init__(self) -> None:
        check_simple_polygon(np.asarray(self.vertices, float), what="obstacle", zone=self.name)
        if not height_ok(self.height_m):
            raise InputError(HEIGHT_RULE, zone=self.name, field="height_m", value=self.height_m)


@dataclass(frozen=True)
class NoGoArea:
    """Where no station may stand; sight passes over it (a lawn, a road, a grave)."""

    name: str
    vertices: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        check_simple_polygon(np.asarray(self.vertices, float), what="no_go", zone=self.name)


@dataclass(frozen=True)
class ControlPoint:
    """A coordinated point of the control network; sigmas 0 mean fixed (error-free)."""

    name: str
    x: float
    y: float
    z: float | None = None
    sigma_x_m: float = 0.0
    sigma_y_m: float = 0.0
    proposed: bool = False
    frame: str = SITE_FRAME  # a proposed point belongs to the frame of the stations it serves

    def __post_init__(self) -> None:
        for f in ("x", "y", "z", "sigma_x_m", "sigma_y_m"):
            v = getattr(self, f)
            if v is None:
                continue
            sigma = f.startswith("sigma")  # coordinates within the zones' +-1e8 m
            if not math.isfinite(v) or (sigma and v < 0) or (not sigma and abs(v) > MAX_COORDINATE_M):
                need = " >= 0" if sigma else f" within +-{MAX_COORDINATE_M:g} m"
                raise InputError(f"must be a finite number{need}", row=f"control point {self.name}", field=f, value=v)


@dataclass(frozen=True)
class Correction:
    """A correction of printed data, kept beside the printed value and the reason."""

    zone: str
    row: int  # the side / vertex index of the table
    field: str
    printed: float
    corrected: float
    reason: str

    @property
    def target(self) -> str:
        kind = "vertex" if self.field in ("interior_angle_deg", "vertex_height_m") else "side"
        return f"{kind} {self.row}"
