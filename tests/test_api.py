"""The public API: every name in planner.__all__ resolves and is documented; results show in notebooks;
the example sweep script uses nothing but the public API."""

from __future__ import annotations

import ast
import inspect

import pytest

import planner
from tests.conftest import INSTANCES, ROOT


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
    tree = ast.parse((ROOT / "scripts/sweep_polygon_a.py").read_text())
    imports = {a.name for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom)) for a in n.names}
    modules = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert not any(m and m.startswith("planner") for m in modules)  # no "from planner.x import y"
    assert "planner" in imports
    used = {n.attr for n in ast.walk(tree)
            if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id == "planner"}
    assert used and used <= set(planner.__all__), used - set(planner.__all__)


def test_only_the_command_line_prints():
    # library modules log; print() appears only in planner/cli*.py (docstring examples aside)
    offenders = [p.name for p in (ROOT / "planner").rglob("*.py") if not p.name.startswith("cli")
                 and any(line.lstrip().startswith("print(") for line in p.read_text().splitlines())]
    assert offenders == []


def test_with_parameters_changes_only_what_is_named_and_validates():
    site = planner.load_site(INSTANCES / "polygon_b.json")
    s2 = site.with_parameters(theta_max_deg=60.0)
    assert s2.parameters.theta_max_deg == 60.0 and s2.parameters.overlap == site.parameters.overlap
    assert s2.zones == site.zones
    with pytest.raises(planner.InputError, match="theta_max_deg = 95"):
        site.with_parameters(theta_max_deg=95.0)
