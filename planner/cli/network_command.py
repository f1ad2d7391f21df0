"""``planner network`` and ``planner chain``: the station network of a plan, its least-squares accuracy and
registration chain (the network check also runs from ``planner plan --network``)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from planner.cli.inputs import load_with_overrides, recorded_notes, some_stations
from planner.cli.tuning import option_name
from planner.core.errors import ExitCode, InputError, UsageError, located_in
from planner.core.text import dumps

# Everything else loads inside the command that needs it, so that --help, --version and validate
# start without the solver, network, figure and report stacks (docs/startup.md).
if TYPE_CHECKING:
    from planner.network.check import NetworkReport
    from planner.plan.problem import Problem
    from planner.site import Site

#: a Monte Carlo design study repeats the adjustment at least 100 times
MIN_MONTE_CARLO = 100


def check_network_options(args: argparse.Namespace) -> None:
    """The network options' values that need no file read: checked before the network stack loads."""
    command = getattr(args, "command", None)  # on plan the network's knobs are tuning keys (--set KEY=VALUE)
    if args.monte_carlo and args.monte_carlo < MIN_MONTE_CARLO:
        raise UsageError(
            f"Monte Carlo needs at least {MIN_MONTE_CARLO} runs",
            field=option_name(command, "monte-carlo"),
            value=args.monte_carlo,
        )
    if getattr(args, "traverse", None) and args.ts_everywhere:
        names = option_name(command, "traverse"), option_name(command, "ts-everywhere")
        raise UsageError(f"{names[0]} and {names[1]} exclude each other", field=names[0], value=args.traverse)


def network_inputs(args: argparse.Namespace) -> tuple[Any, Any]:
    """The network options' values (:func:`check_network_options`) and files (control points, traverse), checked
    and read."""
    check_network_options(args)
    from planner.io.network_files import read_control
    from planner.network.traverse import read_traverse

    with located_in(getattr(args, "control", None)):
        control = read_control(args.control) if getattr(args, "control", None) else None
    traverse = read_traverse(args.traverse) if getattr(args, "traverse", None) else None
    if getattr(args, "observations", None) and not Path(args.observations).is_file():
        raise InputError("cannot read the observations: no such file", file=args.observations)
    return control, traverse


def network_check(
    problem: Problem,
    stations: list[Any],
    args: argparse.Namespace,
    inputs: tuple[Any, Any],
    show: bool = True,
    coverage: Any = None,
) -> NetworkReport:
    """Run the network check of ``problem``'s stations with ``inputs`` = :func:`network_inputs` (control points,
    traverse), under the problem's sight and registration scope; ``coverage``: the stations' coverage on the station
    pieces where the plan built it already (:attr:`planner.plan.result.Plan.stations_cover`)."""
    from planner.io.network_files import adjust_observations
    from planner.network.check import run_network

    control, traverse = inputs
    with located_in(args.traverse if traverse is not None else None):  # a leg naming an unknown point
        report = run_network(
            problem.sight,
            stations,
            control=control,
            monte_carlo_runs=args.monte_carlo,
            seed=args.seed,
            registration=problem.registration,
            traverse=traverse,
            ts_everywhere=getattr(args, "ts_everywhere", False),
            coverage=coverage,
        )
    if not show:
        return report
    print(report.summary())
    if getattr(args, "observations", None):
        with located_in(args.observations):
            print(adjust_observations(report, args.observations))
    if args.out:  # a staging folder that planner.cli.outputs moves into place when the command succeeds
        Path(args.out).mkdir(parents=True, exist_ok=True)
        path = Path(args.out) / "network.json"
        path.write_text(dumps(report.to_dict()))
        print(f"wrote {path}")
    return report


def cmd_network(args: argparse.Namespace) -> int:
    from planner.io.plan_json import read_plan_stations

    check_network_options(args)  # before any work
    site = load_with_overrides(args)
    inputs = network_inputs(args)
    problem = plan_registration(checking_problem(args, site), args)
    stations = some_stations(args.plan, read_plan_stations(args.plan, problem.site))
    recorded_notes(args.plan, problem.site)
    network_check(problem, stations, args, inputs)
    return ExitCode.OK


def checking_problem(args: argparse.Namespace, site: Site | None = None) -> Problem:
    """The site of a checking command (verify, network, chain) resolved once under the sight options it
    has (incidence, precision) and its registration scope; the site is read first (``site``: read already), so
    that a bad one is refused before the planning stack loads."""
    if site is None:
        site = load_with_overrides(args)
    from planner.plan import PlanOptions
    from planner.plan.problem import resolve

    options = PlanOptions.checking(
        incidence_3d=getattr(args, "incidence", "horizontal") == "3d",
        precision=not getattr(args, "no_precision", False),
        combined=getattr(args, "precision", "single") == "combined",
        registration=getattr(args, "registration", None),
    )
    return resolve(site, options)


def plan_registration(problem: Problem, args: argparse.Namespace) -> Problem:
    """``problem`` with the registration the plan file records (unless ``--registration`` asks for one): the
    network relates the plan's own pairs."""
    from planner.core.fileio import read_json
    from planner.plan.problem import with_recorded_registration

    if getattr(args, "registration", None) is not None:
        return problem
    raw = read_json(args.plan)
    return with_recorded_registration(problem, raw) if isinstance(raw, dict) else problem


def cmd_chain(args: argparse.Namespace) -> int:
    """The plan's network as a scanner survey: registration links, ties to control, chain accuracy."""
    from planner.io.plan_json import read_plan_stations
    from planner.network.survey import survey_network

    problem = plan_registration(checking_problem(args), args)
    stations = some_stations(args.plan, read_plan_stations(args.plan, problem.site))
    recorded_notes(args.plan, problem.site)
    print("\n".join(survey_network(problem.sight, stations, problem.registration).lines()))
    return ExitCode.OK
