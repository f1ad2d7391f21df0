"""DXF import: layers, heights (XDATA / thickness / layer default), units, arcs, blocks (mirrored too),
and one-line errors for open, zero-area, self-intersecting polylines and files without closed ones,
arcs too large to flatten, two-vertex outlines, entities not read, bad XDATA and bad options."""

from __future__ import annotations

import math
import resource
import subprocess
import sys

import ezdxf
import numpy as np
import pytest
from ezdxf import units

import planner
from planner.cli import main
from planner.io.dxf_in import APPID, DxfOptions, read_dxf_site
from planner.site.model import ScanSide
from tests.cli.test_cli import assert_one_line_error
from tests.conftest import ROOT

SQUARE = [(0, 0), (10, 0), (10, 10), (0, 10)]


def drawing(unit: int = units.M):
    doc = ezdxf.new("R2010")
    doc.units = unit
    return doc, doc.modelspace()


def save(doc, tmp_path, name="site.dxf"):
    path = tmp_path / name
    doc.saveas(path)
    return path


def assert_refused(doc, tmp_path, capsys, *fragments: str) -> None:
    """``planner validate`` of the drawing exits 3 with one line holding ``fragments``."""
    assert main(["validate", str(save(doc, tmp_path))]) == 3
    assert_one_line_error(capsys.readouterr().err, *fragments)


def test_square_with_thickness_and_label(tmp_path):
    doc, msp = drawing()
    msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "ZONES", "thickness": 6.5})
    msp.add_text("Hall", dxfattribs={"layer": "ZONES"}).set_placement((4, 5))
    site = read_dxf_site(save(doc, tmp_path))
    z = site.zones[0]
    assert z.id == "Hall" and z.scan_side is ScanSide.INSIDE
    assert z.vertex_heights_m == (6.5,) * 4
    assert z.area_m2 == pytest.approx(100.0)  # 10 m x 10 m


def test_clockwise_polyline_in_millimetres_is_read_in_metres_counter_clockwise(tmp_path):
    doc, msp = drawing(units.MM)
    msp.add_lwpolyline(
        [(x * 1000, y * 1000) for x, y in reversed(SQUARE)],
        close=True,
        dxfattribs={"layer": "ZONES-OUTSIDE", "thickness": 4000},
    )
    z = read_dxf_site(save(doc, tmp_path)).zones[0]
    assert z.scan_side is ScanSide.OUTSIDE
    assert z.area_m2 == pytest.approx(100.0)  # 10,000 mm = 10 m sides, CCW after reading
    assert z.vertex_heights_m == (4.0,) * 4  # thickness 4,000 mm


def test_layer_default_height_and_missing_height(tmp_path):
    doc, msp = drawing()
    msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "zones"})
    path = save(doc, tmp_path)
    assert read_dxf_site(path, DxfOptions(layer_heights_m={"ZONES": 3.0})).zones[0].vertex_heights_m == (3.0,) * 4
    with pytest.raises(planner.InputError, match="no wall height"):
        read_dxf_site(path)


def test_bulge_arc_is_flattened(tmp_path):
    # a 10 x 10 square whose top side bulges out into a half circle of radius 5:
    # area = 100 + pi 5^2 / 2 = 139.27 m2
    doc, msp = drawing()
    msp.add_lwpolyline(
        [(0, 0, 0), (10, 0, 0), (10, 10, 1.0), (0, 10, 0)],
        format="xyb",
        close=True,
        dxfattribs={"layer": "ZONES", "thickness": 5},
    )
    z = read_dxf_site(save(doc, tmp_path), DxfOptions(flatten_m=0.001)).zones[0]
    assert len(z.vertices) > 20
    assert z.area_m2 == pytest.approx(100 + math.pi * 25 / 2, rel=1e-3)


