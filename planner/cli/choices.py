"""The fixed choices the ``planner`` command offers, kept here so that parsing the command line
(and ``--help``) imports no numerical stack. tests/cli/test_cli_start.py checks that each tuple equals
the library's own constant."""

from __future__ import annotations

#: planner.plan.METHODS
METHODS = ("closed-form", "greedy", "milp")
#: planner.plan.options.OBJECTIVES
OBJECTIVES = ("stations", "field-time")
#: planner.solve.backends.BACKENDS
BACKENDS = ("cpsat", "scip", "highs", "cbc", "pulp-cbc", "pyscipopt")
#: planner.solve.milp.CONNECTIVITY
CONNECTIVITY = ("auto", "bc", "flow", "loop")
#: planner.solve.milp.PRECISION_MODES
PRECISION_MODES = ("single", "combined")
#: planner.io.export.FORMATS
FORMATS = ("orlib", "mps", "json")
#: planner.io.EXPORTS
EXPORTS = ("dxf", "geojson", "csv")
#: the values of planner.site.model.ScanSide
SIDES = ("inside", "outside", "both")
#: planner.instrument.accuracy.INCIDENCE_MODELS
INCIDENCE_MODELS = ("none", "table", "soudarissanane")
