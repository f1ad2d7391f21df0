"""The ``planner`` commands: one function per subcommand; parses, calls the library, prints (``network`` and
``chain`` in :mod:`planner.cli.network_command`; the entry point in :mod:`planner.cli.main`)."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from planner.cli.hours import session_of, verify_spacing_of
from planner.cli.inputs import guard_memory, load_with_overrides, recorded_notes
from planner.cli.network_command import check_network_options, checking_problem, network_check, network_inputs
from planner.cli.report import parse_exports, write_exports
from planner.cli.tuning import field_flag, option_name
from planner.core.errors import ExitCode, InfeasibleError, UsageError
from planner.core.settings import SETTINGS
from planner.core.text import dumps

# Everything else loads inside the command that needs it, so that --help, --version and validate
# start without the solver, network, figure and report stacks (docs/startup.md).
if TYPE_CHECKING:
    from planner.plan import Plan, PlanOptions
    from planner.solve.result import SolveResult


def cmd_validate(args: argparse.Namespace) -> int:
    from planner.site.validate import validate_site

    report = validate_site(load_with_overrides(args))
    print(dumps(report.to_dict()).rstrip("\n") if args.json else report.summary())
    return ExitCode.OK


def plan_options(args: argparse.Namespace) -> PlanOptions:
    """The options of ``planner plan`` (and of ``export``): every setting the command line gives, walked into the
    option fields its schema names (:func:`planner.plan.options.options_from_settings`); the registration rule
    stays the site's share until the run is resolved."""
    _plan_rules(args)
    from planner.plan.options import options_from_settings

    values = {key: getattr(args, s.dest) for key, s in SETTINGS.items() if hasattr(args, s.dest)}
    try:
        return options_from_settings(values, session_s=session_of(args))
    except UsageError as err:
        raise UsageError(err.message, field=plan_flag(err.field), value=err.value) from None


def _plan_rules(args: argparse.Namespace) -> None:
    """The rules between ``planner plan``'s options, said in its flags before the library says them in its
    fields."""
    if getattr(args, "k", 1) != 1 and args.method != "milp":
        raise UsageError(f"{args.k} needs --method milp (the {args.method} method covers each piece once)", field="--k")
    if getattr(args, "precision", "single") == "combined" and args.no_precision:
        off = option_name("plan", "no-precision")
        raise UsageError(f"combined needs the precision check, which {off} turns off", field="--precision")


def plan_flag(field: str | None) -> str | None:
    """The flag (or ``--set KEY``) of ``planner plan`` that sets a setting or an options field (the field where
    none does)."""
    return option_name("plan", field) if field in SETTINGS else field_flag("plan", field)


def cmd_plan(args: argparse.Namespace) -> int:
    formats = parse_exports(args.export)
    if formats and not args.out:
        raise UsageError("--export writes into the --out folder; give --out DIR", field="--export", value=args.export)
    _plan_rules(args)
    networked = args.network or args.report  # the report runs the network too
    if networked:
        check_network_options(args)
    # the site first (a bad one is refused before the network and field stacks load), then the network's files
    # and the sheet's option values, all before the planning; the outputs are staged (planner.cli.outputs)
    site = load_with_overrides(args)
    inputs = network_inputs(args) if networked else None
    field_options = None
    if args.field:
        from planner.cli.field import field_options as _field_options

        field_options = _field_options(args, "field-")
    from planner.plan.problem import resolve

    try:
        problem = resolve(site, plan_options(args))  # once per run: every stage takes it
    except UsageError as err:  # a strategy option refused: named as the user gave it
        raise UsageError(err.message, field=plan_flag(err.field), value=err.value) from None
    guard_memory(problem)  # before the solver stacks load, so that a refusal is quick
    from planner.engine import plan_site
    from planner.io.plan_json import write_plan

    options = problem.options
    plan = plan_site(problem)
    if not plan.stations and plan.result.status.value in ("infeasible", "no_solution"):
        print(plan.summary().splitlines()[0])
        raise InfeasibleError(f"{plan.result.method} found no plan: {_no_plan_reason(plan.result, options)}")
    print(plan.summary())
    if args.out:
        print(f"wrote {write_plan(plan, args.out)}")
        _write_replan_data(plan, args.out)
    network = None
    if inputs is not None:
        network = network_check(problem, list(plan.stations), args, inputs, args.network, plan.stations_cover)
    numbering = None  # each station's one number and label: the sheet's walking order, else plan order
    if field_options is not None:
        from planner.cli.field import write_field

        settings = plan.hours.settings if plan.hours is not None and field_options.setting is None else None
        numbering = write_field(problem, plan.stations, field_options, args.field, settings=settings).numbering
        if args.out:  # plan.json records the sheet's numbering (written before it: a refused sheet keeps the plan)
            write_plan(plan, args.out, numbering)
    if formats or args.report:  # the report stack loads only here (0.5-0.8 CPU-s a plan without it)
        from planner.plan.outcome import outcome_from_plan
        from planner.report import compare_methods, write_report
        from planner.report.site_map import numbered_outcome

        outcome = outcome_from_plan(plan, network, compare_methods(plan) if args.report else ())
        outcome = numbered_outcome(outcome, numbering)
        write_exports(outcome, formats, args.out, args.crs)
        if args.report:
            print(f"wrote {write_report(outcome, args.report, field=args.field)}")
    return ExitCode.OK


