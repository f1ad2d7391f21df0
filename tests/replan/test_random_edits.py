"""20 seeded random edit sets over three bundled sites (house_doors, building27, plant_1ha): every re-plan keeps its
done stations, avoids the blocked discs and closed areas, verifies every wall still reachable as one network, and
its bound of the rest is never above the count of a fresh plan of the same constrained problem (tests/replan/fresh.py).
No timing here: scripts/bench/replan.py measures."""

from __future__ import annotations

import json
import math
import random

import pytest
import shapely

import planner
from planner.cli.main import main
from tests.conftest import INSTANCES
from tests.replan.fresh import fresh_rest_count

pytestmark = [pytest.mark.slow, pytest.mark.heavy]

SITES = ("house_doors", "building27", "plant_1ha")
SETS = 20


def random_edits(meta: dict, rng: random.Random) -> dict:
    """One to three stations done in walking order (the first moved by up to 0.3 m now and then), one or two of the
    others blocked (0.5-2 m), sometimes a 1.5-m closed square beside one of them, the crew at the last done one."""
    stations = sorted(meta["stations"], key=lambda s: s["number"])
    n_done = rng.randint(1, min(3, len(stations) - 1))
    done = [{"station": s["number"], "status": "done"} for s in stations[:n_done]]
    if rng.random() < 0.3:
        s = stations[0]
        done[0] |= {"x": s["x"] + rng.uniform(-0.3, 0.3), "y": s["y"] + rng.uniform(-0.3, 0.3)}
    others = stations[n_done:]
    blocked = [
        {"station": s["number"], "status": "blocked", "radius_m": round(rng.uniform(0.5, 2.0), 2)}
        for s in rng.sample(others, min(len(others), rng.randint(1, 2)))
    ]
    edits = {
        "format": "planner-edits/1",
        "stations": done + blocked,
        "crew": {"station": stations[n_done - 1]["number"]},
    }
    if rng.random() < 0.5:
        s = rng.choice(others)
        x, y = s["x"] + 3.0, s["y"]
        edits["areas"] = [{"kind": "closed", "polygon": [[x, y], [x + 1.5, y], [x + 1.5, y + 1.5], [x, y + 1.5]]}]
    return edits


@pytest.fixture(scope="module")
def plans(tmp_path_factory):
    d = tmp_path_factory.mktemp("random")
    out = {}
    for site in SITES:
        folder = d / site
        assert main(["plan", str(INSTANCES / f"{site}.json"), "--out", str(folder), "--quiet"]) == 0
        out[site] = folder / "plan.json"
    return out


@pytest.mark.parametrize("k", range(SETS))
def test_random_edit_set(plans, k):
    site = SITES[k % len(SITES)]
    meta = json.loads(plans[site].read_text())
    edits = random_edits(meta, random.Random(1000 + k))
    r = planner.replan(plans[site], edits)
    assert r.unexpected_gaps_m == 0.0, r.lines()
    assert r.connected, r.registration
    assert [s.id for s in r.done] == [e.station.id for e in r.edits.done]
    for e in r.edits.blocked:
        frame = next(s.frame for s in r.source.planned if s.id == e.station.id)
        assert all(math.dist(s.xy, e.station.xy) > e.radius_m for s in r.new if s.frame == frame)
    for a in r.edits.areas:
        assert not any(shapely.Polygon(a.polygon).intersects(shapely.Point(s.xy)) for s in r.new)
    fresh = fresh_rest_count(r)
    assert r.solution.rest_bound is not None and r.solution.rest_bound <= fresh, (r.solution, fresh)
