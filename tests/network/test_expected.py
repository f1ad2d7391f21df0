"""The network check of every bundled instance gives the numbers of the dense solver (expected/*.json).

The expected files were written by the dense adjustment before the sparse one replaced it
(:mod:`tests.network.expected_results` says how to write them again). Everything is compared to
1e-9 (metres, degrees, redundancy numbers, m0, probabilities); an ellipse's azimuth only where the
ellipse is not a circle (a^2 - b^2 > 1e-4 a^2: of a circle the azimuth is any).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest

from tests.network.expected_results import EXPECTED, ROOT, network_numbers

TOL = 1e-9
FILES = sorted(EXPECTED.glob("*.json"))
#: the recorded networks that take seconds to recompute: only in the full run (pytest -m slow)
SLOW = {
    "plant_4ha",
    "plant_1ha",
    "baalbek",
    "baalbek_site",
    "baalbek_site_doors",
    "building27",
    "polygon_a",
    "polygon_c",
}


def differences(want: Any, got: Any, where: str = "", tol: float = TOL) -> list[tuple[str, float]]:
    """(place, difference) for every number of ``got`` off ``want`` by more than ``tol`` (inf: a mismatch of
    kind, length or key)."""
    if isinstance(want, dict) and isinstance(got, dict):
        if set(want) != set(got):
            return [(f"{where} keys {sorted(set(want) ^ set(got))[:5]}", math.inf)]
        if "sample" in want:  # a long vector: its length, sum and samples
            out = [d for k in ("n", "index", "sample") for d in differences(want[k], got[k], f"{where}.{k}", tol)]
            if not abs(want["sum"] - got["sum"]) <= tol * want["n"]:
                out.append((f"{where}.sum", abs(want["sum"] - got["sum"])))
            return out
        return [d for k in want for d in differences(want[k], got[k], f"{where}.{k}", tol)]
    if isinstance(want, list) and isinstance(got, list):
        if len(want) != len(got):
            return [(f"{where} length {len(want)} != {len(got)}", math.inf)]
        if len(want) == 7 and where.count(".points.") == 1 and all(isinstance(v, float) for v in want + got):
            return _point(want, got, where, tol)
        return [d for k, (a, b) in enumerate(zip(want, got)) for d in differences(a, b, f"{where}[{k}]", tol)]
    if isinstance(want, (int, float)) and isinstance(got, (int, float)) and not isinstance(want, bool):
        d = abs(float(want) - float(got))
        return [(where, d)] if not d <= tol else []
    return [] if want == got else [(f"{where}: {want!r} != {got!r}", math.inf)]


def _point(want: list[float], got: list[float], where: str, tol: float) -> list[tuple[str, float]]:
    """x, y, sigma_x, sigma_y, a, b to ``tol``; the azimuth (degrees, modulo 180) where the ellipse is no circle."""
    out = [(f"{where}[{k}]", abs(a - b)) for k, (a, b) in enumerate(zip(want[:6], got[:6])) if not abs(a - b) <= tol]
    a, b = want[4], want[5]
    if a * a - b * b > 1e-4 * a * a:
        d = abs((want[6] - got[6] + 90.0) % 180.0 - 90.0)
        if not d <= tol:
            out.append((f"{where}.azimuth", d))
    return out


def max_difference(want: Any, got: Any) -> float:
    """The largest difference of any number (0 where all are equal), for the report of a comparison."""
    return max((d for _, d in differences(want, got, tol=-1.0)), default=0.0)


@pytest.mark.parametrize(
    "path", [pytest.param(p, id=p.stem, marks=[pytest.mark.slow] if p.stem in SLOW else []) for p in FILES]
)
def test_network_results_equal_the_dense_ones(path: Path):
    data = json.loads(path.read_text())
    # the file reads as a plan (its stations); the scope it was written under where it names one (the plants: zone,
    # their default before issue 44), else the site's default
    got = network_numbers(ROOT / data["instance"], path, registration=data.get("registration"))
    bad = differences(data["expected"], got)
    assert not bad, f"{len(bad)} numbers differ from {path.name}, e.g. {bad[:5]}"


def test_the_comparison_sees_a_change():
    want = {
        "points": {"P": [1.0, 2.0, 0.001, 0.002, 0.0021, 0.0009, 30.0]},
        "r": {"n": 3, "sum": 1.5, "index": [0, 2], "sample": [0.5, 0.25]},
    }
    same = json.loads(json.dumps(want))
    assert differences(want, same) == []
    same["points"]["P"][6] = 210.0 - 1e-12  # the same axis, a half turn on
    assert differences(want, same) == []
    moved = json.loads(json.dumps(want))
    moved["points"]["P"][2] += 1e-8
    moved["r"]["sample"][1] = None
    assert [w for w, _ in differences(want, moved)] == [".points.P[2]", ".r.sample[1]: 0.25 != None"]
