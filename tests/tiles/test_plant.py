"""The generated plants: deterministic, bundled as generated, and what the generator promises."""

from __future__ import annotations

import importlib.util
import json
import math

import pytest

from planner.coverage.links import registration_groups
from planner.io.load import load_site
from planner.plan import PlanOptions, build_problem
from tests.conftest import INSTANCES, ROOT

spec = importlib.util.spec_from_file_location("make_plant", ROOT / "scripts" / "make" / "make_plant.py")
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


@pytest.mark.slow
def test_plant_loads_and_every_piece_is_seen() -> None:
    site = load_site(INSTANCES / "plant_1ha.json")
    problem = build_problem(site, PlanOptions(method="milp"))  # raises InfeasibleError on an unseen piece
    assert problem.uncoverable().size == 0


@pytest.mark.slow
def test_site_registration_puts_the_whole_plant_in_one_group() -> None:
    """The plant's open ground is one accessible area: in ``site`` mode (what tiles use) every candidate is in
    one group, whichever zone proposed it; in ``zone`` mode there is one group per object (9 on 1 ha)."""
    site = load_site(INSTANCES / "plant_1ha.json")
    problem = build_problem(site, PlanOptions(method="milp"))
    labels, _ = registration_groups(site, problem.candidates, "site", 60.0)
    assert len(set(labels)) == 1
    zone_labels, _ = registration_groups(site, problem.candidates, "zone", 60.0)
    assert len(set(zone_labels)) == 9
