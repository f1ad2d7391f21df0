"""Instrument models (scanners, total stations; read from ``models/`` and checked: :mod:`~planner.instrument.models`)
and the accuracy model of a view (e(S, theta) and all derived from it, chapter 2: :mod:`~planner.instrument.accuracy`).
"""