def test_blocks_are_expanded_mirrored_ones_too(tmp_path):
    # an L-shaped room as a block; one plain insert at (0, 0), one mirrored (x scale -1) at (100, 0)
    doc, msp = drawing()
    blk = doc.blocks.new("ROOM")
    blk.add_lwpolyline(
        [(0, 0), (20, 0), (20, 10), (10, 10), (10, 20), (0, 20)], close=True, dxfattribs={"layer": "0", "thickness": 7}
    )
    msp.add_blockref("ROOM", (0, 0), dxfattribs={"layer": "ZONES"})
    msp.add_blockref("ROOM", (100, 0), dxfattribs={"layer": "ZONES", "xscale": -1})
    site = read_dxf_site(save(doc, tmp_path))
    a, b = site.zones
    assert a.area_m2 == pytest.approx(300.0) and b.area_m2 == pytest.approx(300.0)  # 20x20 - 10x10
    assert b.xy[:, 0].min() == pytest.approx(80.0) and b.xy[:, 0].max() == pytest.approx(100.0)  # mirrored to the left
    # vertex for vertex the mirror image x -> 100 - x of the plain insert
    assert sorted((round(100 - x, 9), round(y, 9)) for x, y in a.vertices) == sorted(
        (round(x, 9), round(y, 9)) for x, y in b.vertices
    )
    assert b.vertex_heights_m == (7.0,) * 6


def test_obstacles_and_no_go_layers(tmp_path):
    doc, msp = drawing()
    msp.add_lwpolyline([(0, 0), (40, 0), (40, 30), (0, 30)], close=True, dxfattribs={"layer": "ZONES", "thickness": 8})
    msp.add_circle((20, 15), 1.0, dxfattribs={"layer": "OBSTACLES", "thickness": 8})
    msp.add_lwpolyline([(2, 2), (6, 2), (6, 6), (2, 6)], close=True, dxfattribs={"layer": "NOGO"})
    site = read_dxf_site(save(doc, tmp_path))
    assert len(site.obstacles) == 1 and len(site.no_go_areas) == 1
    col = np.asarray(site.obstacles[0].vertices)
    assert np.hypot(col[:, 0] - 20, col[:, 1] - 15) == pytest.approx(1.0, abs=0.011)  # flattened to 0.01 m


@pytest.mark.parametrize(
    "points, fragment",
    [
        ([(0, 0), (10, 0), (10, 10), (0, 10)], "open polyline"),  # not closed
        ([(0, 0), (10, 0), (20, 0)], "polygon has zero area"),  # closed but flat: side 3 folds back
        ([(0, 0), (10, 10), (10, 0), (0, 10)], "self-intersecting"),  # a bow tie
    ],
)
def test_bad_polylines_give_one_line_errors(tmp_path, capsys, points, fragment):
    doc, msp = drawing()
    msp.add_lwpolyline(points, close=fragment != "open polyline", dxfattribs={"layer": "ZONES", "thickness": 3})
    assert_refused(doc, tmp_path, capsys, "site.dxf", "layer ZONES handle", fragment.split(":")[0])


def test_no_closed_polylines_and_malformed_dxf(tmp_path, capsys):
    doc, msp = drawing()
    msp.add_text("just a title", dxfattribs={"layer": "ZONES"})
    msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "FURNITURE", "thickness": 1})
    assert_refused(doc, tmp_path, capsys, "no closed polyline on a zone layer")
    bad = tmp_path / "broken.dxf"
    bad.write_text("  0\nSECTION\n  2\nENTITIES\n  0\nLWPOLYLINE\n 10\nnot-a-number\n")
    assert main(["validate", str(bad)]) == 3
    assert_one_line_error(capsys.readouterr()[1], "broken.dxf", "not a readable DXF file")


def test_line_entities_on_a_zone_layer_are_refused(tmp_path):
    doc, msp = drawing()
    for a, b in zip(SQUARE, SQUARE[1:] + SQUARE[:1]):
        msp.add_line(a, b, dxfattribs={"layer": "ZONES"})
    with pytest.raises(planner.InputError, match="LINE is open geometry"):
        read_dxf_site(save(doc, tmp_path))


