"""The package's data files: the checkout's where they stand, else the copies an installed wheel ships."""

from __future__ import annotations

from pathlib import Path

import pytest

from planner.core import resources
from tests.conftest import ROOT


def test_a_checkout_reads_its_own_files():
    assert resources.data_path("models") == ROOT / "models"
    assert resources.data_path("best_known.json") == ROOT / "docs" / "benchmarks" / "best_known.json"


def test_outside_a_checkout_the_wheel_copies_are_read(monkeypatch: pytest.MonkeyPatch, tmp_path: Path):
    monkeypatch.setattr(resources, "_ROOT", tmp_path)  # a root with neither file: an installed wheel
    assert resources.data_path("models") == Path(resources.__file__).resolve().parents[1] / "_data" / "models"


def test_the_build_copies_what_the_package_reads():
    """setup.py takes its list from the module itself, so the wheel holds every file the package reads."""
    assert (
        'run_path(str(Path(__file__).resolve().parent / "planner" / "core" / "resources.py"))["DATA"]'
        in (ROOT / "setup.py").read_text()
    )
    for source in resources.DATA.values():
        assert (ROOT / source).exists(), source
