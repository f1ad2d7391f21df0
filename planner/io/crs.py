"""Optional coordinate reference systems (pyproj, always x/y = easting/northing = lon/lat order).

Planning runs in metres on a projected plane. A GeoJSON file in longitude/latitude (RFC 7946) is read by projecting it
to a metric CRS the user names (e.g. ``EPSG:32636``, UTM 36N), and exports go back to lon/lat the same way. pyproj is
needed only when a CRS is given.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from planner.core.errors import UsageError

WGS84 = "EPSG:4326"

Transform = Callable[[NDArray[np.float64]], NDArray[np.float64]]


def _transformer(src: str, dst: str) -> Transform:
    try:
        from pyproj import CRS, Transformer
        from pyproj.exceptions import CRSError
    except ImportError:  # pragma: no cover - depends on the installation
        raise UsageError("a CRS needs pyproj (pip install pyproj)", field="crs", value=dst) from None
    metric = dst if dst != WGS84 else src
    try:
        target = CRS.from_user_input(metric)
    except CRSError:
        raise UsageError("unknown coordinate reference system", field="crs", value=metric) from None
    if not target.is_projected:
        raise UsageError("planning needs a projected (metric) CRS", field="crs", value=target.to_string())
    t = Transformer.from_crs(src, dst, always_xy=True)

    def run(xy: NDArray[np.float64]) -> NDArray[np.float64]:
        a = np.asarray(xy, dtype=float).reshape(-1, 2)
        x, y = t.transform(a[:, 0], a[:, 1])
        return np.column_stack([x, y])

    return run


def to_projected(crs: str) -> Transform:
    """lon/lat (WGS84) -> the metric CRS ``crs``."""
    return _transformer(WGS84, crs)


def to_lonlat(crs: str) -> Transform:
    """The metric CRS ``crs`` -> lon/lat (WGS84)."""
    return _transformer(crs, WGS84)
