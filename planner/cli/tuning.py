"""The tuning keys of the command line: one table of every knob with its type, default and help.

``planner plan`` takes as flags what a surveyor sets (the site, the instrument's limits, the method and its
time, the outputs); the solver, tile and Dask knobs, the registration rule's extra limits, the field-sheet
details and the rarer input-format options are *tuning keys* instead: set by ``--set KEY=VALUE`` or by a
``[plan]`` table of ``--config FILE`` (:mod:`planner.cli.profile`), listed by ``planner plan --help-all``, and
documented with their defaults in ``planner/cli/profiles/default.toml`` (:func:`profile_text` writes it; a test
checks the file against this table). So ``plan --help-all`` stays short while every value remains settable.

The other subcommands that share a knob (``--seed`` of ``export``, ``--incidence`` of ``verify``, the input
formats of ``validate``...) keep it as the flag ``--KEY`` (:func:`add_option`), with the same type, choices,
default and help as the key, so a value means the same wherever it is given.
"""

from __future__ import annotations

import argparse
import json
import textwrap
from collections.abc import Callable, Collection
from dataclasses import dataclass, replace
from typing import Any

from planner.cli.choices import BACKENDS, CONNECTIVITY, SIDES
from planner.cli.option_types import (
    NON_NEGATIVE,
    NON_NEGATIVE_INT,
    POSITIVE,
    POSITIVE_INT,
    SAMPLING_M,
    OncePerKey,
    number,
    once_per_key,
)

#: the time budget of a tiled plan under --tiles auto, s (the issue's 10 minutes on the 16-ha plant, less reading,
#: coverage and verification)
BUDGET_S = 420.0
#: the memory limit of each Dask worker unless the worker-memory key says otherwise
WORKER_MEMORY = "1.5GiB"
#: CFT's heuristic iterations per round (planner.solve.cft.HEUR_ITERS; kept here so that --help imports no solver)
HEUR_ITERS = 250
#: the tiled local search's moves per wall piece (planner.plan.strategy.MOVES_PER_PIECE)
MOVES_PER_PIECE = 10.0

#: the words a true/false key takes on the command line (case does not matter)
_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


@dataclass(frozen=True, kw_only=True)
class Knob:
    """One tuning value: ``key`` (``tile-window-radius``) is its name in ``--set KEY=VALUE``, in a profile and,
    on a subcommand that keeps it as a flag, the flag ``--KEY``; the namespace attribute is :attr:`dest`.

    ``parse`` checks a value given as text (an argparse ``type``; None: the text itself), ``choices`` the
    values it may take; ``switch``: a true/false knob (a ``store_true`` flag); ``repeat``: a list of
    ``NAME=VALUE`` items, each name once (``layer-height``). ``section`` groups the keys in ``--help-all``
    and in the shipped profile."""

    key: str
    help: str
    section: str = ""
    parse: Callable[[str], Any] | None = None
    choices: tuple[str, ...] | None = None
    default: Any = None
    metavar: str | None = None
    switch: bool = False
    repeat: bool = False

    @property
    def dest(self) -> str:
        """The attribute of the parsed namespace that holds the value (as argparse names a flag's)."""
        return self.key.replace("-", "_")

    @property
    def initial(self) -> Any:
        """The value when nothing sets it (a fresh list for a repeatable key)."""
        return [] if self.repeat else (False if self.switch else self.default)

    def usage(self) -> str:
        """``KEY=VALUE`` as ``--help-all`` shows it: the choices or the metavar, none for a switch."""
        if self.switch:
            return f"{self.key}[=true|false]"
        if self.choices is not None:
            return f"{self.key}={{{','.join(self.choices)}}}"
        return f"{self.key}={self.metavar or 'VALUE'}"

    def from_text(self, text: str | None, items: list[str] | None = None) -> Any:
        """The value of ``KEY=text`` (``text`` None: ``KEY`` alone, a switch set), checked as the flag would be;
        ``items``: a repeatable key's values so far. ValueError says why not."""
        if self.switch:
            word = "true" if text is None else text.strip().lower()
            if word not in _TRUE + _FALSE:
                raise ValueError(f"expected true or false, got {text!r}")
            return word in _TRUE
        if text is None:
            raise ValueError(f"expected {self.key}={self.metavar or 'VALUE'}")
        if self.repeat:
            return once_per_key(list(items or []), text)
        try:
            value = self.parse(text) if self.parse is not None else text
        except argparse.ArgumentTypeError as exc:  # the option types' own words
            raise ValueError(str(exc)) from None
        except (ValueError, TypeError):
            name = getattr(self.parse, "__name__", "")
            raise ValueError(f"invalid {name} value: {text!r}") from None
        if self.choices is not None and value not in self.choices:
            raise ValueError(f"must be one of {', '.join(self.choices)}, got {text!r}")
        return value

    def from_profile(self, value: object) -> Any:
        """The value of ``key = value`` in a TOML profile: a boolean for a switch, a string or a list of strings
        for a repeatable key, else a number or string checked as its text would be."""
        if self.switch:
            if not isinstance(value, bool):
                raise ValueError("expected true or false")
            return value
        if self.repeat:
            items: list[str] = []
            for item in value if isinstance(value, list) else [value]:
                if not isinstance(item, str):
                    raise ValueError(f"expected {self.metavar} strings")
                items = once_per_key(items, item)
            return items
        if isinstance(value, (bool, list, dict)):
            raise ValueError("not a value this key takes")
        return self.from_text(str(value))


