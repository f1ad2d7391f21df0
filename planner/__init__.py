"""Terrestrial laser scanner station planning.

The pipeline: site geometry -> closed-form candidate stations -> coverage sets
-> set cover (greedy, MILP) -> station network -> least-squares accuracy check.
This release holds the foundation: the site model and its readers, instrument
and accuracy models, and validation.

Examples
--------
>>> import planner
>>> site = planner.load_site("instances/polygon_a.json")          # doctest: +SKIP
>>> print(planner.validate_site(site).summary())                   # doctest: +SKIP
"""

from planner.accuracy import (
    ErrorBudget, IncidenceErrorTable, instrument_height_tolerance_m, max_slant_range_m, point_error,
    sigma_instr_m, sigma_meas_m, tolerance_for_scale_m,
)
from planner.errors import ClosureError, ExitCode, InfeasibleError, InputError, PlannerError, UsageError
from planner.instruments import Scanner, TotalStation, list_instruments, load_instrument
from planner.params import ClosureTolerance, Parameters, RangeLimit, resolve_range_limit
from planner.site import ScanSide, Site, Wall, Zone, load_site
from planner.validate import ValidationReport, validate_site

__version__ = "0.1.0"

__all__ = [
    "ClosureError", "ClosureTolerance", "ErrorBudget", "ExitCode", "IncidenceErrorTable", "InfeasibleError",
    "InputError", "Parameters", "PlannerError", "RangeLimit", "ScanSide", "Scanner", "Site", "TotalStation",
    "UsageError", "ValidationReport", "Wall", "Zone", "instrument_height_tolerance_m", "list_instruments",
    "load_instrument", "load_site", "max_slant_range_m", "point_error", "resolve_range_limit",
    "sigma_instr_m", "sigma_meas_m", "tolerance_for_scale_m", "validate_site",
]