@pytest.mark.slow
def test_holes_layer_and_round_trip_of_a_court_with_a_block(tmp_path):
    # a 40 x 30 court (walls 6 m) with a 10 x 10 block (8 m) drawn on HOLES: 4 + 4 walls, area 1200 - 100
    doc, msp = drawing()
    msp.add_lwpolyline([(0, 0), (40, 0), (40, 30), (0, 30)], close=True, dxfattribs={"layer": "ZONES", "thickness": 6})
    msp.add_lwpolyline(
        [(15, 10), (25, 10), (25, 20), (15, 20)], close=True, dxfattribs={"layer": "HOLES", "thickness": 8}
    )
    site = read_dxf_site(save(doc, tmp_path), parameters=planner.Parameters(max_slant_range_m=60.0))
    z = site.zones[0]
    assert len(z.walls) == 8 and z.area_m2 == pytest.approx(1100.0)
    assert z.hole_heights_m == ((8.0,) * 4,)
    plan = planner.plan_site(site, planner.PlanOptions(method="milp"))
    assert plan.verification.complete
    back = read_dxf_site(
        planner.write_dxf(planner.outcome_from_plan(plan), tmp_path / "out.dxf"), parameters=site.parameters
    )
    assert back.zones[0].holes == z.holes and back.zones[0].hole_heights_m == z.hole_heights_m
    assert len(planner.plan_site(back, planner.PlanOptions(method="milp")).stations) == len(plan.stations)


def test_a_polyline_copied_onto_itself_is_refused(tmp_path, capsys):
    # a CAD copy in place: two identical closed polylines would be two zones with the same 4 walls
    doc, msp = drawing()
    for _ in range(2):
        msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "ZONES", "thickness": 5})
    path = save(doc, tmp_path)
    assert main(["validate", str(path)]) == 3
    assert_one_line_error(capsys.readouterr().err, "site.dxf", "the same outline as zone")


def _validate_in_a_child(path, limit_s: float = 60.0) -> subprocess.CompletedProcess:
    """``planner validate path`` in a child process with 2 GiB of address space and a time limit: the
    old reader flattened a huge arc without end (and without bound on memory)."""

    def cap() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))

    return subprocess.run(
        [sys.executable, "-m", "planner", "validate", str(path)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=limit_s,
        preexec_fn=cap,
    )


@pytest.mark.parametrize(
    "kind, fragments",
    [
        ("bulge", ("layer WALLS handle", "vertex 1", "bulge = 1e+12", "radius 2.5e+12 m", "beyond +-1e+08 m")),
        ("circle", ("layer WALLS handle", "radius = 1e+12", "beyond +-1e+08 m")),
    ],
)
def test_an_arc_too_large_to_flatten_is_refused_at_once(tmp_path, kind, fragments):
    # a bulge of 1e12 on a 10 m chord is an arc of radius 2.5e12 m; flattened to 0.01 m before the
    # 1e8 m coordinate check, it hung and filled the memory: now refused from its size, before flattening
    doc, msp = drawing()
    if kind == "bulge":
        msp.add_lwpolyline(
            [(0, 0, 0, 0, 1e12), (10, 0, 0, 0, 0), (10, 10, 0, 0, 0)],
            format="xyseb",
            dxfattribs={"layer": "WALLS", "thickness": 3},
        ).closed = True
    else:
        msp.add_circle((0, 0), 1e12, dxfattribs={"layer": "WALLS", "thickness": 3})
    run = _validate_in_a_child(save(doc, tmp_path))
    assert run.returncode == 3, run.stderr
    assert_one_line_error(run.stderr, "site.dxf", *fragments)


def test_flattening_to_too_many_vertices_is_refused(tmp_path):
    # a 10 km circle flattened to 1 um would give about 220,000 vertices (limit 100,000): refused,
    # naming the radius; the same circle at the default 0.01 m reads
    doc, msp = drawing()
    msp.add_circle((0, 0), 1e4, dxfattribs={"layer": "WALLS", "thickness": 3})
    path = save(doc, tmp_path)
    with pytest.raises(
        planner.InputError,
        match=r"handle .*: radius = 10000: flattening its arcs to 1e-06 m would "
        r"give about 2\d\d,\d\d\d vertices \(limit 100,000",
    ):
        read_dxf_site(path, DxfOptions(flatten_m=1e-6))
    assert read_dxf_site(path).zones[0].area_m2 == pytest.approx(math.pi * 1e8, rel=1e-3)


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        (dict(flatten_m=-1), "flatten_m = -1: must be a finite number > 0"),  # hung (flattening never ended)
        (dict(flatten_m=0), "flatten_m = 0: must be a finite number > 0"),  # a raw ValueError from ezdxf
        (dict(flatten_m=math.nan), "flatten_m = nan: must be a finite number > 0"),
        (dict(layer_heights_m={"WALLS": 3.0, "walls": 5.0}), "layer_heights_m = 'walls': layer given twice"),
        (dict(layer_heights_m={"WALLS": -3.0}), "layer_heights_m['WALLS'] = -3: must be a finite number > 0"),
        (dict(default_side="outsde"), "default_side = 'outsde': must be one of inside, outside, both"),
    ],
)
def test_dxf_options_are_checked_when_made(kwargs, fragment):
    # a bad option is a usage error naming the field, before any file is read
    with pytest.raises(planner.UsageError) as info:
        DxfOptions(**kwargs)
    assert fragment in str(info.value)
    assert DxfOptions(default_side="outside").default_side is ScanSide.OUTSIDE  # text is read as the enum


