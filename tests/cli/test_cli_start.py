"""The command starts without the numerical stacks: what ``import planner.cli`` loads, --version, choices.

No timing here (timings are measured in scripts/bench/bench_startup.py, docs/startup.md): the test checks
*which* modules the start imports, read from ``python -X importtime``, which is what the time follows.
"""

from __future__ import annotations

import subprocess
import sys

import planner
from planner.core import settings as cli_choices
from tests.conftest import ROOT

#: what --help, --version and argument parsing must not load
HEAVY = (
    "numpy",
    "scipy",
    "shapely",
    "ortools",
    "networkx",
    "matplotlib",
    "ezdxf",
    "ifcopenshell",
    "cvxpy",
    "pulp",
    "highspy",
    "pyproj",
)


def _imported_by(code: str) -> set[str]:
    return _imported_running(["-c", code])


def _imported_running(argv: list[str], exit_code: int = 0) -> set[str]:
    """The modules ``python -X importtime *argv`` imports; it must exit with ``exit_code``."""
    run = subprocess.run([sys.executable, "-X", "importtime", *argv], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == exit_code, run.stderr[-2000:]
    # lines "import time: self | cumulative | <indent>module"
    return {
        line.rsplit("|", 1)[1].strip()
        for line in run.stderr.splitlines()
        if line.startswith("import time:") and "|" in line and not line.rstrip().endswith("imported package")
    }


def test_import_planner_cli_loads_no_numerical_stack():
    mods = _imported_by("import planner.cli; planner.cli.build_parser()")
    top = {m.split(".")[0] for m in mods}
    assert "planner.cli" in mods
    assert not top & set(HEAVY), sorted(top & set(HEAVY))


def test_a_bad_site_or_the_wrong_file_is_refused_before_the_numerical_stacks_load(tmp_path):
    """An invalid JSON site, and a site given where a plan belongs, are refused before numpy, shapely or the
    planning stack load: what the time of these one-line errors follows (docs/startup.md)."""
    bad = tmp_path / "bad.json"
    bad.write_text('{"zones": [')
    for argv, code in (
        (["plan", str(bad), "--out", str(tmp_path / "o"), "--report", str(tmp_path / "r")], 3),
        (["report", str(ROOT / "instances" / "polygon_b.json")], 2),
        (["network", str(ROOT / "instances" / "polygon_b.json"), str(bad)], 3),
    ):
        top = {m.split(".")[0] for m in _imported_running(["-m", "planner", *argv], code)}
        assert not top & set(HEAVY), (argv[0], sorted(top & set(HEAVY)))
    assert not (tmp_path / "o").exists() and not (tmp_path / "r").exists()


def test_version_and_help_exit_0():
    run = subprocess.run([sys.executable, "-m", "planner", "--version"], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0 and run.stdout.strip() == f"planner {planner.__version__}"
    run = subprocess.run([sys.executable, "-m", "planner", "--help"], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0 and "validate" in run.stdout and "--version" in run.stdout


def test_cli_choices_match_the_library():
    from planner.io import EXPORTS
    from planner.io.export import FORMATS
    from planner.plan import METHODS
    from planner.site import ScanSide
    from planner.solve.backends import BACKENDS
    from planner.solve.milp import PRECISION_MODES

    assert cli_choices.METHODS == METHODS and cli_choices.BACKENDS == BACKENDS
    assert cli_choices.PRECISION_MODES == PRECISION_MODES and cli_choices.FORMATS == FORMATS
    assert cli_choices.EXPORTS == EXPORTS and cli_choices.SIDES == tuple(s.value for s in ScanSide)
    from planner.instrument.accuracy import INCIDENCE_MODELS

    assert cli_choices.INCIDENCE_MODELS == INCIDENCE_MODELS
    from planner.plan.options import OBJECTIVES, SURFACES

    assert cli_choices.OBJECTIVES == OBJECTIVES and cli_choices.SURFACES == SURFACES


def test_the_settings_defaults_are_the_option_dataclasses():
    """The schema feeds the option dataclasses' defaults; where a dataclass keeps its own (the window
    re-solves, the tiles), the values the settings derive equal them, so the same defaults reach the library."""
    from dataclasses import asdict

    from planner.plan import PlanOptions
    from planner.plan.options import options_from_settings
    from planner.plan.strategy import TileOptions
    from planner.solve.windows import WindowOptions

    assert options_from_settings({}) == PlanOptions()
    flat = {f"{part}.{k}": v for part, o in (("plan", PlanOptions()), ("milp", PlanOptions().milp)) for k, v in
            asdict(o).items()}  # fmt: skip
    flat |= {f"tiling.{k}": v for k, v in asdict(TileOptions()).items()}
    flat |= {f"windows.{k}": v for k, v in asdict(WindowOptions()).items()}
    flat |= {f"pool.{k}": v for k, v in asdict(PlanOptions().pool).items()}
    flat |= {f"strategy.{k}": v for k, v in asdict(PlanOptions().strategy).items()}
    for path, value in cli_choices.DEFAULTS.items():
        if path in flat and path != "tiling.tile_m":
            assert flat[path] == value, path


def test_lazy_names_are_the_public_names():
    assert set(planner._LAZY) | {"solve"} == set(planner.__all__)
    import importlib

    importlib.import_module("planner.solve.milp")  # loading the subpackage does not rebind planner.solve
    assert callable(planner.solve) and planner.solve.__doc__.startswith("Solve a coverage problem")
