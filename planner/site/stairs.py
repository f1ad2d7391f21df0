"""Stairs: the vertical connections between the zones of two storeys.

A site read from a building model holds one frame per storey (the rooms of one floor never hide those of
another), so nothing in the plan view joins two storeys. A :class:`Stair` says that a stair leads from a zone of
one storey (``lower_zone``, the room its foot stands in) to a zone of the next (``upper_zone``, the room its top
arrives in) and where it stands: ``footprint``, its plan outline in coordinates that both zones' frames share
(the frames of one building model differ by name only). What a stair does for registration is decided
downstream (:mod:`planner.coverage.stair_links`); the site only records it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.core.errors import InputError
from planner.site.geometry import check_simple_polygon


@dataclass(frozen=True, kw_only=True)
class Stair:
    """A stair from ``lower_zone`` up to ``upper_zone`` (zone ids of two different zones).

    Attributes
    ----------
    name
        The stair's name (the model's element name).
    lower_zone, upper_zone
        The zone its foot stands in and the zone its top arrives in.
    footprint
        Its plan outline (metres, at least 3 vertices, a simple polygon) in the plan coordinates both zones'
        frames share.
    z_min_m, z_max_m
        The bottom and top of the stair (m, the site's vertical datum); information only.
    """

    name: str
    lower_zone: str
    upper_zone: str
    footprint: tuple[tuple[float, float], ...]
    z_min_m: float = 0.0
    z_max_m: float = 0.0

    def __post_init__(self) -> None:
        if self.lower_zone == self.upper_zone:
            raise InputError(
                "a stair joins two different zones", zone=self.lower_zone, field=f"stair {self.name}", value="upper"
            )
        check_simple_polygon(np.asarray(self.footprint, float), what=f"stair {self.name} footprint")

    @property
    def zones(self) -> tuple[str, str]:
        """The lower and the upper zone's ids."""
        return self.lower_zone, self.upper_zone