def _in(section: str, *knobs: Knob) -> tuple[Knob, ...]:
    """``knobs`` in ``section``."""
    return tuple(replace(knob, section=section) for knob in knobs)


SOLVER = "the solver"
RULES = "registration rule, accuracy model, verification"
CHECKS = "network check and field sheet"
TILES = "tiles and Dask (--tiles, --workers, --scheduler)"
INPUTS = "input formats (table CSV closure, DXF, IFC)"

#: every knob, in the order ``--help-all`` and the shipped profile list them
KNOBS: dict[str, Knob] = {
    k.key: k
    for k in (
        *_in(
            SOLVER,
            Knob(key="backend", choices=BACKENDS, default="cpsat", help="MILP backend (default cpsat)"),
            Knob(
                key="threads",
                parse=POSITIVE_INT,
                default=1,
                metavar="N",
                help="solver threads (default 1: deterministic)",
            ),
            Knob(
                key="work-limit",
                parse=POSITIVE,
                default=25.0,
                metavar="S",
                help="milp, cpsat: stop on S deterministic seconds of CP-SAT work, a count (default 25; with one "
                "thread the same plan under any load); --time-limit adds a wall-clock cap",
            ),
            Knob(
                key="local-search-moves",
                parse=NON_NEGATIVE_INT,
                default=500,
                metavar="N",
                help="milp: swaps of the local search for a connected plan one station smaller, tried once per "
                "incumbent size down to the bound (default 500; 0: off)",
            ),
            Knob(
                key="connectivity",
                choices=CONNECTIVITY,
                default="auto",
                help="milp: registration connectivity by branch-and-cut (bc, pyscipopt backend), a flow model or "
                "the cut loop (auto: bc on pyscipopt, loop elsewhere)",
            ),
            Knob(key="layer-cuts", switch=True, help="milp: add distance-layer cuts before the first solve"),
            Knob(key="tree-bound", switch=True, help="milp: add the tree (Hunter) covering bound rows"),
            Knob(
                key="no-ring-bound",
                switch=True,
                help="milp: no ring bound (the cheapest walk over the arcs a zone-side's stations see, exact when "
                "each sees one run of its wall)",
            ),
            Knob(
                key="ring-lagrange-steps",
                parse=NON_NEGATIVE_INT,
                default=500,
                metavar="N",
                help="milp: steps of the Lagrangian ascent that adds the cover rows to the ring bound (default 500; "
                "0: the ring bound alone)",
            ),
            Knob(
                key="no-regions",
                switch=True,
                help="no whole-zone-side candidates from the coverage regions (a smaller pool: closed form, samples, grid)",
            ),
            Knob(
                key="no-pricing",
                switch=True,
                help="milp: no geometric pricing, so the bound holds over the candidate pool only",
            ),
            Knob(
                key="pricing-time-limit",
                parse=NON_NEGATIVE,
                metavar="S",
                help="milp: a wall-clock cap on geometric pricing in s (default none: its rounds and work, counts, "
                "stop it); a capped pricing says so and may depend on the load",
            ),
            Knob(
                key="plane-refine-steps",
                parse=NON_NEGATIVE_INT,
                default=0,
                metavar="N",
                help="milp, zone registration: refine the connected plane bound up to N times where the ring walk "
                "stays below the plan (each a connected MILP over patches of the plane, split where its optimum "
                "sits; Baalbek's outline is certified after 13); default 0, off",
            ),
            Knob(
                key="seed",
                parse=NON_NEGATIVE_INT,
                default=0,
                metavar="N",
                help="seed of the movement-field sampling (default 0)",
            ),
        ),
        *_in(
            RULES,
            Knob(
                key="min-shared",
                parse=NON_NEGATIVE,
                default=0.0,
                metavar="M",
                help="registration: shared wall at least M m",
            ),
            Knob(key="max-link", parse=POSITIVE, metavar="M", help="registration: stations at most M m apart"),
            Knob(
                key="incidence",
                choices=("horizontal", "3d"),
                default="horizontal",
                help="incidence angle in plan (as the dissertation) or 3-D to the top of the wall (default horizontal)",
            ),
            Knob(
                key="no-precision",
                switch=True,
                help="do not require the predicted point error <= sigma_req",
            ),
            Knob(
                key="verify-spacing",
                parse=SAMPLING_M,
                default=0.1,
                metavar="M",
                help="verification sampling (default 0.1 m)",
            ),
            Knob(key="tripod", switch=True, help="compute tripod discs (always on for milp)"),
            Knob(
                key="theta-max-floor",
                parse=number(float, above=0, at_most=90),
                metavar="DEG",
                help="incidence limit of floors and ceilings in deg (default theta_max)",
            ),
        ),
        *_in(
            CHECKS,
            Knob(
                key="monte-carlo",
                parse=NON_NEGATIVE_INT,
                default=0,
                metavar="N",
                help="also simulate N adjustments (seeded; N >= 100)",
            ),
            Knob(
                key="traverse",
                metavar="FILE",
                help="the planned control traverse (JSON: points, legs), the only total-station observations; "
                "'none' for no traverse (default: a proposed one, labelled so)",
            ),
            Knob(
                key="ts-everywhere",
                switch=True,
                help="the earlier design: a total station on every station sight line (no traverse)",
            ),
            Knob(
                key="field-mode",
                choices=("shortest", "registration"),
                default="shortest",
                help="visiting order: shortest, or registration (each station after the first overlaps one "
                "scanned before it) (default shortest)",
            ),
            Knob(
                key="field-start",
                metavar="ID|X,Y",
                help="start at this station or point (default: the station nearest the first door or control point)",
            ),
            Knob(
                key="field-session",
                metavar="DURATION",
                help="split the field time into sessions, e.g. 4h, 90min",
            ),
            Knob(
                key="field-strict-walls",
                switch=True,
                help="refuse a plan whose stations no walk joins (rooms without an opening in the model; exit 4) "
                "instead of a straight leg through the walls",
            ),
        ),
        *_in(
            TILES,
            Knob(
                key="tile-budget",
                parse=POSITIVE,
                default=BUDGET_S,
                metavar="S",
                help=f"--tiles auto: the time budget the tiles' work is split from (default {BUDGET_S:g} s)",
            ),
            Knob(
                key="tile-time-limit",
                parse=POSITIVE,
                default=30.0,
                metavar="S",
                help="--tiles M: MILP work per tile, CP-SAT deterministic seconds (default 30; --time-limit caps "
                "each tile's wall clock)",
            ),
            Knob(
                key="bound-time-limit",
                parse=NON_NEGATIVE,
                default=0.0,
                metavar="S",
                help="--tiles M: work of a whole-site cover MILP for the lower bound (default 0: none; the bound is "
                "the LP's, the Lagrangian's and CFT's)",
            ),
            Knob(
                key="tile-cft-iters",
                parse=NON_NEGATIVE_INT,
                default=HEUR_ITERS,
                metavar="N",
                help=f"--tiles M: heuristic iterations per round of CFT's whole-site plain cover (default {HEUR_ITERS}; "
                "0: no CFT cover)",
            ),
            Knob(
                key="lagrange-work",
                parse=NON_NEGATIVE,
                metavar="S",
                help="--tiles M: also the Lagrangian bound over the tiles, S CP-SAT deterministic seconds per tile "
                "(0: off; default 10)",
            ),
            Knob(
                key="lagrange-group",
                parse=POSITIVE_INT,
                default=1,
                metavar="N",
                help="--tiles M: Lagrangian parts of N x N tiles (default 1)",
            ),
            Knob(
                key="tile-search-moves",
                parse=NON_NEGATIVE_INT,
                metavar="N",
                help="--tiles M: move budget of the local search that shrinks the kept plan (default: "
                "tile-moves-per-piece per wall piece; 0: none)",
            ),
            Knob(
                key="tile-moves-per-piece",
                parse=NON_NEGATIVE,
                default=MOVES_PER_PIECE,
                metavar="K",
                help=f"--tiles M: the local search's moves per wall piece of the site (default {MOVES_PER_PIECE:g})",
            ),
            Knob(
                key="tile-search-seeds",
                parse=POSITIVE_INT,
                default=1,
                metavar="N",
                help="--tiles M: run the local search with seeds 0..N-1 (as Dask tasks with --workers) and keep the "
                "smallest plan (default 1)",
            ),
            Knob(
                key="tile-window-passes",
                parse=NON_NEGATIVE_INT,
                default=1,
                metavar="N",
                help="--tiles M: passes of the exact window re-solves after the local search (default 1; 0: none)",
            ),
            Knob(
                key="tile-window-radius",
                parse=POSITIVE,
                default=60.0,
                metavar="M",
                help="--tiles M: radius of a re-solve window around each station (default 60 m)",
            ),
            Knob(
                key="tile-window-work",
                parse=POSITIVE,
                default=3.0,
                metavar="S",
                help="--tiles M: CP-SAT deterministic seconds per window (default 3)",
            ),
            Knob(
                key="tile-window-batch",
                parse=POSITIVE_INT,
                default=1,
                metavar="N",
                help="--tiles M on Dask: N windows in flight as tasks, their answers taken in order (default 1: one "
                "at a time in this process; same plan either way)",
            ),
            Knob(
                key="tile-wall-clock",
                switch=True,
                help="--tiles M: tile-time-limit and bound-time-limit in wall-clock seconds (the plan may then "
                "depend on the load)",
            ),
            Knob(
                key="worker-memory",
                default=WORKER_MEMORY,
                metavar="SIZE",
                help=f"--tiles --workers: memory limit of each worker (default {WORKER_MEMORY})",
            ),
        ),
        *_in(
            INPUTS,
            Knob(
                key="angular-tolerance",
                parse=float,
                metavar="DEG",
                help="closure tolerance of table CSV zones",
            ),
            Knob(
                key="min-relative-precision",
                parse=float,
                metavar="N",
                help="closure 1:N of table CSV zones",
            ),
            Knob(
                key="layer-height",
                repeat=True,
                metavar="LAYER=M",
                help="DXF: wall height of polylines on LAYER that carry none (repeatable, once per layer)",
            ),
            Knob(
                key="dxf-side",
                choices=SIDES,
                default="inside",
                help="DXF: scan side of zones whose layer and XDATA do not say (default inside)",
            ),
            Knob(key="exterior", switch=True, help="IFC: also scan the storey's outer outline from outside"),
            Knob(
                key="ifc-windows",
                switch=True,
                help="IFC: record windows as openings too (default: a window is wall surface)",
            ),
        ),
    )
}

