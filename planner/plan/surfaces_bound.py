"""Floors and ceilings over the plane: the candidates their coverage regions give, and the plan's bound over every
position for walls and surfaces together.

Two entries for the run (:mod:`planner.plan.run`): :func:`surface_region_candidates` (beside the floor grid, when
the pool is formed) and :func:`with_surfaces_plane` (after the method, on the MILP's result). The geometry is in
:mod:`planner.candidates.surface_regions`, the bound in :mod:`planner.bounds.surfaces_plane`.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

from planner.bounds.surfaces_plane import SurfacePlaneBound, surfaces_plane_bound
from planner.candidates.surface_regions import arrangement_candidates
from planner.coverage.regions import FrameSpace, regions_apply
from planner.solve.result import SolveResult, Status

if TYPE_CHECKING:
    from planner.coverage.targets import Targets
    from planner.plan.methods import MethodInput, MethodOutput
    from planner.plan.problem import Problem
    from planner.plan.surfaces import SurfaceCover, SurfaceSetup
    from planner.site.candidate import Candidate

#: what the bound over walls and surfaces assumes (plan.json ``certificate.assumes``, the summary)
ASSUMES = (
    "walls cut into pieces and floors (ceilings) into patches of the target spacing, each covered only when one "
    "station sees all of it; coverage regions exact to within the tolerance"
)


def scope_of(setup: SurfaceSetup, k: int = 1) -> str:
    """The bound's scope as printed: ``plane, walls and floors``, ``plane, walls, floors and ceilings`` (the kinds
    asked that the site has), with ``, k = K`` for k views."""
    names = ["walls", *(kind + "s" for kind in setup.kinds if kind not in setup.absent)]
    words = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
    return f"plane, {words}" + (f", k = {k}" if k > 1 else "")


def surface_region_candidates(
    problem: Problem,
    targets: Targets,
    spaces: dict[str, FrameSpace] | None = None,
    region_cache: dict[int, Any] | None = None,
) -> list[Candidate]:
    """Candidates in the undominated faces of each inside zone's arrangement of patch and wall regions
    (:func:`planner.candidates.surface_regions.arrangement_candidates`); none without surfaces or coverage regions.
    ``spaces``/``region_cache``: the walls' frame spaces and regions drawn in this run (filled in here)."""
    setup = problem.surfaces
    if setup is None or not (problem.options.regions and regions_apply(problem.limits)):
        return []
    site = problem.site
    spaces = {} if spaces is None else spaces
    region_cache = {} if region_cache is None else region_cache
    found, _ = arrangement_candidates(site, setup.patches, setup.limits, targets, problem.limits, spaces, region_cache)
    return found


def _why_not(problem: Problem, out: MethodOutput) -> str | None:
    """Why the bound over walls and surfaces is not formed for this run (None: it is)."""
    if not problem.options.regions:
        return "coverage regions off (variant no-regions)"
    if not regions_apply(problem.limits):
        return "coverage regions do not model the incidence-dependent view error with 3-D incidence"
    if out.result.objective is None or not out.result.selected:
        return "no plan to bound"
    return None


def with_surfaces_plane(
    problem: Problem, run: MethodInput, out: MethodOutput, cover: SurfaceCover | None
) -> MethodOutput:
    """The MILP's output with the plane bound over walls and surfaces (:func:`with_surfaces_bound`) and its log line;
    ``out`` as it is for walls alone or another method."""
    setup = problem.surfaces
    if (
        cover is None
        or setup is None
        or out.result.method != "milp"
        or out.problem.candidates != run.problem.candidates
    ):
        return out  # (a method that changed the pool is refused by the run itself)
    k = problem.options.milp.k
    scope = scope_of(setup, k)
    why = _why_not(problem, out)
    if why is not None:
        report = SurfacePlaneBound(scope, note=why)
    else:
        report = surfaces_plane_bound(
            problem.site,
            out.problem,
            setup.patches,
            cover.seen,
            cover.matrix,
            setup.limits,
            scope=scope,
            spaces=run.spaces,
            region_cache=run.region_cache,
            outer=run.outer,
        )
    unseen = int(cover.unseen.size)
    return replace(out, result=with_surfaces_bound(out.result, report, k, unseen), log=(*out.log, report.summary()))


def with_surfaces_bound(result: SolveResult, report: SurfacePlaneBound, k: int = 1, unseen: int = 0) -> SolveResult:
    """``result`` with ``info['surfaces_plane']`` (the report), and where the bound was formed ``plane_bound`` (ceil of
    k times Farley's bound), ``plane_bound_scope``, the certificate and ``bound_scope`` (``plane`` when the plan
    meets the bound: ``bound`` becomes it); else ``plane_off`` says why. ``unseen``: patches no candidate sees (left
    out of the plan and of the bound)."""
    info = dict(result.info)
    info["surfaces_plane"] = report.to_dict()
    plane = report.bound(k)
    if plane is None:
        info["plane_off"] = (
            f"surfaces beyond walls: the bound over {report.scope.removeprefix('plane, ')}: {report.note}"
        )
        return replace(result, info=info)
    info.pop("plane_off", None)
    left = f"; {unseen} patch(es) seen by no candidate left out" if unseen else ""
    info["pool_bound"] = result.bound
    info["plane_bound"] = plane
    info["plane_bound_scope"] = report.scope
    info["certificate"] = {
        "assumes": ASSUMES + left,
        "tolerance_m": report.tolerance_m,
        "scope": report.scope,
        "k": k,
        "plane_bound_from": (f"{k} x " if k > 1 else "")
        + "Farley's bound on the cover LP's duals over wall pieces and patches, the heaviest position weighed over "
        "the closed arrangement of both kinds of outer coverage regions grown by the tolerance (a plain cover; "
        "registration not used)",
    }
    proven = result.objective is not None and result.objective <= plane + 1e-9
    info["bound_scope"] = "plane" if proven else "pool"
    if proven:
        return replace(result, status=Status.OPTIMAL, bound=float(plane), info=info)
    return replace(result, info=info)
