"""Terrestrial laser scanner station planning.

The pipeline, and the public API for each step:

1. site: :func:`load_site` (JSON instance, table CSV, DXF, GeoJSON), :class:`Site`, :class:`Parameters`,
   :func:`validate_site`;
2. candidates: :func:`candidate_pool` (the dissertation's closed-form stations, field samples, grid);
3. coverage: :func:`build_problem` (candidates x wall pieces, both sparse views);
4. solving: :func:`greedy_cover`, :func:`solve` (MILP on CP-SAT, SCIP, HiGHS, CBC, PuLP) or all of it
   at once with :func:`plan_site` -> :class:`Plan` (verified);
5. checking: :func:`verify_stations`, :func:`run_network` (least-squares accuracy);
6. showing: :func:`outcome_from_plan` -> :class:`Outcome`, :func:`plan_figures`, :func:`network_figure`,
   :func:`comparison_figure`, :func:`write_report`, :func:`write_dxf`, :func:`write_geojson`,
   :func:`write_stations_csv`.

Results are frozen dataclasses with ``summary()`` and a notebook ``_repr_html_``. Library code logs
(``logging.getLogger("planner")``) and never prints.

Examples
--------
>>> import planner
>>> site = planner.load_site("instances/polygon_b.json")                  # doctest: +SKIP
>>> plan = planner.plan_site(site, planner.PlanOptions(method="milp"))   # doctest: +SKIP
>>> print(plan.summary())                                                # doctest: +SKIP
>>> planner.write_report(planner.outcome_from_plan(plan), "out/")         # doctest: +SKIP
"""

import logging

from planner.accuracy import (
    ErrorBudget, IncidenceErrorTable, instrument_height_tolerance_m, max_slant_range_m, point_error,
    sigma_instr_m, sigma_meas_m, tolerance_for_scale_m,
)
from planner.errors import ClosureError, ExitCode, InfeasibleError, InputError, PlannerError, UsageError
from planner.instruments import Scanner, TotalStation, list_instruments, load_instrument
from planner.params import ClosureTolerance, Parameters, RangeLimit, resolve_range_limit
from planner.site import ControlPoint, NoGoArea, Obstacle, ScanSide, Site, Wall, Zone, load_site
from planner.validate import ValidationReport, validate_site

__version__ = "0.2.0"

from planner.candidates.model import Candidate, CandidateKind  # noqa: E402
from planner.candidates.pool import PoolOptions, candidate_pool  # noqa: E402
from planner.coverage.matrix import CoverageProblem, build_coverage  # noqa: E402
from planner.coverage.overlap import OverlapRule  # noqa: E402
from planner.coverage.stations import StationCoverage, station_coverage  # noqa: E402
from planner.coverage.targets import make_targets  # noqa: E402
from planner.exchange import (  # noqa: E402
    DxfOptions, read_dxf_site, read_geojson_site, write_dxf, write_geojson, write_stations_csv,
)
from planner.figures import comparison_figure, network_figure, plan_figure, plan_figures  # noqa: E402
from planner.network.check import NetworkReport, run_network  # noqa: E402
from planner.outcome import Outcome, outcome_from_file, outcome_from_plan  # noqa: E402
from planner.plan import Plan, PlanOptions, build_problem, plan_site  # noqa: E402
from planner.plan_io import read_plan_stations, write_plan  # noqa: E402
from planner.report import compare_methods, render_report, write_report  # noqa: E402
from planner.solve.greedy import greedy_cover  # noqa: E402
from planner.solve.instance import CoverInstance, cover_instance  # noqa: E402
from planner.solve.milp import MilpOptions, solve  # noqa: E402
from planner.solve.result import SolveResult, Status  # noqa: E402
from planner.verify import VerifyReport, verify_stations  # noqa: E402

logging.getLogger("planner").addHandler(logging.NullHandler())

__all__ = [
    "Candidate", "CandidateKind", "ClosureError", "ClosureTolerance", "ControlPoint", "CoverInstance",
    "CoverageProblem", "DxfOptions", "ErrorBudget", "ExitCode", "IncidenceErrorTable", "InfeasibleError",
    "InputError", "MilpOptions", "NetworkReport", "NoGoArea", "Obstacle", "Outcome", "OverlapRule", "Parameters",
    "Plan", "PlanOptions", "PlannerError", "PoolOptions", "RangeLimit", "ScanSide", "Scanner", "Site",
    "SolveResult", "StationCoverage", "Status", "TotalStation", "UsageError", "ValidationReport", "VerifyReport",
    "Wall", "Zone", "build_coverage", "build_problem", "candidate_pool", "compare_methods", "comparison_figure",
    "cover_instance", "greedy_cover", "instrument_height_tolerance_m", "list_instruments", "load_instrument",
    "load_site", "make_targets", "max_slant_range_m", "network_figure", "outcome_from_file", "outcome_from_plan",
    "plan_figure", "plan_figures", "plan_site", "point_error", "read_dxf_site", "read_geojson_site",
    "read_plan_stations", "render_report", "resolve_range_limit", "run_network", "sigma_instr_m", "sigma_meas_m",
    "solve", "station_coverage", "tolerance_for_scale_m", "validate_site", "verify_stations", "write_dxf",
    "write_geojson", "write_plan", "write_report", "write_stations_csv",
]
