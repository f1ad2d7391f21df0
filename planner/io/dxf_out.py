"""DXF export (ezdxf, metres): layers WALLS, HOLES, OBSTACLES, NOGO, STATIONS, FIELDS, COVERAGE, NETWORK, CONTROL.

Zones are closed LWPOLYLINEs on WALLS with their height as thickness and, in XDATA of the application ``TLS_PLANNER``,
the zone id, scan side, frame and per-vertex heights, so that :func:`planner.io.dxf_in.read_dxf_site` reads the same
site back (the round trip).
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

import ezdxf
from ezdxf import units

from planner.core.checks import argument
from planner.io.dxf_entities import APPID
from planner.io.params_io import dxf_properties, site_record
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering

#: the layers and their ACI colours
LAYERS = dict(WALLS=7, HOLES=7, OBSTACLES=8, NOGO=6, STATIONS=5, NUMBERS=5, FIELDS=4, COVERAGE=3, NETWORK=2, CONTROL=1)
#: coverage colours (ACI): seen by no station, by one, by two or more
COVERAGE_ACI = {0: 1, 1: 3, 2: 5}


def _xdata(*tags: str, heights: Sequence[float] = ()) -> list[tuple[int, object]]:
    """XDATA tags: 1000 strings key=value, then one 1040 real per vertex height."""
    return [(1000, t) for t in tags] + [(1040, float(h)) for h in heights]


#: ezdxf's metadata option is one flag for the whole process: one drawing at a time switches it
_FIXED_METADATA = threading.Lock()


@contextmanager
def _fixed_metadata() -> Iterator[None]:
    """ezdxf's fixed metadata while a drawing is made and saved (dates 2000-01-01, constant GUIDs, a marker without time
    stamp), so that the same plan gives the same bytes; the option is restored afterwards. Held under a lock: two
    threads writing at once would otherwise restore each other's setting."""
    with _FIXED_METADATA:
        before = ezdxf.options.write_fixed_meta_data_for_testing
        ezdxf.options.write_fixed_meta_data_for_testing = True
        try:
            yield
        finally:
            ezdxf.options.write_fixed_meta_data_for_testing = before


def _label_height(o: Outcome) -> float:
    """Text height: 1 % of the site's extent, at least 0.1 m."""
    xs = [v[0] for z in o.site.zones for v in z.vertices]
    ys = [v[1] for z in o.site.zones for v in z.vertices]
    return max(0.1, 0.01 * max(max(xs) - min(xs), max(ys) - min(ys)))


def write_dxf(o: Outcome, path: Path | str) -> Path:
    """Write the outcome as a DXF R2010 drawing in metres; return the path. The same outcome gives the same bytes (fixed
    metadata; the CLASSES section, which ezdxf fills in an order that changes with Python's string hash seed, in name
    order)."""
    argument(o, Outcome, "outcome")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    with _fixed_metadata():
        doc = _drawing(o)
        doc.classes.add_required_classes(doc.dxfversion)
        doc.classes.classes = OrderedDict(sorted(doc.classes.classes.items()))
        doc.saveas(out)
    return out


def _drawing(o: Outcome) -> ezdxf.document.Drawing:
    """The outcome's drawing: layers, zones with XDATA, obstacles, no-go areas, coverage, stations, network."""
    doc = ezdxf.new("R2010", setup=True)
    doc.units = units.M
    doc.header["$MEASUREMENT"] = 1  # metric
    # the instrument and parameters, so that the drawing read back as a site plans the same
    for tag, value in dxf_properties(site_record(o.site.name, o.site.instrument, o.site.parameters)):
        doc.header.custom_vars.append(tag, value)
    doc.appids.add(APPID)
    for name, colour in LAYERS.items():
        doc.layers.add(name, color=colour)
    msp = doc.modelspace()
    th = _label_height(o)
    for z in o.site.zones:
        e = msp.add_lwpolyline(
            z.vertices, close=True, dxfattribs={"layer": "WALLS", "thickness": max(z.vertex_heights_m)}
        )
        e.set_xdata(
            APPID, _xdata(f"zone={z.id}", f"side={z.scan_side.value}", f"frame={z.frame}", heights=z.vertex_heights_m)
        )
        for ring, hs in zip(z.holes, z.hole_heights_m):
            e = msp.add_lwpolyline(ring, close=True, dxfattribs={"layer": "HOLES", "thickness": max(hs)})
            e.set_xdata(APPID, _xdata(f"zone={z.id}", heights=hs))
    for ob in o.site.obstacles:
        e = msp.add_lwpolyline(ob.vertices, close=True, dxfattribs={"layer": "OBSTACLES", "thickness": ob.height_m})
        e.set_xdata(APPID, _xdata(f"name={ob.name}"))
    for a in o.site.no_go_areas:
        e = msp.add_lwpolyline(a.vertices, close=True, dxfattribs={"layer": "NOGO"})
        e.set_xdata(APPID, _xdata(f"name={a.name}"))
    t = o.coverage.targets
    for k in range(len(t)):
        n = min(int(o.coverage.count[k]), 2)
        msp.add_line(tuple(t.a[k]), tuple(t.b[k]), dxfattribs={"layer": "COVERAGE", "color": COVERAGE_ACI[n]})
    numbering = StationNumbering.recorded(o.meta, o.stations)
    for s in numbering.ordered(o.stations):  # by number; the label above right, the number below right
        n, label = numbering.number(s.id), numbering.label(s.id)
        tags = _xdata(f"number={n}", f"label={label}", f"numbering={numbering.basis}")
        msp.add_point((s.x, s.y), dxfattribs={"layer": "STATIONS"}).set_xdata(APPID, tags)
        msp.add_circle((s.x, s.y), th / 2, dxfattribs={"layer": "STATIONS"})
        msp.add_text(label, height=th, dxfattribs={"layer": "STATIONS"}).set_placement((s.x + th, s.y + th))
        msp.add_text(str(n), height=th, dxfattribs={"layer": "NUMBERS"}).set_placement((s.x + th, s.y - 2 * th))
        r = o.tripod_radius_m.get(s.id)
        if r is not None and math.isfinite(r) and r > 0:
            msp.add_circle((s.x, s.y), r, dxfattribs={"layer": "FIELDS"})
    if o.network is not None:
        g = o.network.graph
        for u, v in g.edges():
            ends = [(g.nodes[n]["x"], g.nodes[n]["y"]) for n in (u, v)]
            msp.add_line(*ends, dxfattribs={"layer": "NETWORK"})
        for c in o.network.control:
            msp.add_point((c.x, c.y), dxfattribs={"layer": "CONTROL"})
            msp.add_text(c.name, height=th, dxfattribs={"layer": "CONTROL"}).set_placement((c.x + th, c.y - 2 * th))
    return doc
