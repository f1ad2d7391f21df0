"""The help texts speak to a user: no bundled site's name, no lab notes of the sources ("issue 44", "seed 003"),
and ``planner plan --help-all`` stays short: at most 60 settings, at most 4 of them stopping rules."""

from __future__ import annotations

import argparse
import re

import pytest

from planner.cli import build_parser, main
from planner.cli.tuning import TUNING
from planner.core.settings import SETTINGS

#: names of bundled sites and source-document notes that have no place in a help text
FORBIDDEN = re.compile(
    r"polygon[_ ]?[abc]\b|baalbek|building ?27|\bplants?\b|\bhouse\b|\bfzk\b|issue \d+|seed \d{3}", re.IGNORECASE
)
#: what makes a setting a stopping rule: a time, work, budget, move, iteration or node limit
STOPPING = re.compile(r"time-limit|work-limit|-work\b|budget|moves|iters|node-limit")


def _commands() -> list[str]:
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return list(sub.choices)


def _help(capsys, argv: list[str]) -> str:
    assert main(argv) == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("argv", [["--help"], ["plan", "--help-all"]] + [[c, "--help"] for c in _commands()])
def test_no_site_names_or_lab_notes_in_help(capsys, argv):
    text = _help(capsys, argv)
    assert not FORBIDDEN.findall(text), FORBIDDEN.findall(text)


def _plan_settings(capsys) -> tuple[list[str], list[str]]:
    """The options (every one listed, -h, --set, --config and --help-all too) and the tuning keys
    ``planner plan --help-all`` lists."""
    text = _help(capsys, ["plan", "--help-all"])
    head, keys = text.split("\ntuning keys (")
    flags = set(re.findall(r"^  (-[-\w]+)", head, flags=re.MULTILINE))
    return sorted(flags), re.findall(r"^  ([a-z][-a-z]*)[=\[]", keys, flags=re.MULTILINE)


def test_plan_help_all_lists_at_most_60_settings_and_4_stopping_rules(capsys):
    flags, keys = _plan_settings(capsys)
    assert set(keys) == set(TUNING["plan"])
    assert len(flags) + len(keys) <= 60, (len(flags), len(keys))
    stopping = [name for name in flags + keys if STOPPING.search(name)]
    assert len(stopping) <= 4, stopping
    # the schema says the same: its stopping rules are the ones a user sees
    assert sorted(k for k, s in SETTINGS.items() if s.stop) == sorted(n.lstrip("-") for n in stopping)
