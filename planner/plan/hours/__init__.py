"""The field-time objective: plans for the hours on site.

A view covers a wall piece only at a scan setting that gives every point of it the asked point spacing; each
station gets its own setting from the instrument's table. :mod:`.columns` turns the pool into (station, setting)
columns, :mod:`.field_time` plans with them (fewest stations at a spacing, or least set-up + scan time),
:mod:`.verify` checks the spacing point by point, and :mod:`.record` is what the plan carries
(:class:`Hours`). The trade-off against the plans at one setting and the walk search need the field sheet's route,
so they live above it (:mod:`planner.field.tradeoff`, :mod:`planner.field.route_search`)."""

from planner.plan.hours.record import Hours, no_gain_reason, settings_line

__all__ = ["Hours", "no_gain_reason", "settings_line"]
