"""Figures (matplotlib, headless: built on :class:`matplotlib.figure.Figure`, never pyplot, so no display and no global
state is needed): plan per zone-side, the whole site, registration and network, method comparison; point labels placed
so that they never overlap (:mod:`planner.figures.labels`)."""

from planner.figures.compare import comparison_figure
from planner.figures.labels import place_labels
from planner.figures.network_fig import network_figure
from planner.figures.plan_fig import plan_figure, plan_figures
from planner.figures.site_fig import site_figure

__all__ = ["comparison_figure", "network_figure", "place_labels", "plan_figure", "plan_figures", "site_figure"]