#: per subcommand, its tuning keys: not flags, but ``--set KEY=VALUE`` and ``--config FILE`` keys
TUNING: dict[str, tuple[str, ...]] = {"plan": tuple(KNOBS)}


def add_option(p: argparse.ArgumentParser, key: str, tuning: Collection[str] = (), *, name: str | None = None) -> None:
    """The knob ``key`` as the flag ``--KEY`` (``--NAME``) of ``p``, unless ``key`` is one of ``tuning``, the
    tuning keys of ``p``'s command, which take it by ``--set``/``--config`` instead."""
    if key in tuning:
        return
    knob = KNOBS[key]
    flag = f"--{name or key}"
    if knob.switch:
        p.add_argument(flag, action="store_true", help=knob.help)
    elif knob.repeat:
        p.add_argument(flag, action=OncePerKey, default=[], metavar=knob.metavar, help=knob.help)
    else:
        parse: dict[str, Any] = {} if knob.parse is None else {"type": knob.parse}
        p.add_argument(flag, choices=knob.choices, default=knob.default, metavar=knob.metavar, help=knob.help, **parse)


def option_name(command: str | None, key: str) -> str:
    """How ``command`` takes the knob ``key``, for an error message: ``--set KEY`` where it is a tuning key,
    else the flag ``--KEY``."""
    return f"--set {key}" if key in TUNING.get(command or "", ()) else f"--{key}"


