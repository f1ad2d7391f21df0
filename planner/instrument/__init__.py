"""Instrument models (scanners, total stations; read from ``models/``) and the accuracy model of a view.

- :mod:`planner.instrument.models`: the instrument models as data, read and checked;
- :mod:`planner.instrument.accuracy`: the view error e(S, theta) and everything derived from it (chapter 2).
"""
