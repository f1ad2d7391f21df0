"""The self-contained HTML report of a plan (figures embedded as PNG data URIs)."""

from planner.report.compare import compare_methods
from planner.report.html import render_report, write_report

__all__ = ["compare_methods", "render_report", "write_report"]
