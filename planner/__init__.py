"""Terrestrial laser scanner station planning.

The pipeline, and the public API for each step:

1. site: :func:`load_site` (JSON instance, table CSV, DXF, GeoJSON), :class:`Site`, :class:`Parameters`,
   :func:`validate_site`;
2. the run resolved once: :func:`resolve` -> :class:`Problem` (validation, sight limits, registration rule and
   scope, strategy); candidates: :func:`candidate_pool` (the dissertation's closed-form stations, field
   samples, grid);
3. coverage: :func:`build_problem` (candidates x wall pieces, both sparse views);
4. solving: :func:`greedy_cover`, :func:`solve` (MILP on CP-SAT, SCIP, HiGHS, CBC, PuLP) or all of it
   at once with :func:`plan_site` -> :class:`Plan` (verified);
5. checking: :func:`verify_stations`, :func:`run_network` (least-squares accuracy); on site,
   :func:`replan` -> :class:`Replan` (a plan repaired after its edits: stations done, blocked or moved, obstacles,
   closed areas and zones);
6. showing: :func:`outcome_from_plan` -> :class:`Outcome`, :func:`plan_figures`, :func:`network_figure`,
   :func:`comparison_figure`, :func:`write_report`, :func:`write_dxf`, :func:`write_geojson`,
   :func:`write_stations_csv`.

Results are frozen dataclasses with ``summary()`` and a notebook ``_repr_html_``. Library code logs
(``logging.getLogger("planner")``) and never prints.

Examples
--------
>>> import planner
>>> site = planner.load_site("instances/polygon_b.json")                  # doctest: +SKIP
>>> plan = planner.plan_site(site)          # what `planner plan` gives   # doctest: +SKIP
>>> print(plan.summary())                                                # doctest: +SKIP
>>> planner.write_report(planner.outcome_from_plan(plan), "out/")         # doctest: +SKIP
"""

import importlib
import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

__version__ = "0.2.0"


def _lazy_getattr(package: str, table: dict[str, str], namespace: dict[str, Any]) -> Callable[[str], Any]:
    """A module ``__getattr__`` (PEP 562) that imports ``table[name]`` on first use and keeps the value in
    ``namespace``: for this package and :mod:`planner.io`."""

    def __getattr__(name: str) -> Any:
        module = table.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    return __getattr__


#: public name -> the module that defines it; imported on first use (PEP 562), so that
#: ``import planner`` (and the ``planner`` command's start) loads no numerical stack
_LAZY = {
    **dict.fromkeys(
        (
            "ErrorBudget",
            "IncidenceErrorTable",
            "instrument_height_tolerance_m",
            "max_slant_range_m",
            "point_error",
            "sigma_instr_m",
            "sigma_meas_m",
            "tolerance_for_scale_m",
        ),
        "planner.instrument.accuracy",
    ),
    **dict.fromkeys(
        ("ClosureError", "ExitCode", "InfeasibleError", "InputError", "PlannerError", "UsageError"),
        "planner.core.errors",
    ),
    **dict.fromkeys(("Scanner", "TotalStation", "list_instruments", "load_instrument"), "planner.instrument.models"),
    **dict.fromkeys(("ClosureTolerance", "Parameters", "RangeLimit", "resolve_range_limit"), "planner.site.params"),
    **dict.fromkeys(("ControlPoint", "NoGoArea", "Obstacle", "ScanSide", "Site", "Wall", "Zone"), "planner.site"),
    **dict.fromkeys(("ValidationReport", "validate_site"), "planner.site.validate"),
    **dict.fromkeys(("Candidate", "CandidateKind"), "planner.site.candidate"),
    **dict.fromkeys(("PoolOptions", "candidate_pool"), "planner.candidates.pool"),
    **dict.fromkeys(("CoverageProblem", "build_coverage"), "planner.coverage.matrix"),
    **dict.fromkeys(("OverlapRule",), "planner.coverage.overlap"),
    **dict.fromkeys(("StationCoverage", "station_coverage"), "planner.coverage.stations"),
    **dict.fromkeys(("make_targets",), "planner.coverage.targets"),
    **dict.fromkeys(("write_dxf", "write_geojson", "write_stations_csv"), "planner.io"),
    **dict.fromkeys(("load_site",), "planner.io.load"),
    **dict.fromkeys(("DxfOptions", "read_dxf_site"), "planner.io.dxf_in"),
    **dict.fromkeys(("read_geojson_site",), "planner.io.geojson_in"),
    **dict.fromkeys(("comparison_figure", "network_figure", "plan_figure", "plan_figures"), "planner.figures"),
    **dict.fromkeys(("NetworkReport", "run_network"), "planner.network.check"),
    **dict.fromkeys(("Outcome", "outcome_from_plan"), "planner.plan.outcome"),
    **dict.fromkeys(("outcome_from_file",), "planner.io.plan_file"),
    **dict.fromkeys(("Plan", "PlanOptions", "Problem", "StrategyOptions", "build_problem", "resolve"), "planner.plan"),
    **dict.fromkeys(("plan_site",), "planner.engine"),
    **dict.fromkeys(("Replan", "replan"), "planner.replanning.run"),
    **dict.fromkeys(("Sight",), "planner.coverage.sight"),
    **dict.fromkeys(("read_plan_stations", "write_plan"), "planner.io.plan_json"),
    **dict.fromkeys(("compare_methods", "render_report", "write_report"), "planner.report"),
    **dict.fromkeys(("greedy_cover",), "planner.solve.greedy"),
    **dict.fromkeys(("CoverInstance", "cover_instance"), "planner.solve.instance"),
    **dict.fromkeys(("MilpOptions",), "planner.solve.milp"),
    **dict.fromkeys(("SolveResult", "Status"), "planner.solve.result"),
    **dict.fromkeys(("VerifyReport", "verify_stations"), "planner.plan.verify"),
}

