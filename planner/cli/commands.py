"""The ``planner`` command: one function per subcommand; parses, calls the library, prints.

Exit codes: 0 ok, 1 internal error, 2 usage, 3 invalid input, 4 infeasible problem, 5 unreachable
scheduler, 141 standard output closed by its reader (see :mod:`planner.errors`). Errors print as one
line on stderr; set PLANNER_DEBUG=1 to see the traceback of an internal error.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import traceback
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from planner import progress
from planner.cli.parser import build_parser as _build_parser
from planner.cli.profile import apply_config
from planner.cli.report import parse_exports, write_exports
from planner.cli.tiles import plan_command
from planner.errors import ExitCode, InfeasibleError, InputError, PlannerError, UsageError, located_in
from planner.text import dumps

# Everything else loads inside the command that needs it, so that --help, --version and validate
# start without the solver, network, figure and report stacks (docs/startup.md).
if TYPE_CHECKING:
    from planner.network.check import NetworkReport
    from planner.plan import PlanOptions
    from planner.site import Site
    from planner.site.dxf_in import DxfOptions
    from planner.site.validate import ValidationReport
    from planner.solve.result import SolveResult

#: seed 003: a Monte Carlo design study repeats the adjustment at least 100 times
MIN_MONTE_CARLO = 100


def load_with_overrides(args: argparse.Namespace) -> Site:
    """Load the site and apply the command-line parameter overrides."""
    from planner.site import load_site
    from planner.site.params import ClosureTolerance

    tol_kw = {}
    if args.angular_tolerance is not None:
        tol_kw["angular_deg"] = args.angular_tolerance
    if args.min_relative_precision is not None:
        tol_kw["min_relative_precision"] = args.min_relative_precision
    suffix = Path(args.site).suffix.lower()
    site = load_site(
        args.site,
        ClosureTolerance(**tol_kw) if tol_kw else None,
        crs=args.crs,
        dxf=_dxf_options(args) if suffix == ".dxf" else None,
        ifc=_ifc_options(args) if suffix == ".ifc" else None,
    )
    p = site.parameters
    derive = args.theta_max == "derive"
    changes = {
        k: v
        for k, v in {
            "max_slant_range_m": args.max_range,
            "theta_max_deg": None if derive else args.theta_max,
            "overlap": args.overlap,
            "sigma_req_m": args.sigma_req,
            "instrument_height_m": args.instrument_height,
            "incidence_model": args.incidence_model,
            "min_standoff_m": args.standoff,
            "derive_theta_max": derive or None,
        }.items()
        if v is not None
    }
    if args.sigma_req is not None:
        changes["drawing_scale"] = None
    p = replace(p, **changes)
    if args.scale is not None:
        p = p.with_scale(args.scale)
    return replace(site, parameters=p, instrument=args.instrument or site.instrument)


def _ifc_options(args: argparse.Namespace) -> Any:
    from planner.site.ifc_in import IfcOptions

    return IfcOptions(storey=args.storey, windows=args.ifc_windows, exterior=args.exterior)


def _dxf_options(args: argparse.Namespace) -> DxfOptions:
    from planner.site import ScanSide
    from planner.site.dxf_in import DxfOptions

    heights = {}
    for item in args.layer_height:
        layer, _, value = item.partition("=")
        try:
            heights[layer] = float(value)
        except ValueError:
            raise UsageError("expected LAYER=HEIGHT_M", field="--layer-height", value=item) from None
        if not (math.isfinite(heights[layer]) and heights[layer] > 0):
            raise UsageError("height must be a finite number > 0", field="--layer-height", value=item)
    return DxfOptions(layer_heights_m=heights, default_side=ScanSide(args.dxf_side))


def cmd_validate(args: argparse.Namespace) -> int:
    from planner.site.validate import validate_site

    report = validate_site(load_with_overrides(args))
    print(dumps(report.to_dict()).rstrip("\n") if args.json else report.summary())
    return ExitCode.OK


def _plan_options(args: argparse.Namespace, overlap: float) -> PlanOptions:
    from planner.candidates.pool import PoolOptions
    from planner.coverage.overlap import planning_rule
    from planner.plan import PlanOptions
    from planner.solve.milp import MilpOptions

    pool = PoolOptions(grid_spacing_m=args.grid_spacing, seed=args.seed)
    rule = None if args.no_overlap else planning_rule(overlap, args.min_shared, args.max_link)
    milp = MilpOptions(
        backend=args.backend,
        time_limit_s=args.time_limit,
        seed=args.seed,
        threads=args.threads,
        k=args.k,
        overlap=rule,
        precision=args.precision,
        connectivity=args.connectivity,
        layer_cuts=args.layer_cuts,
        tree_bound=args.tree_bound,
        work_limit=args.work_limit,
        local_search_moves=args.local_search_moves,
        ring_bound=not args.no_ring_bound,
        ring_lagrange_steps=args.ring_lagrange_steps,
    )
    return PlanOptions(
        method=args.method,
        target_spacing_m=args.target_spacing,
        pool=pool,
        incidence_3d=args.incidence == "3d",
        precision=not args.no_precision,
        verify_spacing_m=args.verify_spacing,
        milp=milp,
        tripod=args.method == "milp" or args.tripod,
        recentre=args.recentre,
        registration=args.registration,
        regions=not args.no_regions,
        pricing=not args.no_pricing,
        pricing_time_limit_s=args.pricing_time_limit,
        memory_limit_bytes=_memory_limit(args),
    )


def _guard_memory(site: Site, args: argparse.Namespace, validation: ValidationReport) -> None:
    """The memory check of build_problem, run before the solver stacks load so that a refusal is quick."""
    from planner.plan.memory_guard import check_memory

    max_slant_range_m = validation.range_limit.max_slant_range_m
    check_memory(site, args.target_spacing, args.grid_spacing, max_slant_range_m, _memory_limit(args))


def _memory_limit(args: argparse.Namespace) -> int | None:
    from planner.plan.memory_guard import parse_memory

    return parse_memory(args.memory_limit) if args.memory_limit else None


def _usable_folder(flag: str, folder: str | None) -> None:
    """An output folder given on the command line: it is (or can be made) a folder, else a usage error."""
    if folder is None:
        return
    if not folder.strip():
        raise UsageError("is empty: name a folder", field=flag, value=folder)
    try:
        Path(folder).mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(
            f"cannot be used as an output folder ({exc.strerror or exc})", field=flag, value=folder
        ) from None


def cmd_plan(args: argparse.Namespace) -> int:
    formats = parse_exports(args.export)
    if formats and not args.out:
        raise UsageError("--export writes into the --out folder; give --out DIR", field="--export", value=args.export)
    for flag, folder in (("--out", args.out), ("--report", args.report), ("--field", args.field)):
        _usable_folder(flag, folder)  # before the planning, not after it
    if args.monte_carlo and not (args.network or args.report):
        raise UsageError(
            "Monte Carlo runs are part of the network check; give --network",
            field="--monte-carlo",
            value=args.monte_carlo,
        )
    # the network's option values and files, read before the planning (the report runs the network too)
    inputs = _network_inputs(args) if args.network or args.report else None
    field_options = None
    if args.field:  # the sheet's option values, checked before the planning too
        from planner.cli.field import field_options as _field_options

        field_options = _field_options(args, "field-")
    site = load_with_overrides(args)
    from planner.site.validate import validate_site

    validation = validate_site(site)  # once per run: the guard, the strategy and the plan all take it
    _guard_memory(site, args, validation)
    from planner.plan.outcome import outcome_from_plan
    from planner.plan.plan_json import write_plan
    from planner.report import compare_methods, write_report

    options = _plan_options(args, site.parameters.overlap)
    plan = plan_command(site, options, args, validation)
    if not plan.stations and plan.result.status.value in ("infeasible", "no_solution"):
        print(plan.summary().splitlines()[0])
        raise InfeasibleError(f"{plan.result.method} found no plan: {_no_plan_reason(plan.result, options)}")
    print(plan.summary())
    if args.out:
        print(f"wrote {write_plan(plan, args.out)}")
    network = None
    if inputs is not None:
        network = _network(site, list(plan.stations), args, inputs, show=args.network)
    if field_options is not None:
        from planner.cli.field import write_field

        write_field(site, plan.stations, field_options, args.field)
    if formats or args.report:
        outcome = outcome_from_plan(plan, network, compare_methods(site, options, plan) if args.report else ())
        write_exports(outcome, formats, args.out, args.crs)
        if args.report:
            print(f"wrote {write_report(outcome, args.report, field=args.field)}")
    return ExitCode.OK


def _no_plan_reason(result: SolveResult, options: PlanOptions) -> str:
    """Why a solver stopped without stations, in words."""
    info = result.info
    if "targets_seen_by_fewer_than_k" in info:
        return f"{info['count']} target(s) seen by fewer than k = {options.milp.k} candidates"
    if result.status.value == "no_solution":
        return f"no cover found within the time limit of {options.milp.time_limit_s:g} s (raise --time-limit)"
    rules = ["every piece covered"] + ([f"k = {options.milp.k}"] if options.milp.k > 1 else [])
    rules += ["registration overlap connected"] if options.milp.rule is not None else []
    rules += ["combined precision"] if options.combined else []
    return f"the solver proved that no set of candidates meets {', '.join(rules)}"


def _network_inputs(args: argparse.Namespace) -> tuple[Any, Any]:
    """The network options' values and files (control points, traverse), checked and read."""
    from planner.network.io import read_control
    from planner.network.traverse import read_traverse

    if args.monte_carlo and args.monte_carlo < MIN_MONTE_CARLO:
        raise UsageError(
            f"Monte Carlo needs at least {MIN_MONTE_CARLO} runs (seed 003)",
            field="--monte-carlo",
            value=args.monte_carlo,
        )
    if getattr(args, "traverse", None) and args.ts_everywhere:
        raise UsageError("--traverse and --ts-everywhere exclude each other", field="--traverse", value=args.traverse)
    with located_in(getattr(args, "control", None)):
        control = read_control(args.control) if getattr(args, "control", None) else None
    traverse = read_traverse(args.traverse) if getattr(args, "traverse", None) else None
    if getattr(args, "observations", None) and not Path(args.observations).is_file():
        raise InputError("cannot read the observations: no such file", file=args.observations)
    return control, traverse


