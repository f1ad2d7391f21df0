"""The parts of a setting: :class:`Setting`, the fixed choices, and how a derived limit follows its setting."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

#: the fixed choices (each equal to the library's own constant: tests/cli/test_cli_start.py)
METHODS = ("closed-form", "greedy", "milp")
OBJECTIVES = ("stations", "field-time")
BACKENDS = ("cpsat", "scip", "highs", "cbc", "pulp-cbc", "pyscipopt")
PRECISION_MODES = ("single", "combined")
FORMATS = ("orlib", "mps", "json")
EXPORTS = ("dxf", "geojson", "csv")
SIDES = ("inside", "outside", "both")
INCIDENCE_MODELS = ("none", "table", "soudarissanane")
SURFACES = ("walls", "floors", "ceilings")
#: the model variants of the ``variant`` key: each a switch of the MILP or the pool, by its field
VARIANTS: dict[str, tuple[str, bool]] = {
    "layer-cuts": ("milp.layer_cuts", True),
    "tree-bound": ("milp.tree_bound", True),
    "no-ring-bound": ("milp.ring_bound", False),
    "no-regions": ("plan.regions", False),
    "no-pricing": ("plan.pricing", False),
}

#: ``--tiles M``: each tile's MILP work, each Lagrangian part's work and each window's work as shares of the
#: tile budget (420 s: 30, 10 and 3 deterministic seconds)
TILE_SPLIT = {"tiling.tile_time_limit_s": 1 / 14, "tiling.lagrange_work_s": 1 / 42, "windows.work_s": 1 / 140}
#: the single MILP's local search: swaps per incumbent size, per move per piece of the tiled search (10 -> 500)
SEARCH_MOVES_PER_PIECE = 50

SURVEY = "survey"  # a flag of planner plan; the other sections are tuning keys
SOLVER = "the solver"
RULES = "registration rule, accuracy model"
CHECKS = "network check and field sheet"
TILES = "tiles and Dask (--tiles, --workers, --scheduler)"
INPUTS = "input formats (table CSV closure, DXF, IFC)"

Convert = Callable[[Any], Any] | None


@dataclass(frozen=True, kw_only=True)
class Setting:
    """One setting. ``kind``: ``float``, ``int``, ``text``, ``switch`` (true/false), ``items`` (repeatable
    ``NAME=VALUE``), ``list`` (comma-separated ``choices``), ``memory`` (a size such as 1.5GiB, bytes inside),
    ``tiles`` (a size in m, auto or off); a number is checked against ``above``, ``at_least``, ``at_most``.
    ``to``: the option fields it sets, each with how its value becomes the field's (None: as it is)."""

    key: str
    help: str
    default: Any = None
    kind: str = "text"
    choices: tuple[str, ...] | None = None
    above: float | None = None
    at_least: float | None = None
    at_most: float | None = None
    metavar: str | None = None
    section: str = SURVEY
    to: Mapping[str, Convert] = field(default_factory=dict)
    stop: bool = False
    plan: bool = True  # a setting of planner plan (else of the other subcommands only)

    @property
    def dest(self) -> str:
        """The attribute of the parsed namespace that holds the value."""
        return self.key.replace("-", "_")

    @property
    def initial(self) -> Any:
        """The value when nothing sets it."""
        return [] if self.kind == "items" else (False if self.kind == "switch" else self.default)


def _s(section: str, *settings: Setting) -> tuple[Setting, ...]:
    return tuple(Setting(**{**s.__dict__, "section": section}) for s in settings)


def _variant(name: str, on: bool) -> Callable[[str], bool]:
    """The field of the ``variant`` name: ``on`` where the list names it."""
    return lambda text: (name in text.split(",")) == on


def _share(fraction: float) -> Callable[[float], float]:
    """A limit derived from its setting (the tile budget, the MILP's work limit): ``fraction`` of it."""
    return lambda budget: budget * fraction


INT0: dict[str, Any] = {"kind": "int", "at_least": 0, "metavar": "N"}
