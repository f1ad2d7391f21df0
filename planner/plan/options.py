"""The options of a planning run (:class:`PlanOptions`) and the sight limits they give a validated site."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from planner.candidates.pool import PoolOptions
from planner.core.checks import SAMPLING_M, argument, count, flag, real
from planner.core.errors import UsageError
from planner.core.settings import DEFAULTS, OBJECTIVES, SURFACES, field_values, setting_of
from planner.coverage.sight import sight_of
from planner.coverage.visibility import SightLimits
from planner.plan.methods import METHODS
from planner.plan.strategy import StrategyOptions
from planner.site.validate import ValidationReport
from planner.solve.milp import MilpOptions


@dataclass(frozen=True, kw_only=True)
class PlanOptions:
    """Everything about a planning run that is not the site itself. The defaults are the ``planner plan``
    command's: the MILP with tripod discs, the registration rule at the site's overlap share, the strategy
    (one model or tiles) chosen for the site.

    ``target_spacing_m`` = 1 m: walls are cut into pieces of at most 1 m, and a
    piece counts as covered only when one station sees all of it, so a coarse
    piece costs coverage at its ends; 1 m keeps that loss below the verify
    sampling's resolution on the bundled sites while A (1,500 m of wall, both
    sides) stays at 3,000 targets and the coverage build under a few seconds.
    """

    method: str = DEFAULTS["plan.method"]
    target_spacing_m: float = DEFAULTS["plan.target_spacing_m"]
    pool: PoolOptions = field(default_factory=PoolOptions)
    incidence_3d: bool = DEFAULTS["plan.incidence_3d"]
    #: the precision check: a view covers a point only where its predicted error meets sigma_req
    precision: bool = DEFAULTS["plan.precision"]
    verify_spacing_m: float = DEFAULTS["plan.verify_spacing_m"]
    milp: MilpOptions = field(default_factory=MilpOptions)
    #: tripod discs round the stations; None (default): for the MILP, which always places them, else not
    tripod: bool | None = None
    recentre: bool = DEFAULTS["plan.recentre"]
    registration: str | None = DEFAULTS["plan.registration"]  # zone | site; None: site where zones share a frame
    regions: bool = DEFAULTS["plan.regions"]
    pricing: bool = DEFAULTS["plan.pricing"]
    #: a wall-clock cap on pricing, only where the user sets one (None: none; its rounds and work, counts, stop it)
    pricing_time_limit_s: float | None = None
    #: refinements of the connected cover over patches for a zone-side the ring walk leaves below the plan
    #: (:mod:`planner.bounds.plane_refine`; 0: the quick cover only). Each is one connected MILP
    plane_refine_steps: int = DEFAULTS["plan.plane_refine_steps"]
    #: None: a share of the available memory (planner.plan.memory_guard)
    memory_limit_bytes: int | None = DEFAULTS["plan.memory_limit_bytes"]
    strategy: StrategyOptions = field(default_factory=StrategyOptions)
    #: the surfaces planned: walls always, and floors and ceilings where asked
    #: (:mod:`planner.plan.surfaces`; ``("walls",)``: the wall plan alone, unchanged)
    surfaces: tuple[str, ...] = DEFAULTS["plan.surfaces"]
    #: the incidence limit of floors and ceilings in degrees (None: theta_max)
    theta_max_floor_deg: float | None = DEFAULTS["plan.theta_max_floor_deg"]
    #: the largest point spacing a view may give a wall piece to cover it, in metres
    #: (:mod:`planner.coverage.spacing`; None: no spacing condition, the plan unchanged)
    max_point_spacing_m: float | None = DEFAULTS["plan.max_point_spacing_m"]
    #: what the plan minimises: ``stations`` (the default, unchanged) or ``field-time``, the set-up and scan
    #: time with a scan setting chosen per station (:mod:`planner.plan.hours.field_time`)
    objective: str = DEFAULTS["plan.objective"]
    #: the length of a field session in seconds (the field sheet's ``--session``), in which the field-time
    #: trade-off counts each plan's sessions (None: not counted)
    session_s: float | None = None

    @property
    def hours(self) -> bool:
        """A run with point spacing or the field-time objective (scan settings per station)."""
        return self.max_point_spacing_m is not None or self.objective != "stations"

    @property
    def beyond_walls(self) -> bool:
        """Floors or ceilings are targets besides the walls."""
        return any(s != "walls" for s in self.surfaces)

    @classmethod
    def checking(
        cls,
        *,
        incidence_3d: bool = False,
        precision: bool = True,
        combined: bool = False,
        registration: str | None = None,
    ) -> PlanOptions:
        """The options that check stations already chosen (verify, network, a plan read back): the sight modes
        and registration scope only, as one model."""
        return cls(
            incidence_3d=incidence_3d,
            precision=precision,
            milp=MilpOptions(precision="combined" if combined and precision else "single"),
            registration=registration,
            strategy=StrategyOptions(single=True),
        )

    @property
    def combined(self) -> bool:
        """Views add information (``--precision combined``), for every method."""
        return self.precision and self.milp.precision == "combined"

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise UsageError(f"unknown method (known: {', '.join(METHODS)})", field="method", value=self.method)
        argument(self.pool, PoolOptions, "pool")
        argument(self.milp, MilpOptions, "milp")
        argument(self.strategy, StrategyOptions, "strategy")
        if self.tripod is None:  # the MILP places tripod discs; the greedy and the closed form only when asked
            object.__setattr__(self, "tripod", self.method == "milp")
        real(self.target_spacing_m, "target_spacing_m", above=0)
        real(self.verify_spacing_m, "verify_spacing_m", at_least=SAMPLING_M[0])  # finer than 1 mm: no survey resolution
        if self.pricing_time_limit_s is not None:
            real(self.pricing_time_limit_s, "pricing_time_limit_s", at_least=0)
        count(self.plane_refine_steps, "plane_refine_steps", 0)
        for name in ("incidence_3d", "precision", "tripod", "recentre", "regions", "pricing"):
            flag(getattr(self, name), name)
        if self.memory_limit_bytes is not None:
            count(self.memory_limit_bytes, "memory_limit_bytes", 1)
        _check_surfaces(self.surfaces)
        if self.theta_max_floor_deg is not None:
            real(self.theta_max_floor_deg, "theta_max_floor_deg", above=0)
            if self.theta_max_floor_deg > 90:
                raise UsageError("must be at most 90 deg", field="theta_max_floor_deg", value=self.theta_max_floor_deg)
        if self.max_point_spacing_m is not None:
            real(self.max_point_spacing_m, "max_point_spacing_m", above=0)
        if self.session_s is not None:
            real(self.session_s, "session_s", above=0)
        if self.objective not in OBJECTIVES:
            raise UsageError(
                f"unknown objective (known: {', '.join(OBJECTIVES)})", field="objective", value=self.objective
            )
        if self.hours and self.method != "milp":
            raise UsageError(
                "point spacing and the field-time objective need method='milp' (settings are chosen by the MILP)",
                field="method",
                value=self.method,
            )
        if self.hours and (self.milp.k != 1 or self.milp.precision == "combined"):
            raise UsageError(
                "point spacing and the field-time objective cover each piece once, each view on its own: "
                "plan them with k = 1 and single precision",
                field="k" if self.milp.k != 1 else "precision",
                value=self.milp.k if self.milp.k != 1 else self.milp.precision,
            )
        if self.hours and self.beyond_walls:
            raise UsageError(
                "point spacing and the field-time objective are checked on walls only for now: "
                "plan floors and ceilings without them",
                field="surfaces",
                value=",".join(self.surfaces),
            )
        if self.registration not in (None, "zone", "site"):
            raise UsageError("must be 'zone', 'site' or None", field="registration", value=self.registration)
        if self.milp.k != 1 and self.method != "milp":  # the greedy and the closed form cover each piece once
            raise UsageError(
                f"k > 1 needs method='milp' (method {self.method!r} covers each piece once)",
                field="k",
                value=self.milp.k,
            )
        if self.milp.precision == "combined" and not self.precision:
            raise UsageError(
                "combined precision needs the precision check (precision=True)", field="precision", value=self.precision
            )


__all__ = ["OBJECTIVES", "SURFACES", "PlanOptions", "options_from_settings", "plan_limits"]


def _check_surfaces(surfaces: object) -> None:
    """``surfaces``: a tuple of distinct names of :data:`SURFACES` that holds ``walls``."""
    if not isinstance(surfaces, tuple) or not all(isinstance(s, str) for s in surfaces):
        raise UsageError("must be a tuple of surface names", field="surfaces", value=surfaces)
    unknown = [s for s in surfaces if s not in SURFACES]
    if unknown:
        raise UsageError(
            f"unknown surface {unknown[0]!r} (known: {', '.join(SURFACES)})", field="surfaces", value=",".join(surfaces)
        )
    if "walls" not in surfaces:
        raise UsageError(
            "must include walls: walls are always targets (e.g. walls,floors)",
            field="surfaces",
            value=",".join(surfaces),
        )
    if len(set(surfaces)) != len(surfaces):
        raise UsageError("names a surface twice", field="surfaces", value=",".join(surfaces))


def plan_limits(validation: ValidationReport, options: PlanOptions) -> SightLimits:
    """The sight limits of a run: :func:`sight_limits` with the options' incidence and precision modes."""
    modes = {"incidence_3d": options.incidence_3d, "precision": options.precision, "combined": options.combined}
    return sight_of(validation.site, validation=validation, **modes)[1].limits