def _network(
    site: Site, stations: list[Any], args: argparse.Namespace, inputs: tuple[Any, Any], show: bool = True
) -> NetworkReport:
    """Run the network check with ``inputs`` = :func:`_network_inputs` (control points, traverse)."""
    from planner.network.check import run_network
    from planner.network.io import adjust_observations

    control, traverse = inputs
    with located_in(args.traverse if traverse is not None else None):  # a leg naming an unknown point
        report = run_network(
            site,
            stations,
            control=control,
            monte_carlo_runs=args.monte_carlo,
            seed=args.seed,
            registration=getattr(args, "registration", None),
            precision=getattr(args, "precision", "single"),
            traverse=traverse,
            ts_everywhere=getattr(args, "ts_everywhere", False),
        )
    if not show:
        return report
    print(report.summary())
    if getattr(args, "observations", None):
        with located_in(args.observations):
            print(adjust_observations(report, args.observations))
    if args.out:
        Path(args.out).mkdir(parents=True, exist_ok=True)
        path = Path(args.out) / "network.json"
        path.write_text(dumps(report.to_dict()))
        print(f"wrote {path}")
    return report


def cmd_network(args: argparse.Namespace) -> int:
    from planner.plan.plan_json import read_plan_stations

    _usable_folder("--out", args.out)
    inputs = _network_inputs(args)  # before any work
    site = load_with_overrides(args)
    stations = _some_stations(args.plan, read_plan_stations(args.plan, site))
    _recorded_notes(args.plan, site)
    _network(site, stations, args, inputs)
    return ExitCode.OK