def _write_replan_data(plan: Plan, folder: str) -> None:
    """DIR/replan.npz beside plan.json: what ``planner replan`` re-plans from without building the pool again
    (:mod:`planner.io.replan_data`); a plan that kept no pool (tiles) gets none, and says so."""
    from planner.io.replan_data import FILE_NAME, make_replan_data, write_replan_data

    if plan.coverage is None:
        print(f"note: no {FILE_NAME} (this plan kept no single pool); planner replan will build the pool again")
        return
    data = make_replan_data(plan.problem, plan.coverage, plan.stations)
    print(f"wrote {write_replan_data(data, [z.id for z in plan.site.zones], folder)}")


def _no_plan_reason(result: SolveResult, options: PlanOptions) -> str:
    """Why a solver stopped without stations, in words."""
    info = result.info
    if "targets_seen_by_fewer_than_k" in info:
        return f"{info['count']} target(s) seen by fewer than k = {options.milp.k} candidates"
    if result.status.value == "no_solution":
        o = options.milp
        work = o.limits["work_limit"]
        stops = [f"work limit of {work:g} s of CP-SAT work (--set work-limit=S)"] if work else []
        stops += [f"wall-clock cap of {o.time_limit_s:g} s (raise --time-limit)"] if o.time_limit_s is not None else []
        return "no cover found within the " + (" or the ".join(stops) or f"{o.backend} solver's node limit")
    rules = ["every piece covered"] + ([f"k = {options.milp.k}"] if options.milp.k > 1 else [])
    rules += ["registration overlap connected"] if options.milp.rule is not None else []
    rules += ["combined precision"] if options.combined else []
    return f"the solver proved that no set of candidates meets {', '.join(rules)}"


def cmd_verify(args: argparse.Namespace) -> int:
    from planner.io.plan_json import read_plan_stations
    from planner.plan.verify import verify_stations

    problem = checking_problem(args)
    stations = read_plan_stations(args.plan, problem.site)
    surfaces = tuple(args.surfaces.split(","))
    setup = None
    if surfaces != ("walls",):  # floors and ceilings too: the same setup as planning takes
        from planner.plan.surfaces import surface_setup

        checked = replace(problem.options, surfaces=surfaces, theta_max_floor_deg=args.theta_max_floor)
        try:
            setup = surface_setup(problem.site, problem.validation, checked, problem.limits)
        except UsageError as err:
            raise UsageError(err.message, field=plan_flag(err.field), value=err.value) from None
    report = verify_stations(problem.sight, stations, args.spacing)
    print(f"plan {args.plan}: {len(stations)} stations")
    recorded_notes(args.plan, problem.site)
    print(report.summary())
    complete = report.complete
    if setup is not None:
        from planner.plan.verify_surfaces import verify_surfaces

        checked_surfaces = verify_surfaces(problem.site, setup, None, stations, args.spacing)
        print("\n".join(checked_surfaces.lines()))
        complete = complete and checked_surfaces.complete
    if args.max_point_spacing is not None:  # the spacing at each station's own setting
        spacing = verify_spacing_of(args, problem, stations)
        print("\n".join(spacing.lines()))
        complete = complete and spacing.complete
    return ExitCode.OK if complete else ExitCode.INFEASIBLE


def cmd_export(args: argparse.Namespace) -> int:
    site = load_with_overrides(args)
    from planner.plan.problem import resolve

    options = plan_options(args)
    resolved = resolve(site, options)
    guard_memory(resolved)
    from planner.io.export import export_problem
    from planner.plan import build_problem

    problem = build_problem(resolved)
    text = export_problem(problem, args.format, resolved.checked_rule)
    if args.out:
        Path(args.out).write_text(text)
        print(
            f"wrote {args.out}: {problem.shape[0]} candidates, {problem.shape[1]} targets, {problem.by_candidate.nnz:,} pairs"
        )
    else:
        sys.stdout.write(text)
    return ExitCode.OK


def cmd_instruments(args: argparse.Namespace) -> int:
    from planner.instrument.models import list_instruments, load_instrument

    for name in list_instruments():
        inst = load_instrument(name)
        print(f"{name:<22}{type(inst).__name__:<14}{inst.description}")
    return ExitCode.OK


def cmd_assemble(args: argparse.Namespace) -> int:
    """Place the table zones of an instance from their shared walls; print matches, residuals, unplaced zones."""
    from planner.core.fileio import read_json
    from planner.io import load_site
    from planner.io.assembly_io import assembled_instance
    from planner.site.assemble import assemble

    path = Path(args.site)
    site = load_site(path)
    report = assemble(site, tolerance_m=args.tolerance, wall_thickness_m=args.wall_thickness, anchor=args.anchor)
    print("\n".join(report.lines()))
    if args.out:
        out = Path(args.out)
        source = (
            read_json(path)
            if path.suffix.lower() == ".json"
            else {"format": "tls-planner/1", "name": path.stem, "zones": [{"table_csv": path.name}]}
        )
        data = assembled_instance(source, str(path.parent), str(out.parent), report)
        out.write_text(dumps(data))
        print(f"wrote {out}: {len(report.placements)} zones placed, {len(report.unplaced)} left in their own frames")
    return ExitCode.OK
