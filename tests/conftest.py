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

#: quick-tier tests over ~1 s on a quiet machine (the slowest of `pytest -m "not slow" --durations=100`, 2026-11-28:
#: the first 23 at 2.5-8.5 s under a load of 6, the rest at 1.0-5.2 s quiet): the slow tier runs them (CI runs both
#: tiers), so that the quick tier answers in about two minutes; by node id, a parametrised case by its id
SLOW_BY_TIME = frozenset(
    {
        "tests/bounds/test_ring_ahead.py::test_quick_covers_begun_ahead_are_the_covers_made_for_the_count[1]",
        "tests/bounds/test_ring_ahead.py::test_quick_covers_begun_ahead_are_the_covers_made_for_the_count[3]",
        "tests/bounds/test_ring_ahead.py::test_quick_covers_begun_ahead_are_the_covers_made_for_the_count[30]",
        "tests/bounds/test_ring_ahead.py::test_regions_sent_by_the_parent_give_the_parts_of_regions_drawn_there",
        "tests/bounds/test_patch_cover.py::test_the_narrow_tests_give_the_answers_of_the_full_ones",
        "tests/solve/test_lazy_links.py::test_plain_dominance_as_the_walk",
        "tests/test_api.py::test_one_home_for_the_overlap_rule_and_the_site_validation",
        "tests/plan/test_plan.py::test_greedy_verifies_at_100_percent[polygon_b]",
        "tests/coverage/test_openings.py::test_overlap_zero_turns_registration_off",
        "tests/plan/test_plan_milp.py::test_plain_cover_backends_agree_and_beat_greedy[polygon_b]",
        "tests/coverage/test_sight_boxes.py::test_boxes_meeting_is_the_trees_query",
        "tests/io/test_fuzz_inputs.py::test_mutated_inputs_are_read_whole_or_refused_in_one_line[plan]",
        "tests/field/test_walls.py::test_rooms_without_openings_get_legs_through_walls",
        "tests/solve/test_presolve.py::test_linked_dominance_drops_what_the_whole_relation_drops",
        "tests/solve/test_presolve.py::test_dominated_matches_its_definition",
        "tests/solve/test_presolve.py::test_an_optimal_connected_plan_survives_the_passes",
        "tests/solve/test_windows.py::test_same_input_same_plan_and_a_moved_site_changes_nothing",
        "tests/solve/test_windows.py::test_one_window_over_the_whole_line_finds_the_chain_of_19",
        "tests/solve/test_windows.py::test_small_windows_rejoin_the_line_they_cut",
        "tests/solve/test_windows.py::test_a_window_over_everything_meets_enumeration[5]",
        "tests/plan/test_plan_milp.py::test_export_orlib_roundtrip",
        "tests/solve/test_covers.py::test_every_method_covers_the_plain_instance_and_the_milp_is_smallest",
        "tests/test_engine.py::test_resolve_names_tiles_for_the_16_ha_plant_and_one_model_for_a_building",
        "tests/io/test_fuzz_inputs.py::test_mutated_inputs_are_read_whole_or_refused_in_one_line[dxf]",
        "tests/tiles/test_tiles.py::test_tiles_complete_a_pool_that_misses_pieces",
        "tests/tiles/test_tiles.py::test_tiles_plan_a_corridor_from_the_single_models_pool",
        "tests/tiles/test_auto.py::test_a_tiled_site_of_few_pieces_gets_the_fine_grid_where_none_is_given",
        "tests/tiles/test_auto.py::test_16ha_plant_goes_to_tiles_split_by_the_budget",
        "tests/tiles/test_cli_tiles.py::test_a_scheduler_address_that_is_malformed_or_silent_is_named",
        "tests/solve/test_cft.py::test_matches_brute_force",
        "tests/plan/test_tripod_discs.py::test_recentring_disc_reads_no_uninitialised_memory",
        "tests/plan/test_relied_targets.py::test_relied_targets_equal_the_plain_loop",
        "tests/bounds/test_plane_refine.py::test_a_u_block_is_proven_by_the_cover_over_patches_where_the_ring_walk_is_not",
        "tests/solve/test_ring.py::test_lagrangian_bound_stays_below_the_optimum_and_can_pass_the_ring",
        "tests/field/test_spread.py::test_spread_triple_is_the_brute_force_optimum",
        "tests/solve/test_work_limit.py::test_a_node_limit_stops_the_other_backends[scip]",
        "tests/plan/test_surfaces_plan.py::test_l_room_with_a_column_planned_with_floor_and_ceiling",
        "tests/plan/test_surfaces_plan.py::test_moving_the_room_changes_no_station_count",
        "tests/plan/test_surfaces_plan.py::test_verify_command_checks_floors_when_asked",
        "tests/plan/test_surfaces_plan.py::test_ceilings_planned_and_verified",
        "tests/plan/test_surfaces_plan.py::test_every_method_but_the_closed_form_covers_the_floor[extra2]",
        "tests/plan/test_field_time.py::test_the_report_shows_the_hours_and_the_trade_off",
        "tests/plan/test_field_time.py::test_same_command_same_plan",
        "tests/io/test_fuzz_inputs.py::test_mutated_inputs_are_read_whole_or_refused_in_one_line[geojson]",
        "tests/cli/test_cli.py::test_a_hand_edited_plan_json_is_refused_in_one_line",
        "tests/coverage/test_regions_accuracy.py::test_region_with_view_error_and_standoff_agrees_with_the_coverage_test[convex-0.4-soudarissanane]",
        "tests/network/test_proposal.py::test_control_spots_and_triangles_equal_the_loops",
        "tests/coverage/test_regions_batch.py::test_chunked_regions_are_the_single_piece_regions[plain-False-0.0]",
        "tests/coverage/test_surface_sight.py::test_the_matrix_equals_a_brute_force_oracle_and_does_not_move_with_the_site",
        "tests/field/test_field.py::test_cli_exit_codes",
        "tests/field/test_certify.py::test_bound_below_brute_force_optimum_below_route",
        "tests/plan/test_memory_guard.py::test_estimate_bounds_what_the_build_makes[polygon_b.json]",
        "tests/plan/test_field_time.py::test_a_plan_without_settings_has_no_hours_section",
        "tests/plan/test_registration_home.py::test_registration_is_decided_only_where_the_problem_is_resolved",
        "tests/report/test_surfaces_report.py::test_section_rows_are_plan_json_verification",
        "tests/plan/test_surfaces_plan.py::test_room_floor_planned_and_found_covered_by_an_independent_check",
        "tests/plan/test_surfaces_discs.py::test_batched_rims_give_the_discs_of_the_station_by_station_test",
    }
)


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
    """Mark the heavy properties ``heavy``, the quick tests too slow for the quick tier (:data:`SLOW_BY_TIME`) ``slow``,
    and every ``heavy`` test ``slow`` as well, before ``-m`` deselects: heavy is a part of the slow tier."""
    for item in items:
        path, _, name = item.nodeid.partition("::")
        if name.split("[")[0] in HEAVY_PROPERTIES.get(path, ()):
            item.add_marker(pytest.mark.heavy)
        if item.nodeid in SLOW_BY_TIME:
            item.add_marker(pytest.mark.slow)
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
