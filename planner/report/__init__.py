"""The self-contained HTML report of a plan (figures embedded as PNG data URIs). Its names load on first use, so
that a command that only checks outputs (:mod:`planner.report.consistency`) does not import the report's stack."""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from planner.report.compare import compare_methods
    from planner.report.html import render_report, write_report

__all__ = ["compare_methods", "render_report", "write_report"]
_HOMES = {
    "compare_methods": "planner.report.compare",
    "render_report": "planner.report.html",
    "write_report": "planner.report.html",
}


def __getattr__(name: str) -> Any:
    if name in _HOMES:
        return getattr(importlib.import_module(_HOMES[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
