"""The data files the package reads beside its code: the instrument models (``models/``) and the table of best
plans known (``docs/benchmarks/best_known.json``).

In a checkout they are read where they stand in the repository, so an edit there is seen at once; an installed
wheel carries a copy of each under ``planner/_data/`` (``setup.py`` puts it there at build time), so a wheel
install reads the same files as the checkout it was built from."""

from __future__ import annotations

from pathlib import Path

#: the repository root of a checkout (the folder holding ``planner/``)
_ROOT = Path(__file__).resolve().parents[2]
#: where a wheel keeps the copies
_PACKAGED = Path(__file__).resolve().parents[1] / "_data"

#: each data file or folder: its place in a checkout, and its name in the wheel's copy
DATA = {"models": Path("models"), "best_known.json": Path("docs") / "benchmarks" / "best_known.json"}


def data_path(name: str) -> Path:
    """The file or folder ``name`` (a key of :data:`DATA`): the checkout's where it exists, else the wheel's."""
    checkout = _ROOT / DATA[name]
    return checkout if checkout.exists() else _PACKAGED / name
