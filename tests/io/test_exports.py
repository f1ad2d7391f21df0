"""Exports: DXF opens with ezdxf (layers, labels), GeoJSON with shapely, the station CSV; the DXF and
GeoJSON round trips keep the station count; a CRS round trip keeps coordinates."""

from __future__ import annotations

import csv
import json
from dataclasses import replace

import ezdxf
import numpy as np
import pytest
from shapely.geometry import shape

import planner
from planner.io.dxf_out import LAYERS
from tests.conftest import INSTANCES


@pytest.fixture(scope="module")
def polygon_b(polygon_b_default):
    site, plan = polygon_b_default  # the library's defaults: the MILP with tripod discs
    network = planner.run_network(site, list(plan.stations))
    return site, plan, planner.outcome_from_plan(plan, network)


def same_parameters(site, like):
    return replace(site, parameters=like.parameters, instrument=like.instrument)


@pytest.mark.slow
def test_dxf_has_every_layer_and_a_label_per_station(polygon_b, tmp_path):
    site, plan, o = polygon_b
    doc = ezdxf.readfile(planner.write_dxf(o, tmp_path / "plan.dxf"))
    assert {name for name in LAYERS} <= {layer.dxf.name for layer in doc.layers}
    msp = doc.modelspace()
    labels = sorted(t.dxf.text for t in msp.query('TEXT[layer=="STATIONS"]'))
    assert labels == sorted(s.id for s in plan.stations)
    assert len(msp.query('LWPOLYLINE[layer=="WALLS"]')) == len(site.zones)
    # one coverage line per wall piece (B: 385 per side, 770 in all; tests/plan/test_tripod_discs.py)
    assert len(msp.query('LINE[layer=="COVERAGE"]')) == len(o.coverage.targets)
    assert len(msp.query('LINE[layer=="NETWORK"]')) == o.network.graph.number_of_edges()
    assert len(msp.query('POINT[layer=="CONTROL"]')) == len(o.network.control)
    assert doc.units == 6  # metres


@pytest.mark.slow
def test_dxf_round_trip_keeps_station_count(polygon_b, tmp_path):
    site, plan, o = polygon_b
    # the drawing carries the instrument and parameters (header properties): read back as they were, so the
    # count holds without restoring them by hand (polygon B's instrument is the dissertation's tables; the
    # default P30 would give 5 stations)
    back = planner.read_dxf_site(planner.write_dxf(o, tmp_path / "b.dxf"))
    assert (back.name, back.instrument, back.parameters) == (site.name, site.instrument, site.parameters)
    z0, z1 = site.zones[0], back.zones[0]
    assert (z1.id, z1.scan_side, z1.frame) == (z0.id, z0.scan_side, z0.frame)
    np.testing.assert_allclose(z1.xy, z0.xy, atol=1e-9)
    again = planner.plan_site(back, planner.PlanOptions(method="milp"))
    assert len(again.stations) == len(plan.stations)
    assert again.verification.complete


@pytest.mark.slow
def test_dxf_round_trip_of_a_multi_frame_site_keeps_greedy_count(tmp_path):
    site = planner.load_site(INSTANCES / "baalbek.json")
    plan = planner.plan_site(site)  # greedy
    back = planner.read_dxf_site(planner.write_dxf(planner.outcome_from_plan(plan), tmp_path / "b.dxf"))
    assert (back.instrument, back.parameters) == (site.instrument, site.parameters)
    assert [(z.id, z.frame) for z in back.zones] == [(z.id, z.frame) for z in site.zones]
    assert len(planner.plan_site(back).stations) == len(plan.stations)


@pytest.mark.slow
def test_geojson_opens_with_shapely_and_round_trips(polygon_b, tmp_path):
    site, plan, o = polygon_b
    path = planner.write_geojson(o, tmp_path / "plan.geojson")
    data = json.loads(path.read_text())
    roles = [f["properties"]["role"] for f in data["features"]]
    geoms = [shape(f["geometry"]) for f in data["features"]]
    assert all(g.is_valid for g in geoms)
    assert roles.count("station") == len(plan.stations)
    assert roles.count("coverage") == len(o.coverage.targets)
    assert roles.count("network") == o.network.graph.number_of_edges()
    zone = next(g for g, r in zip(geoms, roles) if r == "zone")
    assert zone.area == pytest.approx(site.zones[0].area_m2, rel=1e-12)
    back = planner.read_geojson_site(path)  # instrument and parameters from the file's "planner" member
    assert (back.name, back.instrument, back.parameters) == (site.name, site.instrument, site.parameters)
    assert len(planner.plan_site(back, planner.PlanOptions(method="milp")).stations) == len(plan.stations)


