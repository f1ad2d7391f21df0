"""The public API: every name in planner.__all__ resolves and is documented; results show in notebooks;
the example sweep script uses nothing but the public API."""

from __future__ import annotations

import ast
import dataclasses
import inspect

import pytest

import planner
from planner.core.errors import InputError, UsageError
from tests.conftest import INSTANCES, ROOT, package_calls


def test_every_public_name_resolves_and_has_a_docstring():
    for name in planner.__all__:
        obj = getattr(planner, name)
        if inspect.isclass(obj) or inspect.isfunction(obj):
            assert inspect.getdoc(obj), name


def test_public_functions_are_typed():
    for name in planner.__all__:
        obj = getattr(planner, name)
        if inspect.isfunction(obj):
            sig = inspect.signature(obj)
            assert sig.return_annotation is not inspect.Signature.empty, name
            for p in sig.parameters.values():
                if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                    assert p.annotation is not inspect.Parameter.empty, (name, p.name)


@pytest.mark.slow
def test_results_have_summary_and_html_repr():
    site = planner.load_site(INSTANCES / "polygon_b.json")
    plan = planner.plan_site(site)
    network = planner.run_network(site, list(plan.stations))
    outcome = planner.outcome_from_plan(plan, network)
    for obj in (plan, plan.result, plan.verification, plan.validation, network, outcome):
        text = obj.summary()
        html = obj._repr_html_()
        assert text and html.startswith('<div class="tls-planner">')
        first = text.splitlines()[0].replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
        assert first.replace("'", "&#x27;").replace('"', "&quot;") in html


def test_sweep_script_uses_only_the_public_api():
    tree = ast.parse((ROOT / "scripts/studies/sweep_polygon_a.py").read_text())
    imports = {a.name for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom)) for a in n.names}
    modules = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert not any(m and m.startswith("planner") for m in modules)  # no "from planner.x import y"
    assert "planner" in imports
    used = {
        n.attr
        for n in ast.walk(tree)
        if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id == "planner"
    }
    assert used and used <= set(planner.__all__), used - set(planner.__all__)


def test_only_the_command_line_prints():
    # library modules log; print() appears only in planner/cli/ (docstring examples aside)
    offenders = [
        p.name
        for p in (ROOT / "planner").rglob("*.py")
        if "cli" not in p.relative_to(ROOT / "planner").parts
        and any(line.lstrip().startswith("print(") for line in p.read_text().splitlines())
    ]
    assert offenders == []


def test_with_parameters_changes_only_what_is_named_and_validates():
    site = planner.load_site(INSTANCES / "polygon_b.json")
    s2 = site.with_parameters(theta_max_deg=60.0)
    assert s2.parameters.theta_max_deg == 60.0 and s2.parameters.overlap == site.parameters.overlap
    assert s2.zones == site.zones
    with pytest.raises(planner.InputError, match="theta_max_deg = 95"):
        site.with_parameters(theta_max_deg=95.0)


@pytest.mark.parametrize(
    "make, field",
    [
        # options: the field at fault is named (a wrong type is refused, not coerced or crashed on later)
        (lambda: planner.MilpOptions(time_limit_s=0), "time_limit_s"),
        (lambda: planner.MilpOptions(threads=0), "threads"),
        (lambda: planner.MilpOptions(k=1.5), "k"),
        (lambda: planner.MilpOptions(k=True), "k"),
        (lambda: planner.MilpOptions(ring_lagrange_steps=-5), "ring_lagrange_steps"),
        (lambda: planner.MilpOptions(presolve="no"), "presolve"),
        (lambda: planner.MilpOptions(overlap=0.3), "overlap"),
        (lambda: planner.OverlapRule(overlap=1.0), "overlap"),
        (lambda: planner.OverlapRule(max_link_m=0.0), "max_link_m"),
        (lambda: planner.OverlapRule(min_shared_m=float("nan")), "min_shared_m"),
        (lambda: planner.PoolOptions(grid_spacing_m=0), "grid_spacing_m"),
        (lambda: planner.PoolOptions(seed=-1), "seed"),
        (lambda: planner.PlanOptions(precision="no"), "precision"),
        (lambda: planner.PlanOptions(verify_spacing_m=1e-6), "verify_spacing_m"),
        (lambda: planner.PlanOptions(memory_limit_bytes=float("nan")), "memory_limit_bytes"),
        # k > 1 is the MILP's: the greedy and the closed form would ignore it silently
        (lambda: planner.PlanOptions(method="greedy", milp=planner.MilpOptions(k=2)), "k"),
    ],
)
def test_bad_options_name_their_field(make, field):
    with pytest.raises(UsageError, match=rf"\b{field} = "):
        make()