def _recorded_notes(path: str, site: Any) -> None:
    """Say which limits the plan was made under that differ from the site's (the check uses the site's)."""
    from planner.plan.plan_json import recorded_differences

    for line in recorded_differences(path, site):
        print(line)


def _some_stations(path: str, stations: list[Any]) -> list[Any]:
    """A network needs a station (verify, by contrast, reports an empty plan as 0 % covered)."""
    if not stations:
        raise InputError("the plan has no stations: there is no network to check", file=path, field="stations", value=0)
    return stations


def cmd_verify(args: argparse.Namespace) -> int:
    from planner.coverage.visibility import sight_limits
    from planner.plan.plan_json import read_plan_stations
    from planner.plan.verify import verify_stations
    from planner.site.validate import validate_site

    site = load_with_overrides(args)
    validation = validate_site(site)
    stations = read_plan_stations(args.plan, site)
    limits = sight_limits(validation, args.incidence == "3d", not args.no_precision, args.precision == "combined")
    report = verify_stations(site, stations, limits, args.spacing)
    print(f"plan {args.plan}: {len(stations)} stations")
    _recorded_notes(args.plan, site)
    print(report.summary())
    return ExitCode.OK if report.complete else ExitCode.INFEASIBLE


def cmd_export(args: argparse.Namespace) -> int:
    site = load_with_overrides(args)
    from planner.site.validate import validate_site

    validation = validate_site(site)
    _guard_memory(site, args, validation)
    from planner.candidates.pool import PoolOptions
    from planner.coverage.overlap import rule_of
    from planner.exchange.export import export_problem
    from planner.plan import PlanOptions, build_problem

    options = PlanOptions(
        target_spacing_m=args.target_spacing,
        pool=PoolOptions(grid_spacing_m=args.grid_spacing, seed=args.seed),
        incidence_3d=args.incidence == "3d",
        precision=not args.no_precision,
        memory_limit_bytes=_memory_limit(args),
    )
    problem = build_problem(site, options, validation)
    text = export_problem(problem, args.format, rule_of(site.parameters.overlap))
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
    from planner.site import load_site
    from planner.site.assemble import assemble
    from planner.site.assembly_io import assembled_instance
    from planner.site.fileio import read_json

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


