"""The generated plants: deterministic, bundled as generated, and what the generator promises."""

from __future__ import annotations

import importlib.util
import json
import math

import pytest

from planner.coverage.groups import open_ground, registration_groups
from planner.plan import PlanOptions, build_problem
from planner.site.load import load_site
from tests.conftest import INSTANCES, ROOT

spec = importlib.util.spec_from_file_location("make_plant", ROOT / "scripts" / "make_plant.py")
make_plant = importlib.util.module_from_spec(spec)
spec.loader.exec_module(make_plant)


def test_same_seed_same_plant_other_seed_other_plant() -> None:
    assert make_plant.plant(4, 0) == make_plant.plant(4, 0)
    assert make_plant.plant(4, 0)["zones"] != make_plant.plant(4, 1)["zones"]


@pytest.mark.parametrize("area", [1, 4, 16])
def test_bundled_plants_are_the_generator_output(area: int, tmp_path) -> None:
    out = tmp_path / "p.json"
    make_plant.main(["--area-ha", str(area), "--seed", "0", "--out", str(out)])
    assert out.read_text() == (INSTANCES / f"plant_{area}ha.json").read_text()
    data = json.loads(out.read_text())
    # one object per 33 m cell: 1 ha is a 100 m square -> round(100 / 33) = 3 cells a side, 9 objects;
    # 16 ha -> round(400 / 33) = 12 a side, 144
    n = round(math.sqrt(area * 10_000) / 33)
    assert len(data["zones"]) == n * n
    assert all(z["scan_side"] == "outside" for z in data["zones"])
    assert out.stat().st_size < 64_000  # small files


def test_plant_loads_and_every_piece_is_seen() -> None:
    site = load_site(INSTANCES / "plant_1ha.json")
    problem = build_problem(site, PlanOptions(method="milp"))  # raises InfeasibleError on an unseen piece
    assert problem.uncoverable().size == 0


def test_groups_follow_the_ground_a_station_stands_on_not_pool_order() -> None:
    """On the plant the open ground (roads) is one piece, so every candidate is in one group, whichever
    zone proposed it; before, the proposing zone decided (9 groups, most candidates in the first zone)."""
    site = load_site(INSTANCES / "plant_1ha.json")
    problem = build_problem(site, PlanOptions(method="milp"))
    assert len(open_ground(site, "site")) == 1
    assert set(registration_groups(site, problem.candidates)) == {"site/area 1"}
    assert len({c.zone for c in problem.candidates}) == 9
