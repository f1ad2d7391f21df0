"""Coverage regions of floor and ceiling patches (planner.candidates.surface_regions) against the sight test itself,
and the candidates of their arrangement.

- Regions: on a plain room, an L room with a column and a ceiling, and a U room with a low block and a tall triangular
  one (floors and ceilings), at random positions and at positions within 2 mm of every region's boundary: no position
  of an inner region fails the sight test (:func:`planner.plan.surfaces.patch_matrix`, with the walls' exclusions),
  and every position that passes it lies in the outer region.
- Dominance: one face per distinct set of regions, none whose set another holds.
- The 4.3 x 3.3 m room (IH 1.5 m, the P30's 35 deg cone, theta_max 68 deg): the candidates of the arrangement cover
  walls and floor with 2 stations, where the floor grid's pool needs 3.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import shapely

from planner.candidates.surface_regions import arrangement_candidates, patch_regions, undominated
from planner.coverage.matrix import build_coverage, station_places
from planner.io.load import load_site
from planner.plan import PlanOptions
from planner.plan.problem import resolve
from planner.plan.surfaces import floor_candidates, surface_cover
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide
from tests.bounds.plane_cases import min_cover


def _site(tmp_path: Path, name: str, xy: list, holes: list | None = None, ceiling: float | None = None) -> Path:
    zone = {"id": "R", "scan_side": "inside", "coordinates": xy, "height_m": 3.0, "holes": holes or []}
    if ceiling is not None:
        zone["ceiling_height_m"] = ceiling
    path = tmp_path / f"{name}.json"
    doc = {"name": name, "instrument": "leica-p30", "parameters": {"instrument_height_m": 1.5}, "zones": [zone]}
    path.write_text(json.dumps(doc))
    return path


ROOMS = {
    "plain": ([[0, 0], [4.3, 0], [4.3, 3.3], [0, 3.3]], [], None),
    "L_column_ceiling": (
        [[0, 0], [6, 0], [6, 3], [3, 3], [3, 5.5], [0, 5.5]],
        [{"coordinates": [[1, 1], [1.6, 1], [1.6, 1.6], [1, 1.6]], "height_m": 3.0}],
        2.8,
    ),
    "U_blocks": (
        [[0, 0], [7, 0], [7, 5], [5, 5], [5, 2], [2, 2], [2, 5.3], [0, 5.3]],
        [
            {"coordinates": [[3, 0.6], [3.3, 0.6], [3.3, 0.9], [3, 0.9]], "height_m": 1.2},
            {"coordinates": [[5.6, 3], [6.2, 3.1], [6.0, 3.6]], "height_m": 3.0},
        ],
        2.6,
    ),
}


def _near_boundaries(regions: list[shapely.Geometry], rng: np.random.Generator, per: int) -> np.ndarray:
    """Points on each region's boundary moved by up to 2 mm either way."""
    out = []
    for g in regions:
        if g.is_empty:
            continue
        line = g.boundary
        at = shapely.line_interpolate_point(line, rng.random(per), normalized=True)
        out.append(shapely.get_coordinates(at) + rng.uniform(-2e-3, 2e-3, (per, 2)))
    return np.vstack(out)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(ROOMS))
def test_regions_agree_with_the_sight_test(tmp_path, name):
    xy, holes, ceiling = ROOMS[name]
    site = load_site(_site(tmp_path, name, xy, holes, ceiling))
    kinds = ("walls", "floors", "ceilings") if ceiling else ("walls", "floors")
    problem = resolve(site, PlanOptions(surfaces=kinds))
    setup = problem.surfaces
    assert setup is not None
    p = setup.patches
    every = np.arange(len(p))
    inner = patch_regions(site, p, setup.limits, problem.limits, every, {})
    outer = patch_regions(site, p, setup.limits, problem.limits, every, {}, outer=True)
    rng = np.random.default_rng(7)
    box = shapely.Polygon(xy).bounds
    pts = np.vstack(
        [
            np.column_stack(
                [rng.uniform(box[0] - 0.3, box[2] + 0.3, 1500), rng.uniform(box[1] - 0.3, box[3] + 0.3, 1500)]
            ),
            _near_boundaries([*inner.values(), *outer.values()], rng, 12),
        ]
    )
    cands = [
        Candidate(f"Q{k}", "R", ScanSide.INSIDE, "site", float(a), float(b), CandidateKind.GRID)
        for k, (a, b) in enumerate(pts)
    ]
    places = station_places(site, pts, ["site"] * len(pts))
    excluded = [k for k, why in enumerate(places.reason) if why]
    seen = surface_cover(site, setup, cands, excluded)
    full = np.zeros((len(pts), len(p)), dtype=bool)
    full[:, seen.seen] = seen.matrix.toarray()
    points = shapely.points(pts)
    assert seen.matrix.nnz > 1000
    for t in every:
        sees = full[:, t]
        in_inner = shapely.covers(inner[int(t)], points)
        assert not np.any(in_inner & ~sees), (name, p.label(int(t)), pts[in_inner & ~sees][:3])
        out = ~shapely.covers(outer[int(t)], points) & sees
        if out.any():  # only within float noise of the outer region
            assert shapely.distance(outer[int(t)], points[out]).max() < 1e-7, (name, p.label(int(t)))


def test_one_face_per_undominated_set():
    member = np.array(
        [
            [1, 1, 0, 0],  # held by row 2
            [1, 1, 1, 0],
            [1, 1, 1, 0],  # the same set as row 1
            [0, 0, 0, 1],
            [0, 0, 0, 0],  # in no region
            [0, 1, 1, 0],  # held by row 1
        ],
        dtype=bool,
    )
    assert undominated(member).tolist() == [1, 3]
    assert undominated(np.zeros((3, 2), dtype=bool)).tolist() == []


def test_the_arrangement_gives_the_4_3_x_3_3_room_two_stations(tmp_path):
    xy, holes, _ = ROOMS["plain"]
    site = load_site(_site(tmp_path, "plain", xy, holes))
    problem = resolve(site, PlanOptions(surfaces=("walls", "floors")))
    setup = problem.surfaces
    assert setup is not None
    found, notes = arrangement_candidates(site, setup.patches, setup.limits, problem.targets, problem.limits, {}, {})
    assert notes == [] and 10 <= len(found) <= 200
    assert all(c.kind is CandidateKind.REGION and c.side is ScanSide.INSIDE for c in found)

    def fewest(cands: list[Candidate]) -> float:
        walls = build_coverage(site, cands, problem.targets, problem.limits)
        cover = surface_cover(site, setup, cands, walls.excluded)
        assert cover.unseen.size == 0
        return min_cover(sp.hstack([walls.by_candidate, cover.matrix], format="csr"))

    assert fewest(found) == 2
    grid = floor_candidates(site, setup, site.parameters.min_standoff_m)
    assert fewest(grid) == 3  # the floor grid alone (1.33 m) needs one more