def options_from_settings(values: Mapping[str, Any], *, session_s: float | None = None) -> PlanOptions:
    """The options of a run from setting values by key (:data:`planner.core.settings.SETTINGS`; a missing one:
    its default): each value goes to the fields its setting names, part by part. ``session_s``: the field
    session in seconds. A value the options refuse is a :class:`UsageError` whose field is the setting's key."""
    from planner.coverage.overlap import SiteShare
    from planner.plan.strategy import StrategyOptions, TileOptions
    from planner.solve.milp import MilpOptions
    from planner.solve.windows import WindowOptions

    parts: dict[str, dict[str, Any]] = {}
    for path, value in field_values(values).items():
        part, name = path.split(".")
        parts.setdefault(part, {})[name] = value
    try:
        tiling = parts.pop("tiling")
        tile_m = tiling.pop("tile_m")
        if tile_m not in ("auto", "off") and parts["plan"]["method"] != "milp":
            raise UsageError("tiles plan with the MILP", field="method", value=parts["plan"]["method"])
        windows = WindowOptions(**parts.pop("windows"))
        tiles = None if tile_m in ("auto", "off") else TileOptions(tile_m=tile_m, windows=windows, **tiling)
        rule = None if values.get("no-overlap") else SiteShare(**parts.pop("rule"))
        return PlanOptions(
            pool=PoolOptions(**parts.pop("pool")),
            milp=MilpOptions(overlap=rule, **parts.pop("milp")),
            strategy=StrategyOptions(tiling=tiles, **parts.pop("strategy")),
            session_s=session_s,
            **parts.pop("plan"),
        )
    except UsageError as err:  # named by the setting that gave the field
        s = setting_of(err.field)
        raise UsageError(err.message, field=s.key if s else err.field, value=err.value) from None
