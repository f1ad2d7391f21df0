"""Stairs: the vertical connections between the zones of two storeys.

A site read from a building model holds one frame per storey, so nothing in the plan view joins two
storeys. A :class:`Stair` leads from a zone of one storey (``lower_zone``, where its foot stands) to a
zone of the next (``upper_zone``) and stands at ``footprint``, in coordinates both zones' frames share.
What a stair does for registration is decided in :mod:`planner.coverage.stair_links`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.core.errors import InputError
from planner.site.geometry import check_simple_polygon


@dataclass(frozen=True, kw_only=True)
class Stair:
    """A stair (``name``: the model's element name) from ``lower_zone`` up to ``upper_zone`` (two different zones);
    ``footprint``: its plan outline (m, a simple polygon) in the plan coordinates both zones' frames share; ``z_min_m``,
    ``z_max_m``: its bottom and top in the site's vertical datum (information only)."""

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
