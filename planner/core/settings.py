"""Every setting of a planning run, defined once: its name, default, values, unit, help, whether a surveyor sets it
(a flag of ``planner plan``) or a benchmark tunes it (a key of ``--set KEY=VALUE`` and ``--config FILE``), and
the fields of the option dataclasses it sets.

Import-light on purpose (the standard library only): the command line builds its flags, keys, ``--help-all`` and
the shipped profile (``planner/cli/profiles/default.toml``) from :data:`SETTINGS` without loading a solver, and
the option dataclasses (:class:`planner.plan.PlanOptions`, :class:`planner.solve.milp.MilpOptions`,
:class:`planner.candidates.pool.PoolOptions`, the tile strategy's) take their defaults from :data:`DEFAULTS`,
the fields :func:`field_values` gives when no setting is set. :func:`planner.plan.options.options_from_settings`
builds the options from setting values by walking the same paths, so nothing is copied by hand.

A field path is ``PART.FIELD`` with PART one of ``plan`` (:class:`PlanOptions`), ``pool``, ``milp``, ``rule``
(the registration rule), ``strategy``, ``tiling`` (``--tiles M``) and ``windows`` (its window re-solves).

The stopping rules are four settings (``stop=True``): the MILP's wall-clock cap ``time-limit`` and its work in
deterministic seconds ``work-limit``, the tiles' budget ``tile-budget`` and the local search's
``moves-per-piece``; the other limits derive from them (:data:`TILE_SPLIT`, :data:`SEARCH_MOVES_PER_PIECE`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from planner.core.checks import SAMPLING_M

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
    """A limit derived from the tile budget: ``fraction`` of it."""
    return lambda budget: budget * fraction


_INT0 = {"kind": "int", "at_least": 0, "metavar": "N"}

#: every setting, in the order ``--help-all`` and the shipped profile list them
SETTINGS: dict[str, Setting] = {
    s.key: s
    for s in (
        Setting(
            key="method",
            choices=METHODS,
            default="milp",
            help="closed-form (the dissertation), greedy (Chvatal) or milp (optimal; default)",
            to={"plan.method": None},
        ),
        Setting(
            key="time-limit",
            kind="float",
            above=0,
            metavar="S",
            stop=True,
            help="a wall-clock cap on the MILP in s (default none: it stops on its work-limit, the same plan under "
            "any load; a capped plan says so)",
            to={"milp.time_limit_s": None},
        ),
        Setting(
            key="k",
            kind="int",
            at_least=1,
            default=1,
            help="each wall piece seen by at least k stations (default 1)",
            to={"milp.k": None},
        ),
        Setting(
            key="precision",
            choices=PRECISION_MODES,
            default="single",
            help="single: each view must meet sigma_req; combined: the views of a point add information (default "
            "single)",
            to={"milp.precision": None},
        ),
        Setting(
            key="surfaces",
            kind="list",
            choices=SURFACES,
            default="walls",
            metavar="LIST",
            help="walls and, besides them, floors and ceilings, e.g. walls,floors,ceilings (default walls; "
            "docs/surfaces.md)",
            to={"plan.surfaces": lambda v: tuple(v.split(","))},
        ),
        Setting(
            key="max-point-spacing",
            kind="float",
            above=0,
            metavar="M",
            help="the largest point spacing on the walls in m, e.g. 0.006: a view covers a piece only at a scan "
            "setting that gives it that (default none; docs/field-time.md)",
            to={"plan.max_point_spacing_m": None},
        ),
        Setting(
            key="objective",
            choices=OBJECTIVES,
            default="stations",
            help="stations: the fewest stations (default); field-time: the least set-up + scan time, a scan "
            "setting chosen per station, compared with the plans at one setting",
            to={"plan.objective": None},
        ),
        Setting(key="no-overlap", kind="switch", help="MILP and greedy without the registration-overlap constraint"),
        Setting(
            key="registration",
            choices=("zone", "site"),
            help="one registration bundle per zone-side, or per accessible area of the site (default: site where "
            "the zones share one frame or openings are given; zone for one zone or zones in their own frames)",
            to={"plan.registration": None},
        ),
        Setting(
            key="recentre",
            kind="switch",
            help="move each station to the centre of its tripod disc",
            to={"plan.recentre": None},
        ),
        Setting(
            key="memory-limit",
            kind="memory",
            metavar="SIZE",
            help="refuse a problem whose estimated memory passes SIZE, e.g. 4G (default: half the available memory)",
            to={"plan.memory_limit_bytes": None},
        ),
        Setting(
            key="target-spacing",
            kind="float",
            above=0,
            default=1.0,
            metavar="M",
            help="wall piece length (default 1 m)",
            to={"plan.target_spacing_m": None},
        ),
        Setting(
            key="grid-spacing",
            kind="float",
            above=0,
            metavar="M",
            help="candidate grid spacing (default 10 m; 4 m where the automatic strategy (--tiles auto) plans the "
            "site by tiles and it has at most 10,000 wall pieces: docs/large-sites.md)",
            to={"pool.grid_spacing_m": None},
        ),
        Setting(
            key="tiles",
            kind="tiles",
            default="auto",
            metavar="M|auto|off",
            help="milp: plan by square tiles of M m (margins of S_max), stitched into one registered plan; auto "
            "(default): tiles for a large site, sized to the site and the tile-budget key (docs/large-sites.md); "
            "off: one model",
            to={"strategy.single": lambda v: v == "off", "tiling.tile_m": lambda v: v},
        ),
        Setting(
            key="workers",
            **_INT0,
            default=0,
            help="--tiles: run tiles on an embedded Dask LocalCluster of N processes (default 0: in this process)",
            to={"strategy.workers": None},
        ),
        Setting(
            key="scheduler",
            metavar="ADDRESS",
            help="--tiles: run tiles on the Dask cluster at ADDRESS (tcp://HOST:PORT)",
            to={"strategy.scheduler": None},
        ),
        *_s(
            SOLVER,
            Setting(
                key="backend",
                choices=BACKENDS,
                default="cpsat",
                help="MILP backend (default cpsat)",
                to={"milp.backend": None},
            ),  # fmt: skip
            Setting(
                key="work-limit",
                kind="float",
                above=0,
                default=25.0,
                metavar="S",
                stop=True,
                help="milp, cpsat: stop on S deterministic seconds of CP-SAT work, a count (default 25; with one "
                "thread the same plan under any load); geometric pricing stops on its own rounds",
                to={"milp.work_limit": None},
            ),
            Setting(
                key="moves-per-piece",
                kind="float",
                at_least=0,
                default=10.0,
                metavar="K",
                stop=True,
                help="local search: the tiled plan's moves per wall piece of the site, and the single MILP's swaps "
                f"per incumbent size, {SEARCH_MOVES_PER_PIECE} K (default 10: 500 swaps; 0: off)",
                to={
                    "tiling.moves_per_piece": None,
                    "milp.local_search_moves": lambda v: round(SEARCH_MOVES_PER_PIECE * v),
                },
            ),
            Setting(
                key="variant",
                kind="list",
                choices=tuple(VARIANTS),
                default="",
                metavar="LIST",
                help="model variants for studies, comma-separated: layer-cuts (distance-layer cuts), tree-bound "
                "(Hunter's covering bound), no-ring-bound, no-regions (no whole-zone-side candidates), no-pricing "
                "(the bound over the pool only) (default none)",
                to={path: _variant(name, on) for name, (path, on) in VARIANTS.items()},
            ),
            Setting(
                key="plane-refine-steps",
                **_INT0,
                default=0,
                help="milp, zone registration: refine the connected plane bound up to N times where the ring walk "
                "stays below the plan (each a connected MILP over patches of the plane, split where its optimum "
                "sits); default 0, off",
                to={"plan.plane_refine_steps": None},
            ),
            Setting(
                key="seed",
                **_INT0,
                default=0,
                help="random seed: the movement-field sampling, the local search, the Monte Carlo runs (default 0)",
                to={"pool.seed": None, "milp.seed": None, "windows.seed": None},
            ),
        ),
        *_s(
            RULES,
            Setting(
                key="min-shared",
                kind="float",
                at_least=0,
                default=0.0,
                metavar="M",
                help="registration: shared wall at least M m",
                to={"rule.min_shared_m": None},
            ),
            Setting(
                key="max-link",
                kind="float",
                above=0,
                metavar="M",
                help="registration: stations at most M m apart",
                to={"rule.max_link_m": None},
            ),
            Setting(
                key="incidence",
                choices=("horizontal", "3d"),
                default="horizontal",
                help="incidence angle in plan (as the dissertation) or 3-D to the top of the wall (default horizontal)",
                to={"plan.incidence_3d": lambda v: v == "3d"},
            ),
            Setting(
                key="no-precision",
                kind="switch",
                help="do not require the predicted point error <= sigma_req",
                to={"plan.precision": lambda v: not v},
            ),
            Setting(
                key="verify-spacing",
                plan=False,
                kind="float",
                at_least=SAMPLING_M[0],
                at_most=SAMPLING_M[1],
                default=0.1,
                metavar="M",
                help="sampling along the walls (default 0.1 m)",
                to={"plan.verify_spacing_m": None},
            ),
            Setting(
                key="theta-max-floor",
                kind="float",
                above=0,
                at_most=90,
                metavar="DEG",
                help="incidence limit of floors and ceilings in deg (default theta_max)",
                to={"plan.theta_max_floor_deg": None},
            ),
        ),
        *_s(
            CHECKS,
            Setting(
                key="monte-carlo",
                plan=False,
                **_INT0,
                default=0,
                help="also simulate N adjustments (seeded; N >= 100)",
            ),
            Setting(
                key="traverse",
                metavar="FILE",
                help="the planned control traverse (JSON: points, legs), the only total-station observations; "
                "'none' for no traverse (default: a proposed one, labelled so)",
            ),
            Setting(
                key="ts-everywhere",
                plan=False,
                kind="switch",
                help="the earlier design: a total station on every station sight line (no traverse)",
            ),
            Setting(
                key="field-mode",
                choices=("shortest", "registration"),
                default="shortest",
                help="visiting order: shortest, or registration (each station after the first overlaps one scanned "
                "before it) (default shortest)",
            ),
            Setting(
                key="field-start",
                plan=False,
                metavar="ID|X,Y",
                help="start at this station or point (default: the station nearest the first door or control point)",
            ),
            Setting(
                key="field-session",
                metavar="DURATION",
                help="split the field time into sessions, e.g. 4h, 90min (the field-time objective counts them)",
            ),
            Setting(
                key="strong-overlap",
                plan=False,
                kind="float",
                at_least=0,
                at_most=1,
                default=0.5,
                metavar="F",
                help="a registration link sharing less than F of the smaller scan's wall gets targets (default 0.5)",
                to={"field.strong_overlap": None},
            ),
            Setting(
                key="solution-limit",
                plan=False,
                kind="int",
                at_least=1,
                default=1000,
                metavar="N",
                help="routing: guided local search stops after N solutions (deterministic; default 1000)",
                to={"field.solution_limit": None},
            ),
            Setting(
                key="field-strict-walls",
                kind="switch",
                help="refuse a plan whose stations no walk joins (rooms without an opening in the model; exit 4) "
                "instead of a straight leg through the walls",
            ),
        ),
        *_s(
            TILES,
            Setting(
                key="tile-budget",
                kind="float",
                above=0,
                default=420.0,
                metavar="S",
                stop=True,
                help="the tiles' work in deterministic seconds: --tiles auto splits it by the tile count; --tiles M "
                "gives each tile's MILP 1/14 of it, each Lagrangian part 1/42, each window 1/140 (default 420 s: "
                "30, 10, 3)",
                to={"strategy.budget_s": None, **{p: _share(f) for p, f in TILE_SPLIT.items()}},
            ),
            Setting(
                key="worker-memory",
                kind="memory",
                default=int(1.5 * 2**30),
                metavar="SIZE",
                help="--tiles --workers: memory limit of each worker (default 1.5GiB)",
                to={"strategy.worker_memory": None},
            ),
        ),
        *_s(
            INPUTS,
            Setting(key="angular-tolerance", kind="float", metavar="DEG", help="closure tolerance of table CSV zones"),
            Setting(key="min-relative-precision", kind="float", metavar="N", help="closure 1:N of table CSV zones"),
            Setting(
                key="layer-height",
                kind="items",
                metavar="LAYER=M",
                help="DXF: wall height of polylines on LAYER that carry none (repeatable, once per layer)",
            ),
            Setting(
                key="dxf-side",
                plan=False,
                choices=SIDES,
                default="inside",
                help="DXF: scan side of zones whose layer and XDATA do not say (default inside)",
            ),
            Setting(key="exterior", kind="switch", help="IFC: also scan the storey's outer outline from outside"),
            Setting(
                key="tolerance",
                plan=False,
                kind="float",
                above=0,
                default=0.005,
                metavar="M",
                help="equal side lengths within M m (default 0.005)",
                to={"assemble.tolerance_m": None},
            ),
            Setting(
                key="wall-thickness",
                plan=False,
                kind="float",
                at_least=0,
                default=0.0,
                metavar="M",
                help="offset between the two faces (default 0)",
                to={"assemble.wall_thickness_m": None},
            ),
            Setting(
                key="ifc-windows",
                kind="switch",
                help="IFC: record windows as openings too (default: a window is wall surface)",
            ),
        ),
    )
}

#: the settings ``planner plan`` takes as flags (what a surveyor sets) and as tuning keys, by key
PLAN_FLAGS = tuple(k for k, s in SETTINGS.items() if s.section == SURVEY)
#: the plan's tuning keys: the other subcommands take some of them as flags
PLAN_KEYS = tuple(k for k, s in SETTINGS.items() if s.section != SURVEY and s.plan)


def field_values(values: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The option fields, by path, that the setting ``values`` (by key; a missing one: its default) give."""
    out: dict[str, Any] = {}
    for s in SETTINGS.values():
        value = (values or {}).get(s.key, s.initial)
        for path, convert in s.to.items():
            out[path] = value if convert is None else convert(value)
    return out


#: the option fields when nothing is set: the defaults of the option dataclasses
DEFAULTS: dict[str, Any] = field_values()


def setting_of(path: str | None) -> Setting | None:
    """The setting that gives the field ``path`` (``PART.FIELD`` or a bare field name), else None."""
    for s in SETTINGS.values():
        if any(p == path or p.endswith(f".{path}") for p in s.to):
            return s
    return None