def keys_help(command: str, width: int = 80) -> str:
    """The tuning keys of ``command`` by section, each with its values and help (the end of ``--help-all``)."""
    lines = textwrap.wrap(
        f"tuning keys (--set KEY=VALUE, repeatable, or a [{command}] table in --config FILE; the defaults, "
        f"commented: planner/cli/profiles/default.toml):",
        width,
        break_on_hyphens=False,
    )
    indent = 24
    section = None
    for key in TUNING.get(command, ()):
        knob = KNOBS[key]
        if knob.section != section:
            section = knob.section
            lines += ["", f" {section}:"]
        head = f"  {knob.usage()}"
        body = textwrap.wrap(knob.help, max(width - indent, 20), break_on_hyphens=False)
        if len(head) + 2 <= indent:
            lines.append(head.ljust(indent) + body[0])
            body = body[1:]
        else:
            lines.append(head)
        lines += [" " * indent + line for line in body]
    return "\n".join(lines)


def profile_text(command: str) -> str:
    """The shipped profile of ``command`` (``planner/cli/profiles/default.toml``): every tuning key with its help
    as a comment and its default (keys without one commented out)."""
    out = [
        f"# The tuning keys of `planner {command}` and their defaults (`planner {command} --help-all` lists them).",
        "# Copy the lines you change into a file of your own and give it with",
        f"# `planner {command} SITE --config FILE`, or set one key on the command line with `--set KEY=VALUE`",
        "# (`--set` wins over the file). A test checks this file against the table of keys",
        "# (planner/cli/tuning.py), so it is what the command does when nothing is said.",
        "",
        f"[{command}]",
    ]
    section = None
    for key in TUNING[command]:
        knob = KNOBS[key]
        if knob.section != section:
            section = knob.section
            out += ["", f"# --- {section} ---"]
        out += [""] + ["# " + line for line in textwrap.wrap(knob.help, 108, break_on_hyphens=False)]
        value = knob.initial
        if value is None or value == []:
            out.append(f"# {key} = (no default: unset)")
        else:
            out.append(f"{key} = {_toml(value)}")
    return "\n".join(out) + "\n"


def _toml(value: object) -> str:
    """``value`` as a TOML value (booleans, numbers and strings are all the defaults hold)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    return json.dumps(value)