def cmd_chain(args: argparse.Namespace) -> int:
    """The plan's network as a scanner survey: registration links, ties to control, chain accuracy."""
    from planner.network.survey import survey_network
    from planner.plan.plan_json import read_plan_stations

    site = load_with_overrides(args)
    stations = _some_stations(args.plan, read_plan_stations(args.plan, site))
    _recorded_notes(args.plan, site)
    print("\n".join(survey_network(site, stations, args.registration).lines()))
    return ExitCode.OK


def build_parser() -> argparse.ArgumentParser:
    """The ``planner`` parser with this module's commands (:func:`planner.cli.parser.build_parser`)."""
    return _build_parser(
        {
            "validate": cmd_validate,
            "plan": cmd_plan,
            "verify": cmd_verify,
            "export": cmd_export,
            "network": cmd_network,
            "chain": cmd_chain,
            "assemble": cmd_assemble,
            "instruments": cmd_instruments,
        }
    )


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    try:
        parser = build_parser()
        apply_config(parser, argv)  # --config FILE: the profile's values become the defaults, the command line wins
        args = parser.parse_args(argv)
    except UsageError as exc:
        print(f"planner: usage error: {exc.one_line()}", file=sys.stderr)
        return int(exc.exit_code)
    except SystemExit as done:  # --help, --version, or a usage error already printed in one line
        return int(done.code or 0) if not isinstance(done.code, str) else int(ExitCode.USAGE)
    show = not getattr(args, "quiet", True) and sys.stderr.isatty()
    previous = progress.set_sink(progress.Bar(sys.stderr) if show else None)
    try:
        return int(args.func(args))
    except PlannerError as exc:
        print(f"planner: error: {exc.one_line()}", file=sys.stderr)
        return int(exc.exit_code)
    except KeyboardInterrupt:
        print("planner: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader of standard output stopped reading (| head): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so that the interpreter's final flush does not fail again
        return int(ExitCode.BROKEN_PIPE)
    except OSError as exc:  # a path given on the command line that cannot be written (or read)
        where = f"{exc.filename}: " if exc.filename else ""
        print(
            f"planner: error: {where}{exc.strerror or exc} (an output path given on the command line?)", file=sys.stderr
        )
        return int(ExitCode.USAGE)
    except Exception as exc:  # a bug: one line, the traceback only on request
        if os.environ.get("PLANNER_DEBUG"):
            traceback.print_exc()
        first = str(exc).splitlines()[0] if str(exc) else ""
        print(
            f"planner: internal error: {type(exc).__name__}: {first} (set PLANNER_DEBUG=1 for the traceback)",
            file=sys.stderr,
        )
        return int(ExitCode.INTERNAL)
    finally:
        progress.set_sink(previous)