logging.getLogger("planner").addHandler(logging.NullHandler())


__getattr__ = _lazy_getattr("planner", _LAZY, globals())


def __dir__() -> list[str]:
    """The public names (``__all__``) and the version: what tab completion should offer, not the helpers."""
    return sorted(set(__all__) | {"__version__"})


# ``planner.solve`` is both a subpackage and the MILP function. The (namespace) package is bound
# first, cheaply, so that loading its modules later never rebinds the name; then the function.
import planner.solve  # noqa: E402, F401

if not TYPE_CHECKING:

    def solve(*args: Any, **kwargs: Any) -> "SolveResult":
        """Solve a coverage problem as a set-cover MILP: :func:`planner.solve.milp.solve` (same arguments)."""
        from planner.solve.milp import solve as _solve

        return _solve(*args, **kwargs)


if TYPE_CHECKING:  # the static view of the same names, for type checkers and IDEs
    from planner.candidates.pool import PoolOptions, candidate_pool
    from planner.core.errors import ClosureError, ExitCode, InfeasibleError, InputError, PlannerError, UsageError
    from planner.coverage.matrix import CoverageProblem, build_coverage
    from planner.coverage.overlap import OverlapRule
    from planner.coverage.sight import Sight
    from planner.coverage.stations import StationCoverage, station_coverage
    from planner.coverage.targets import make_targets
    from planner.engine import plan_site
    from planner.figures import comparison_figure, network_figure, plan_figure, plan_figures
    from planner.instrument.accuracy import (
        ErrorBudget,
        IncidenceErrorTable,
        instrument_height_tolerance_m,
        max_slant_range_m,
        point_error,
        sigma_instr_m,
        sigma_meas_m,
        tolerance_for_scale_m,
    )
    from planner.instrument.models import Scanner, TotalStation, list_instruments, load_instrument
    from planner.io import load_site, write_dxf, write_geojson, write_stations_csv
    from planner.io.dxf_in import DxfOptions, read_dxf_site
    from planner.io.geojson_in import read_geojson_site
    from planner.io.plan_file import outcome_from_file
    from planner.io.plan_json import read_plan_stations, write_plan
    from planner.network.check import NetworkReport, run_network
    from planner.plan import Plan, PlanOptions, Problem, StrategyOptions, build_problem, resolve
    from planner.plan.outcome import Outcome, outcome_from_plan
    from planner.plan.verify import VerifyReport, verify_stations
    from planner.replanning.run import Replan, replan
    from planner.report import compare_methods, render_report, write_report
    from planner.site import ControlPoint, NoGoArea, Obstacle, ScanSide, Site, Wall, Zone
    from planner.site.candidate import Candidate, CandidateKind
    from planner.site.params import ClosureTolerance, Parameters, RangeLimit, resolve_range_limit
    from planner.site.validate import ValidationReport, validate_site
    from planner.solve.greedy import greedy_cover
    from planner.solve.instance import CoverInstance, cover_instance
    from planner.solve.milp import MilpOptions, solve
    from planner.solve.result import SolveResult, Status

__all__ = [
    "Candidate",
    "CandidateKind",
    "ClosureError",
    "ClosureTolerance",
    "ControlPoint",
    "CoverInstance",
    "CoverageProblem",
    "DxfOptions",
    "ErrorBudget",
    "ExitCode",
    "IncidenceErrorTable",
    "InfeasibleError",
    "InputError",
    "MilpOptions",
    "NetworkReport",
    "NoGoArea",
    "Obstacle",
    "Outcome",
    "OverlapRule",
    "Parameters",
    "Plan",
    "PlanOptions",
    "PlannerError",
    "PoolOptions",
    "Problem",
    "RangeLimit",
    "Replan",
    "ScanSide",
    "Sight",
    "Scanner",
    "Site",
    "SolveResult",
    "StationCoverage",
    "Status",
    "StrategyOptions",
    "TotalStation",
    "UsageError",
    "ValidationReport",
    "VerifyReport",
    "Wall",
    "Zone",
    "build_coverage",
    "build_problem",
    "candidate_pool",
    "compare_methods",
    "comparison_figure",
    "cover_instance",
    "greedy_cover",
    "instrument_height_tolerance_m",
    "list_instruments",
    "load_instrument",
    "load_site",
    "make_targets",
    "max_slant_range_m",
    "network_figure",
    "outcome_from_file",
    "outcome_from_plan",
    "plan_figure",
    "plan_figures",
    "plan_site",
    "point_error",
    "read_dxf_site",
    "read_geojson_site",
    "read_plan_stations",
    "render_report",
    "replan",
    "resolve",
    "resolve_range_limit",
    "run_network",
    "sigma_instr_m",
    "sigma_meas_m",
    "solve",
    "station_coverage",
    "tolerance_for_scale_m",
    "validate_site",
    "verify_stations",
    "write_dxf",
    "write_geojson",
    "write_plan",
    "write_report",
    "write_stations_csv",
]
