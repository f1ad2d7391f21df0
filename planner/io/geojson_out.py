"""GeoJSON export of an outcome: zones (importable again), walls' coverage, stations, tripod discs, network links and
control points, one FeatureCollection, each feature with a ``role``."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from shapely.geometry import mapping

from planner.core.checks import argument
from planner.core.errors import UsageError
from planner.core.text import dumps
from planner.io.crs import to_lonlat
from planner.io.params_io import RECORD_KEY, site_record
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering
from planner.site.model import SITE_FRAME


def _num(v: float) -> float | None:
    return None if v is None or not math.isfinite(v) else round(float(v), 6)


def _feature(geom: shapely.Geometry, role: str, **props: Any) -> dict[str, Any]:
    """A feature of ``role``; ``props`` follow the role in its properties."""
    return {"type": "Feature", "geometry": mapping(geom), "properties": {"role": role, **props}}


def _site_features(o: Outcome) -> list[dict[str, Any]]:
    out = [
        _feature(
            z.polygon,
            "zone",
            id=z.id,
            scan_side=z.scan_side.value,
            frame=z.frame,
            vertex_heights_m=list(z.vertex_heights_m),
        )
        for z in o.site.zones
    ]
    out += [
        _feature(shapely.Polygon(ob.vertices), "obstacle", name=ob.name, height_m=ob.height_m)
        for ob in o.site.obstacles
    ]
    out += [_feature(shapely.Polygon(a.vertices), "no_go", name=a.name) for a in o.site.no_go_areas]
    return out


def _coverage_features(o: Outcome) -> list[dict[str, Any]]:
    t = o.coverage.targets
    return [
        _feature(
            shapely.LineString([t.a[k], t.b[k]]),
            "coverage",
            zone=t.zone_ids[t.zone[k]],
            side=("inside", "outside")[t.side[k]],
            wall=int(t.wall[k]),
            from_m=_num(t.s0_m[k]),
            to_m=_num(t.s1_m[k]),
            frame=t.frames[t.frame[k]],
            stations=int(o.coverage.count[k]),
            best_incidence_deg=_num(o.coverage.best_incidence_deg[k]),
        )
        for k in range(len(t))
    ]


def _station_features(o: Outcome) -> list[dict[str, Any]]:
    """One point per station, by number (its ``number`` and ``label`` as every file and figure of the plan give
    them), and its tripod disc."""
    out = []
    numbering = StationNumbering.recorded(o.meta, o.stations)
    per = dict(zip((s.id for s in o.stations), o.coverage.per_station))
    for s in numbering.ordered(o.stations):
        st, r = per[s.id], o.tripod_radius_m.get(s.id)
        out.append(
            _feature(
                shapely.Point(s.x, s.y),
                "station",
                id=s.id,
                number=numbering.number(s.id),
                label=numbering.label(s.id),
                zone=s.zone,
                side=s.side.value,
                kind=s.kind.value,
                frame=s.frame,
                covered_m=_num(st.covered_m),
                worst_incidence_deg=_num(st.worst_incidence_deg),
                longest_range_m=_num(st.longest_range_m),
                worst_point_error_m=_num(st.worst_point_error_m),
                tripod_radius_m=_num(r) if r is not None else None,
            )
        )
        if r is not None and r > 0:
            disc = shapely.Point(s.x, s.y).buffer(r, quad_segs=16)
            out.append(_feature(disc, "tripod_disc", station=s.id, radius_m=_num(r), frame=s.frame))
    return out


def _network_features(o: Outcome) -> list[dict[str, Any]]:
    if o.network is None:
        return []
    g = o.network.graph
    out = [
        _feature(
            shapely.LineString([(g.nodes[u]["x"], g.nodes[u]["y"]), (g.nodes[v]["x"], g.nodes[v]["y"])]),
            "network",
            **{"from": u, "to": v},
            kinds=sorted(d["kinds"]),
            length_m=_num(d["length_m"]),
            frame=g.nodes[u]["frame"],
        )
        for u, v, d in g.edges(data=True)
    ]
    out += [
        _feature(
            shapely.Point(c.x, c.y),
            "control",
            name=c.name,
            proposed=c.proposed,
            frame=c.frame,
            sigma_m=_num(o.network.station_sigma_m.get(c.name, 0.0)),
        )
        for c in o.network.control
    ]
    return out


def outcome_geojson(o: Outcome, crs: str | None = None) -> dict[str, Any]:
    """The outcome as a GeoJSON FeatureCollection (site-frame metres, or lon/lat when ``crs`` is given)."""
    feats = _site_features(o) + _coverage_features(o) + _station_features(o) + _network_features(o)
    if crs is not None:
        frames = {f["properties"].get("frame", SITE_FRAME) for f in feats} - {SITE_FRAME}
        if frames:
            raise UsageError(
                "only site-frame coordinates can be given a CRS; these zones have local frames",
                field="crs",
                value=", ".join(sorted(frames)),
            )
        fwd = to_lonlat(crs)
        for f in feats:
            geom = shapely.geometry.shape(f["geometry"])
            f["geometry"] = mapping(shapely.transform(geom, lambda a: fwd(np.asarray(a))))
    return {
        "type": "FeatureCollection",
        "name": o.site.name,
        "planner": {
            "units": "degrees (WGS84 lon/lat)" if crs else "metres",
            "crs": crs,
            "method": o.meta.get("method"),
            "stations": len(o.stations),
            "numbering": StationNumbering.recorded(o.meta, o.stations).legend,
            # what the geometry does not say, so that the file read back as a site plans the same
            RECORD_KEY: site_record(o.site.name, o.site.instrument, o.site.parameters),
        },
        "features": feats,
    }


def write_geojson(o: Outcome, path: Path | str, crs: str | None = None) -> Path:
    """Write :func:`outcome_geojson` to ``path`` (folders created) and return the path."""
    argument(o, Outcome, "outcome")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(dumps(outcome_geojson(o, crs), indent=None))
    return out
