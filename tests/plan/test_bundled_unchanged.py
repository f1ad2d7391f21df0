"""The quick bundled rows of tests/expected/bundled_plans.json, replanned (issue 33: behaviour unchanged by moves).

The recorded table is the one written before the refactor (docs/benchmarks/certificates.md, stop 37); the
slower rows (polygons A and C, Baalbek, the plants) are checked by ``python scripts/checks/check_bundled.py``.
"""

from __future__ import annotations

import importlib.util
import json

import pytest

from tests.conftest import ROOT

_spec = importlib.util.spec_from_file_location("check_bundled", ROOT / "scripts" / "checks" / "check_bundled.py")
check = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(check)  # type: ignore[union-attr]
ROWS = json.loads(check.EXPECTED.read_text())["plans"]
#: each row plans a site twice (seconds each): in the full run only (the quick tier plans B in tests/plan/test_plan*.py)
pytestmark = pytest.mark.slow


@pytest.mark.parametrize("name", ["house_doors", "corridor_200x8"])  # B and the room: tests/plan/test_plan*.py
def test_quick_bundled_row_as_recorded(name, tmp_path):
    # house_doors: 6 stations, optimal, pool bound 6, plain plane bound 5, scope pool (site registration);
    # the 200 x 8 m corridor: 11 stations, both bounds 11, scope plane (issue 31's regression)
    site, extra = check.site_path(name, tmp_path)
    got = check.plan_json(site, extra, tmp_path / "out")
    assert check.differences(name, ROWS[name], got, None) == []
