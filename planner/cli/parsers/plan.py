"""``planner plan``: plan the stations of a site and verify the plan (the tuning options are hidden from ``--help``; :mod:`planner.cli.profile`)."""

from __future__ import annotations

import argparse

from planner.cli.choices import BACKENDS, CONNECTIVITY, METHODS, PRECISION_MODES
from planner.cli.field import add_field_options
from planner.cli.option_types import NON_NEGATIVE, NON_NEGATIVE_INT, POSITIVE, POSITIVE_INT, SAMPLING_M
from planner.cli.parsers.common import (
    Handlers,
    add_limit_options,
    add_memory_option,
    add_network_options,
    add_pool_options,
    add_site_options,
)
from planner.cli.profile import add_profile_options, hide_tuning
from planner.cli.tiles import add_tile_options


def add_parser(sub: argparse._SubParsersAction, handlers: Handlers) -> None:
    """Add ``plan`` to the subcommands ``sub``."""
    pl = sub.add_parser("plan", help="plan the stations of a site and verify the plan")
    add_site_options(pl)
    pl.add_argument(
        "--method",
        choices=METHODS,
        default="milp",
        help="closed-form (the dissertation), greedy (Chvatal) or milp (optimal; default)",
    )
    pl.add_argument("--backend", choices=BACKENDS, default="cpsat", help="MILP backend (default cpsat)")
    pl.add_argument("--time-limit", type=POSITIVE, default=60.0, metavar="S", help="MILP time limit in s (default 60)")
    pl.add_argument(
        "--work-limit",
        type=POSITIVE,
        default=None,
        metavar="S",
        help="cpsat, 1 thread: stop on S deterministic seconds of CP-SAT work (same plan under any load); "
        "--time-limit stays a wall-clock cap",
    )
    pl.add_argument(
        "--local-search-moves",
        type=NON_NEGATIVE_INT,
        default=500,
        metavar="N",
        help="milp: swaps of the local search for a connected plan one station smaller, tried once per "
        "incumbent size down to the bound (default 500; 0: off)",
    )
    pl.add_argument("--threads", type=POSITIVE_INT, default=1, help="solver threads (default 1: deterministic)")
    pl.add_argument("--k", type=POSITIVE_INT, default=1, help="each wall piece seen by at least k stations (default 1)")
    pl.add_argument(
        "--precision",
        choices=PRECISION_MODES,
        default="single",
        help="single: each view must meet sigma_req; combined: views add information (every method; default single)",
    )
    pl.add_argument(
        "--no-overlap", action="store_true", help="MILP and greedy without the registration-overlap constraint"
    )
    pl.add_argument(
        "--connectivity",
        choices=CONNECTIVITY,
        default="auto",
        help="milp: registration connectivity by branch-and-cut (bc, pyscipopt backend), a flow model or "
        "the cut loop (auto: bc on pyscipopt, loop elsewhere)",
    )
    pl.add_argument("--layer-cuts", action="store_true", help="milp: add distance-layer cuts before the first solve")
    pl.add_argument("--tree-bound", action="store_true", help="milp: add the tree (Hunter) covering bound rows")
    pl.add_argument(
        "--no-ring-bound",
        action="store_true",
        help="milp: no ring bound (the cheapest walk over the arcs a zone-side's stations see, exact when "
        "each sees one run of its wall)",
    )
    pl.add_argument(
        "--ring-lagrange-steps",
        type=NON_NEGATIVE_INT,
        default=500,
        metavar="N",
        help="milp: steps of the Lagrangian ascent that adds the cover rows to the ring bound (default 500; "
        "0: the ring bound alone)",
    )
    pl.add_argument(
        "--min-shared", type=NON_NEGATIVE, default=0.0, metavar="M", help="registration: shared wall at least M m"
    )
    pl.add_argument(
        "--max-link", type=POSITIVE, default=None, metavar="M", help="registration: stations at most M m apart"
    )
    pl.add_argument(
        "--registration",
        choices=("zone", "site"),
        default=None,
        help="one registration bundle per zone-side, or per accessible area of the site (default: site "
        "where zones are placed or openings given)",
    )
    pl.add_argument("--tripod", action="store_true", help="compute tripod discs (always on for milp)")
    pl.add_argument("--recentre", action="store_true", help="move each station to the centre of its tripod disc")
    pl.add_argument(
        "--no-regions",
        action="store_true",
        help="no whole-zone-side candidates from the coverage regions (a smaller pool: closed form, samples, grid)",
    )
    pl.add_argument(
        "--no-pricing",
        action="store_true",
        help="milp: no geometric pricing, so the bound holds over the candidate pool only",
    )
    pl.add_argument(
        "--pricing-time-limit",
        type=NON_NEGATIVE,
        default=120.0,
        metavar="S",
        help="milp: time for geometric pricing (default 120 s); past it the bound scope stays 'pool'",
    )
    pl.add_argument(
        "--plane-refine-steps",
        type=NON_NEGATIVE_INT,
        default=0,
        metavar="N",
        help="milp, zone registration: refine the connected plane bound up to N times where the ring walk stays "
        "below the plan (each a connected MILP over patches of the plane, split where its optimum sits; "
        "Baalbek's outline is certified after 13); default 0, off",
    )
    add_memory_option(pl)
    pl.add_argument("--network", action="store_true", help="then build the station network and check its accuracy")
    add_network_options(pl)
    pl.add_argument("--out", metavar="DIR", help="write DIR/plan.json")
    pl.add_argument(
        "--export",
        metavar="LIST",
        help="also write into --out: dxf (plan.dxf), geojson (plan.geojson), csv (stations.csv), comma-separated",
    )
    pl.add_argument("--report", metavar="DIR", help="write DIR/report.html (figures embedded; runs the network check)")
    pl.add_argument(
        "--field",
        metavar="DIR",
        help="write the field sheet into DIR (field.html/.csv/.geojson/.json: "
        "visiting order, walking route, field time, targets; see planner field)",
    )
    add_field_options(pl, "field-")
    add_pool_options(pl)
    pl.add_argument(
        "--verify-spacing", type=SAMPLING_M, default=0.1, metavar="M", help="verification sampling (default 0.1 m)"
    )
    add_limit_options(pl)
    add_tile_options(pl)
    add_profile_options(pl)
    hide_tuning(pl, "plan")
    pl.set_defaults(func=handlers["plan"])
