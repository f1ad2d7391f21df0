"""The memory guard: estimates from geometry alone, refuses the 10,000-km square at once (exit 3)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import planner
from planner.core.errors import InputError, UsageError
from planner.plan import PlanOptions, build_problem, closed_form_limits
from planner.plan.memory_guard import check_memory, estimate_work, parse_memory
from tests.conftest import INSTANCES, ROOT

HUGE_M = 10_000_000.0  # 10,000 km


def _square(path, side_m: float):
    path.write_text(
        json.dumps(
            {
                "format": "tls-planner/1",
                "name": "square",
                "zones": [
                    {
                        "id": "sq",
                        "scan_side": "inside",
                        "coordinates": [[0, 0], [side_m, 0], [side_m, side_m], [0, side_m]],
                        "vertex_heights_m": [10, 10, 10, 10],
                    }
                ],
            }
        )
    )
    return path


@pytest.mark.slow  # a fresh interpreter; the in-process twin below is quick
def test_ten_thousand_km_square_is_refused_in_one_line(tmp_path):
    path = _square(tmp_path / "huge.json", HUGE_M)
    run = subprocess.run([sys.executable, "-m", "planner", "plan", str(path)], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 3
    assert run.stderr.count("\n") == 1 and "MemoryError" not in run.stderr
    assert "--memory-limit" in run.stderr and "4e+07 wall pieces" in run.stderr


def test_ten_thousand_km_square_is_refused_in_one_line_by_the_command(tmp_path, capsys):
    # the same refusal through the command's entry point in this process: exit 3, one line, no MemoryError
    from planner.cli import main

    assert main(["plan", str(_square(tmp_path / "huge.json", HUGE_M))]) == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "MemoryError" not in err
    assert "--memory-limit" in err and "4e+07 wall pieces" in err


def test_estimate_counts_of_the_huge_square(tmp_path):
    site = planner.load_site(_square(tmp_path / "huge.json", HUGE_M))
    est = estimate_work(site, 1.0, 10.0, 270.0)
    assert est.targets == 4 * 10_000_000  # four 10^7 m walls in 1 m pieces
    # inside grid: (10^7 / 10)^2 = 10^12 points (the region's area over the cell) + 1 (the grid's count of a
    # region rounds up: memory_guard._grid_count), plus CANDIDATES_PER_WALL = 40 per wall, 4 walls
    assert est.candidates == 10**12 + 1 + 40 * 4
    with pytest.raises(InputError, match="over this limit"):
        check_memory(site, 1.0, 10.0, 270.0, limit_bytes=10 * 2**40)


@pytest.mark.parametrize(
    "name", ["polygon_b.json", "courtyard.json", pytest.param("baalbek.json", marks=pytest.mark.slow)]
)
def test_estimate_bounds_what_the_build_makes(name, request):
    site = planner.load_site(INSTANCES / name)
    if name == "polygon_b.json":  # the pool of the session's default plan of B: this very build, made once
        problem = request.getfixturevalue("polygon_b_default")[1].coverage
    else:
        problem = build_problem(site, PlanOptions())
    est = estimate_work(site, 1.0, 10.0, closed_form_limits(planner.validate_site(site)).max_slant_range_m)
    assert est.targets == len(problem.targets)  # ceil(length / spacing) per wall, as make_targets cuts
    assert est.pairs >= problem.by_candidate.nnz  # an upper estimate of the kept pairs


def test_a_tight_limit_refuses_a_small_site():
    site = planner.load_site(INSTANCES / "polygon_b.json")
    with pytest.raises(InputError, match="--memory-limit = '1.0 KiB'"):
        build_problem(site, PlanOptions(memory_limit_bytes=1024))


def test_parse_memory():
    assert parse_memory("4G") == 4 * 2**30 and parse_memory("512M") == 512 * 2**20
    assert parse_memory("800k") == 800 * 1024 and parse_memory("1000") == 1000 and parse_memory("2GiB") == 2 * 2**30
    for bad in ("lots", "-1G", "0", "nanG"):
        with pytest.raises(UsageError, match="--memory-limit"):
            parse_memory(bad)