@pytest.mark.parametrize("layer, label", [("HOLES", False), ("WALLS", True)])
def test_a_two_vertex_closed_polyline_is_a_one_line_error(tmp_path, capsys, layer, label):
    # a closed polyline of two vertices on HOLES (beside a valid room), or on WALLS with a label TEXT,
    # crashed in shapely ("A linearring requires at least 4 coordinates", exit 1): now the error the
    # plain case gives, naming the layer and the handle
    doc, msp = drawing()
    if layer == "HOLES":
        msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "WALLS", "thickness": 3})
    msp.add_lwpolyline([(2, 2), (4, 2)], close=True, dxfattribs={"layer": layer, "thickness": 3})
    if label:
        msp.add_text("Z1", dxfattribs={"layer": "WALLS"}).set_placement((3, 2))
    fragments = ("site.dxf", f"layer {layer} handle", "polygon = 2", "a polygon needs at least 3 vertices")
    assert_refused(doc, tmp_path, capsys, *fragments)


@pytest.mark.parametrize("kind", ["SOLID", "HATCH", "POINT", "3DFACE"])
def test_filled_areas_and_points_on_a_zone_layer_are_refused(tmp_path, capsys, kind):
    # these were dropped silently (the room read without them); refused like LINE, saying what to draw
    doc, msp = drawing()
    msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "WALLS", "thickness": 3})
    attribs = {"layer": "WALLS"}
    if kind == "SOLID":
        msp.add_solid([(1, 1), (2, 1), (1, 2), (2, 2)], dxfattribs=attribs)
    elif kind == "HATCH":
        msp.add_hatch(dxfattribs=attribs).paths.add_polyline_path([(1, 1), (2, 1), (2, 2)], is_closed=True)
    elif kind == "POINT":
        msp.add_point((1, 1), dxfattribs=attribs)
    else:
        msp.add_3dface([(1, 1, 0), (2, 1, 0), (2, 2, 0)], dxfattribs=attribs)
    fragments = (
        "site.dxf",
        "layer WALLS handle",
        f"{kind} ",
        "draw zones, obstacles and no-go areas as closed polylines",
    )
    assert_refused(doc, tmp_path, capsys, *fragments)


def test_an_unknown_xdata_scan_side_is_refused(tmp_path, capsys):
    # XDATA side=outsde fell back to inside silently: now refused, naming the value
    doc, msp = drawing()
    doc.appids.new(APPID)
    msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "ZONES", "thickness": 3}).set_xdata(
        APPID, [(1000, "side=outsde")]
    )
    assert_refused(doc, tmp_path, capsys, "site.dxf", "layer ZONES handle", "side = 'outsde'", "unknown scan side")


def test_a_layer_height_given_twice_is_a_usage_error(tmp_path, capsys):
    # --layer-height WALLS=3 --layer-height WALLS=5: the last won silently; now exit 2 naming the layer
    doc, msp = drawing()
    msp.add_lwpolyline(SQUARE, close=True, dxfattribs={"layer": "WALLS"})
    path = str(save(doc, tmp_path))
    for second in ("WALLS=5", "walls=3"):  # layer names are case-insensitive
        assert main(["validate", path, "--layer-height", "WALLS=3", "--layer-height", second]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--layer-height" in err and "'WALLS' given twice" in err, err
    assert main(["validate", path, "--layer-height", "WALLS=3", "--layer-height", "HOLES=5"]) == 0
