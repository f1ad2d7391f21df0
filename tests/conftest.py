"""Shared fixtures: paths to the bundled instances and a CSV writer for small test sites; the test tiers.

Three tiers: the quick tier (``-m "not slow"``, under three minutes serial on a quiet 2-core machine), the CI
command (``-m "not heavy"``: the quick tier and the slow tests) and the heavy tests (``-m heavy``: large sites
re-planned end to end, properties, fuzzing and browsers at full size). A heavy test is always slow too, so the quick
tier never runs one even where its file marks it ``heavy`` alone.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
INSTANCES = ROOT / "instances"
HEADER = "zone,scan_side,index,side_length_m,wall_height_m,interior_angle_deg,vertex_height_m\n"


#: heavy properties marked here, not by a decorator: hypothesis derandomises a property by its source, decorators
#: included, so a marker line would change the examples it has always run (file -> test names)
HEAVY_PROPERTIES = {
    "tests/bounds/test_plane_properties.py": {
        "test_a_no_piece_refused_that_a_position_sees",
        "test_b_no_sampled_position_beats_the_plane_bound",
        "test_c_plane_bound_at_most_brute_force_optimum",
        "test_d_corridor_within_the_centre_line_construction",
    },
}


@functools.cache
def package_trees() -> tuple[tuple[Path, ast.Module], ...]:
    """Every module of the planner package, parsed once per session: ``(path, tree)`` sorted by path. The source checks
    (tests/test_codebase.py, tests/test_api.py, tests/plan/test_registration_home.py) read them and change none."""
    return tuple((p, ast.parse(p.read_text())) for p in sorted((ROOT / "planner").rglob("*.py")))


@functools.cache
def package_calls() -> tuple[tuple[str, int, str | None], ...]:
    """Every call in the planner package, once per session: ``(module path from the root, line, name called)``, the
    name being the function's (``f(...)``) or the attribute's (``x.f(...)``), None for other callees."""
    return tuple(
        (str(p.relative_to(ROOT)), node.lineno, getattr(node.func, "id", getattr(node.func, "attr", None)))
        for p, tree in package_trees()
        for node in ast.walk(tree)
        if isinstance(node, ast.Call)
    )


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark the heavy properties ``heavy`` and every ``heavy`` test ``slow`` as well, before ``-m`` deselects: heavy
    is a part of the slow tier."""
    for item in items:
        path, _, name = item.nodeid.partition("::")
        if name.split("[")[0] in HEAVY_PROPERTIES.get(path, ()):
            item.add_marker(pytest.mark.heavy)
        if item.get_closest_marker("heavy") is not None and item.get_closest_marker("slow") is None:
            item.add_marker(pytest.mark.slow)


@pytest.fixture
def write_csv(tmp_path: Path):
    """Write table rows ``(zone, side, index, L, wall h, angle, vertex h)`` to a CSV and return its path."""

    def _write(rows: list[tuple], name: str = "site.csv", header: str = HEADER) -> Path:
        path = tmp_path / name
        path.write_text(header + "".join(",".join(str(c) for c in r) + "\n" for r in rows))
        return path

    return _write


@pytest.fixture(scope="session")
def polygon_b_greedy():
    """``(site, plan)``: bundled polygon B planned by the greedy, made once per session and shared by the tests that
    only read it (a Plan is frozen; they must not change its arrays)."""
    import planner

    site = planner.load_site(INSTANCES / "polygon_b.json")
    return site, planner.plan_site(site, planner.PlanOptions(method="greedy"))


@pytest.fixture(scope="session")
def polygon_b_default():
    """``(site, plan)``: bundled polygon B planned with the library's defaults (the MILP, tripod discs), made once per
    session for the tests that only read it."""
    import planner

    site = planner.load_site(INSTANCES / "polygon_b.json")
    return site, planner.plan_site(site, planner.PlanOptions())


@pytest.fixture(scope="session")
def house_doors_greedy():
    """``(site, plan)``: bundled house_doors (4 rooms, 4 openings) planned by the greedy, made once per session for
    the tests that only read it."""
    import planner

    site = planner.load_site(INSTANCES / "house_doors.json")
    return site, planner.plan_site(site, planner.PlanOptions(method="greedy"))


@pytest.fixture(scope="session")
def polygon_b_report(tmp_path_factory) -> Path:
    """The folder where ``planner plan instances/polygon_b.json --target-spacing 2 --out D --report D`` wrote its
    plan.json and report.html (a walls-only plan without settings: every section and figure of the report at half the
    1-m coverage's cost), made once per session for the tests that only read them."""
    from planner.cli import main

    out = tmp_path_factory.mktemp("polygon_b_report")
    site = str(INSTANCES / "polygon_b.json")
    assert main(["plan", site, "--target-spacing", "2", "--out", str(out), "--report", str(out), "--quiet"]) == 0
    return out


def square_rows(zone: str = "S", side: str = "inside", length: float = 10.0, height: float = 5.0) -> list[tuple]:
    """A length x length square zone, every angle 90 deg."""
    return [(zone, side, i, length, height, 90, height) for i in range(1, 5)]