@pytest.mark.slow
@pytest.mark.parametrize(
    "edit, words",
    [
        (lambda r: r["parameters"].update(theta_max=70), "tls_planner_site.parameters: theta_max = 70: unknown key"),
        (lambda r: r["parameters"].update(overlap="0.3"), "parameters.overlap = '0.3': must be a number, not text"),
        (lambda r: r.update(instrument="no-such-scanner"), "no-such-scanner"),
    ],
)
def test_an_edited_site_record_in_an_export_is_refused_naming_the_file(polygon_b, tmp_path, edit, words):
    # the record is checked like an instance's parameters: an edit by hand that breaks it is one line naming
    # the file, never a silently different plan
    from planner.core.errors import InputError
    from planner.io.params_io import RECORD_KEY

    site, plan, o = polygon_b
    path = planner.write_geojson(o, tmp_path / "plan.geojson")
    data = json.loads(path.read_text())
    edit(data["planner"][RECORD_KEY])
    path.write_text(json.dumps(data))
    with pytest.raises(InputError) as err:
        planner.read_geojson_site(path)
    assert str(path) in str(err.value) and words in str(err.value)


@pytest.mark.slow
def test_station_csv_lists_every_station_after_comment_lines(polygon_b, tmp_path):
    site, plan, o = polygon_b
    text = planner.write_stations_csv(o, tmp_path / "stations.csv").read_text().splitlines()
    comments = [line for line in text if line.startswith("#")]
    assert len(comments) >= 2 and "metres" in comments[1]
    rows = list(csv.DictReader(line for line in text if not line.startswith("#")))
    assert [r["ID"] for r in rows] == [s.id for s in plan.stations]
    for r, s in zip(rows, plan.stations):
        assert (float(r["X"]), float(r["Y"])) == pytest.approx((s.x, s.y), abs=0.0005)  # 3 decimals
        assert float(r["Z"]) == site.parameters.instrument_height_m


#: a 40 x 30 m court in UTM zone 37N (EPSG:32637): east 277,000 m, north 3,770,000 m
COURT_UTM = np.array([[277000.0, 3770000.0], [277040.0, 3770000.0], [277040.0, 3770030.0], [277000.0, 3770030.0]])


def test_crs_round_trip_lonlat_to_utm_and_back(tmp_path):
    path = _lonlat_court(tmp_path)
    from planner.io.crs import to_lonlat, to_projected

    utm = COURT_UTM
    lonlat = to_lonlat("EPSG:32637")(utm)
    assert 36.0 < lonlat[0, 0] < 37.0 and 34.0 < lonlat[0, 1] < 34.1  # x = longitude first (always_xy)
    site = planner.read_geojson_site(path, crs="EPSG:32637")
    np.testing.assert_allclose(site.zones[0].xy, utm, atol=1e-6)
    np.testing.assert_allclose(to_projected("EPSG:32637")(lonlat), utm, atol=1e-6)
    plan = planner.plan_site(site)
    out = planner.io.outcome_geojson(planner.outcome_from_plan(plan), crs="EPSG:32637")
    pts = np.array([f["geometry"]["coordinates"] for f in out["features"] if f["properties"]["role"] == "station"])
    back = to_projected("EPSG:32637")(pts)
    np.testing.assert_allclose(back, [s.xy for s in plan.stations], atol=1e-6)


def _lonlat_court(tmp_path):
    """The court (:data:`COURT_UTM`) written as a lon/lat GeoJSON (RFC 7946's coordinates)."""
    pytest.importorskip("pyproj")
    from planner.io.crs import to_lonlat

    ring = [list(p) for p in to_lonlat("EPSG:32637")(COURT_UTM)]
    fc = {
        "type": "FeatureCollection",
        "features": [
            {
                "type": "Feature",
                "geometry": {"type": "Polygon", "coordinates": [ring + ring[:1]]},
                "properties": {"id": "court", "height_m": 8.0},
            }
        ],
    }
    path = tmp_path / "court.geojson"
    path.write_text(json.dumps(fc))
    return path


