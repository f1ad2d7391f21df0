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
``moves-per-piece``; the other limits derive from them (:data:`TILE_SPLIT`, :data:`SEARCH_MOVES_PER_PIECE`, and the
MILP's stall rule ``milp.stall_work``: 2/25 of its work limit, 2 of the 25 deterministic seconds).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from planner.core.settings.model import (
    BACKENDS,
    CHECKS,
    EXPORTS,
    FORMATS,
    INCIDENCE_MODELS,
    INPUTS,
    METHODS,
    OBJECTIVES,
    PRECISION_MODES,
    RULES,
    SEARCH_MOVES_PER_PIECE,
    SIDES,
    SOLVER,
    SURFACES,
    SURVEY,
    TILE_SPLIT,
    TILES,
    VARIANTS,
    Setting,
)
from planner.core.settings.table import SETTINGS

__all__ = [
    "BACKENDS",
    "CHECKS",
    "DEFAULTS",
    "EXPORTS",
    "FORMATS",
    "INCIDENCE_MODELS",
    "INPUTS",
    "METHODS",
    "OBJECTIVES",
    "PLAN_FLAGS",
    "PLAN_KEYS",
    "PRECISION_MODES",
    "RULES",
    "SEARCH_MOVES_PER_PIECE",
    "SETTINGS",
    "SIDES",
    "SOLVER",
    "SURFACES",
    "SURVEY",
    "TILE_SPLIT",
    "TILES",
    "VARIANTS",
    "Setting",
    "field_values",
    "setting_of",
]

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
