"""Figures (matplotlib, headless: built on :class:`matplotlib.figure.Figure`, never pyplot, so no display
and no global state is needed): plan per zone-side, registration and network, method comparison."""

from planner.figures.compare import comparison_figure
from planner.figures.network_fig import network_figure
from planner.figures.plan_fig import plan_figure, plan_figures

__all__ = ["comparison_figure", "network_figure", "plan_figure", "plan_figures"]