@pytest.mark.slow
def test_library_misuse_is_refused_not_answered():
    site = planner.load_site(INSTANCES / "polygon_b.json")
    problem = planner.build_problem(site, planner.PlanOptions())
    n = problem.by_candidate.shape[0]
    # costs of 0 or -1 made "0 stations" (or "-21 stations") optimal
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(InputError, match="cost"):
            planner.cover_instance(problem, cost=[bad] * n)
        with pytest.raises(InputError, match="weights"):
            planner.greedy_cover(problem.by_candidate, weights=[bad] * n)
    # solve takes the solver's view of a problem, and only MilpOptions' fields
    with pytest.raises(UsageError, match="cover_instance"):
        planner.solve(problem)
    with pytest.raises(UsageError, match="bogus = 1"):
        planner.solve(planner.cover_instance(problem), bogus=1)
    # a scan side given as text is read as the enum
    z = planner.Zone("A", "inside", ((0, 0), (10, 0), (10, 10), (0, 10)), (3.0,) * 4)
    assert z.scan_side is planner.ScanSide.INSIDE
    # two stations with one id would merge into one network node
    plan = planner.plan_site(site, planner.PlanOptions(method="greedy"))
    twins = [plan.stations[0], dataclasses.replace(plan.stations[1], id=plan.stations[0].id)]
    with pytest.raises(InputError, match="station id used twice"):
        planner.run_network(site, twins)
    with pytest.raises(InputError, match="at least one station"):
        planner.run_network(site, [])


@pytest.fixture(scope="module")
def greedy_b(polygon_b_greedy):
    return polygon_b_greedy


@pytest.mark.parametrize(
    "call, field, words",
    [
        # a path where a Site goes, a method name where options go, a Plan where an Outcome or stations go ...
        (lambda site, plan: planner.plan_site(5), "site", "load_site(path) reads one"),
        (lambda site, plan: planner.plan_site(site, "milp"), "options", "PlanOptions(method='milp')"),
        (lambda site, plan: planner.validate_site(plan), "site", "not a Plan"),
        (lambda site, plan: planner.build_problem(site, planner.MilpOptions()), "options", "not a MilpOptions"),
        (lambda site, plan: planner.outcome_from_plan(site), "plan", "plan_site(site, options) makes one"),
        (lambda site, plan: planner.outcome_from_plan(plan, plan), "network", "run_network(site, plan.stations)"),
        (lambda site, plan: planner.run_network(site, plan), "stations", "use plan.stations"),
        (lambda site, plan: planner.run_network(plan, plan.stations), "site", "not a Plan"),
        (lambda site, plan: planner.run_network(site, [1, 2]), "stations", "item 1 is an int"),
        (lambda site, plan: planner.write_report(plan, "unused"), "outcome", "outcome_from_plan(plan) makes one"),
        (lambda site, plan: planner.write_dxf(plan, "unused.dxf"), "outcome", "not a Plan"),
        (lambda site, plan: planner.write_geojson(site, "unused.geojson"), "outcome", "not a Site"),
        (lambda site, plan: planner.write_stations_csv(plan, "unused.csv"), "outcome", "not a Plan"),
        (lambda site, plan: planner.plan_figures(plan), "outcome", "not a Plan"),
        (lambda site, plan: planner.network_figure(plan), "outcome", "not a Plan"),
        (lambda site, plan: planner.cover_instance(plan), "problem", "build_problem(site, options) makes one"),
        # a Site, None or a number where a path goes (pathlib's TypeError before)
        (lambda site, plan: planner.load_site(site), "path", "must be a file path (str or pathlib.Path), not Site"),
        (lambda site, plan: planner.load_site(None), "path", "not NoneType"),
        (lambda site, plan: planner.outcome_from_file(5), "plan_path", "not int"),
        (lambda site, plan: planner.greedy_cover(None), "by_candidate", "must be a scipy.sparse matrix"),
    ],
)
def test_an_object_of_the_wrong_kind_is_named_with_how_to_get_the_right_one(
    greedy_b, call, field, words, tmp_path, monkeypatch
):
    # before: AttributeError deep inside ('Plan' object has no attribute 'coverage'); now one line naming the
    # argument, what it got and how to make what it takes, a UsageError that is also a TypeError; no file written
    monkeypatch.chdir(tmp_path)
    with pytest.raises(planner.core.errors.ArgumentTypeError) as err:
        call(*greedy_b)
    assert isinstance(err.value, TypeError) and isinstance(err.value, UsageError)
    assert str(err.value).startswith(field) and words in str(err.value)
    assert not list(tmp_path.iterdir())


def test_scripts_import_only_public_names():
    # issue 33: benchmarks and reproductions use the public API (no private module, no _name), so the package
    # can change its insides without breaking them
    import ast

    offenders = []
    for path in sorted((ROOT / "scripts").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("planner"):
                parts = node.module.split(".")
                names = [a.name for a in node.names]
                if any(p.startswith("_") for p in parts) or any(n.startswith("_") for n in names):
                    offenders.append(f"{path.name}: from {node.module} import {', '.join(names)}")
            elif isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__"):
                base = node.value
                if isinstance(base, ast.Name) and base.id in ("planner", "P"):
                    offenders.append(f"{path.name}: {base.id}.{node.attr}")
    assert offenders == []


def test_one_home_for_the_overlap_rule_and_the_site_validation():
    # issue 33: an OverlapRule is built in one place (planner.coverage.overlap.rule_of; planning_rule decides
    # "overlap 0 means off"), and the command line validates a site once per run (tests/cli/test_cli_profile.py)

    # every call of the package (parsed once per session: tests/conftest.py)
    builders = [rel for rel, _, name in package_calls() if name == "OverlapRule"]
    assert builders == ["planner/coverage/overlap.py"]
    from planner.coverage.overlap import planning_rule, rule_of

    assert planning_rule(0.0) is None and planning_rule(0.3) == rule_of(0.3)
    assert rule_of(0.0).overlap == 0.0  # share 0 still links stations that share wall (checks, surveys)
