"""The plan a re-plan starts from (:func:`plan_source`): its plan.json, the site it names (read with the parameters
it records), its stations and the problem it was made under (the plan's sight, registration, target spacing and
pool options), and the edits checked against it (:func:`edits_of`)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from planner.core.errors import UsageError
from planner.core.fileio import read_json
from planner.io.edits import Edits, edits_from_dict, read_edits, with_plan_done
from planner.io.plan_file import site_for_plan
from planner.io.plan_json import check_plan_meta, read_plan_stations
from planner.plan.options import PlanOptions
from planner.plan.problem import Problem, resolve, with_recorded_registration
from planner.site.candidate import Candidate
from planner.site.model import Site


@dataclass(frozen=True, kw_only=True, eq=False)
class PlanSource:
    """A plan.json read back: ``path``, its data ``meta``, the ``site``, the ``problem`` it answers and its
    stations (``planned``, in the file's order)."""

    path: str
    meta: dict[str, Any]
    site: Site
    problem: Problem
    planned: tuple[Candidate, ...]

    @property
    def folder(self) -> Path:
        return Path(self.path).parent

    def options_of(self, site: Site) -> Problem:
        """The plan's problem for ``site`` (the edited site: the same options, sight modes and registration)."""
        if site is self.site:
            return self.problem
        return with_recorded_registration(resolve(site, self.problem.options), self.meta)


def recorded_options(meta: dict[str, Any]) -> PlanOptions:
    """The options a plan.json records: sight modes, target and verification spacing, the pool's grid, field
    samples and seed (what its pool and coverage were built under)."""
    p = meta.get("parameters") or {}
    combined = (p.get("milp") or {}).get("precision") == "combined" or p.get("precision_mode") == "combined"
    base = PlanOptions.checking(
        incidence_3d=p.get("incidence") == "3d", precision=bool(p.get("precision", True)), combined=combined
    )
    pool = replace(
        base.pool,
        grid_spacing_m=float(p.get("grid_spacing_m", base.pool.grid_m)),
        field_samples=int(p.get("field_samples", base.pool.field_samples)),
        seed=int(p.get("seed", base.pool.seed)),
    )
    return replace(
        base,
        target_spacing_m=float(p.get("target_spacing_m", base.target_spacing_m)),
        verify_spacing_m=float(p.get("verify_spacing_m", base.verify_spacing_m)),
        pool=pool,
    )


def plan_source(plan: str | Path, site_path: str | Path | None = None) -> PlanSource:
    """The plan.json at ``plan`` read back (``site_path``: the site file, default the one it records)."""
    name = str(plan)
    if Path(name).suffix.lower() != ".json":
        raise UsageError("expects a plan.json written by `planner plan --out DIR`", field="PLAN", value=name)
    meta = check_plan_meta(read_json(name), name)
    if "zones" in meta and "stations" not in meta:
        raise UsageError(f"{name} is a site file; planner replan expects a plan.json", field="PLAN", value=name)
    site = site_for_plan(meta, site_path, name)
    planned = tuple(read_plan_stations(name, site))
    problem = with_recorded_registration(resolve(site, recorded_options(meta)), meta)
    return PlanSource(path=name, meta=meta, site=site, problem=problem, planned=planned)


def edits_of(source: PlanSource, edits: str | Path | dict[str, Any] | Edits) -> Edits:
    """The edits (a file, its parsed data or :class:`Edits` already read) checked against the plan, with the
    stations the plan records as done in an earlier re-plan done too (:func:`planner.io.edits.with_plan_done`)."""
    zone_ids = tuple(z.id for z in source.site.zones)
    if isinstance(edits, Edits):
        checked = edits
    elif isinstance(edits, dict):
        checked = edits_from_dict(edits, "edits", source.meta, zone_ids)
    else:
        checked = read_edits(edits, source.meta, zone_ids)
    return with_plan_done(checked, source.meta, source.path)