def test_a_lonlat_geojson_without_crs_is_refused_not_read_as_a_millimetre_room(tmp_path):
    # the 40 x 30 m court of the test above in lon/lat spans 0.0004 x 0.0003 degrees; read as metres it
    # was a room 0.4 mm across that planned nothing (exit 4, no reason); now one line asking for --crs
    path = _lonlat_court(tmp_path)
    with pytest.raises(planner.InputError, match="look like lon/lat degrees .* give --crs") as err:
        planner.read_geojson_site(path)
    assert str(path) in str(err.value)


def test_crs_must_be_projected():
    pytest.importorskip("pyproj")
    from planner.io.crs import to_projected

    with pytest.raises(planner.UsageError, match="projected"):
        to_projected("EPSG:4326")


def test_cli_plans_a_lonlat_geojson_with_crs_and_exports_lonlat(tmp_path, capsys):
    pytest.importorskip("pyproj")
    from planner.cli import main

    site = _lonlat_court(tmp_path)
    out = tmp_path / "out"
    assert (
        main(
            [
                "plan",
                str(site),
                "--crs",
                "EPSG:32637",
                "--max-range",
                "60",
                "--method",
                "greedy",
                "--out",
                str(out),
                "--export",
                "geojson,csv",
                "--quiet",
            ]
        )
        == 0
    )
    data = json.loads((out / "plan.geojson").read_text())
    assert data["planner"]["crs"] == "EPSG:32637"
    st = [f["geometry"]["coordinates"] for f in data["features"] if f["properties"]["role"] == "station"]
    assert st and all(36.0 < lon < 37.0 and 34.0 < lat < 34.1 for lon, lat in st)  # back in lon/lat
    rows = [r for r in (out / "stations.csv").read_text().splitlines() if r[:1].isalpha() and r != "ID,X,Y,Z"]
    assert all(277000 <= float(r.split(",")[1]) <= 277040 for r in rows)  # the field list stays in UTM metres
    assert "projected CRS EPSG:32637" in (out / "stations.csv").read_text()


@pytest.mark.slow
def test_dxf_is_the_same_bytes_in_two_processes_with_different_hash_seeds(tmp_path):
    # ezdxf stamps creation and save times, random GUIDs and a written-at marker, and orders its CLASSES
    # section by set iteration (PYTHONHASHSEED): the same plan gave a different file each run. Now two
    # processes with hash seeds 0 and 1, a few seconds apart, write the same bytes, and the file still reads.
    import os

    from tests.io.cli import planner_cli

    files = []
    for seed in ("0", "1"):
        out = tmp_path / f"d{seed}"
        args = ("plan", str(INSTANCES / "polygon_b.json"), "--method", "greedy", "--out", str(out), "--export", "dxf")
        run = planner_cli(*args, "--quiet", env={**os.environ, "PYTHONHASHSEED": seed})
        assert run.returncode == 0, run.stderr
        files.append((out / "plan.dxf").read_bytes())
    assert files[0] == files[1]
    lines = files[0].decode().splitlines()
    assert lines[lines.index("$TDCREATE") + 2] == "2451545.0"  # 2000-01-01 00:00 as a Julian date
    doc = ezdxf.readfile(tmp_path / "d0" / "plan.dxf")
    names = [c.dxf.name for c in doc.classes]
    assert names == sorted(names) and len(names) >= 13
    assert ezdxf.options.write_fixed_meta_data_for_testing is False  # the option is restored after a save


@pytest.mark.slow
def test_dxf_written_from_threads_at_once_is_the_same_and_leaves_ezdxf_as_it_was(polygon_b, tmp_path):
    # ezdxf's metadata option is process-wide: 16 writes on 4 threads must each give the one file, and the
    # option must be off afterwards (without the lock one thread restored another's "on" in 2 of 3 runs)
    from concurrent.futures import ThreadPoolExecutor

    from planner.io.dxf_out import write_dxf

    outcome = polygon_b[2]
    with ThreadPoolExecutor(4) as ex:
        paths = list(ex.map(lambda k: write_dxf(outcome, tmp_path / f"{k}.dxf"), range(16)))
    assert len({p.read_bytes() for p in paths}) == 1
    assert ezdxf.options.write_fixed_meta_data_for_testing is False
