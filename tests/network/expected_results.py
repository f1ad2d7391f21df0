"""Expected results of the network check on the bundled instances (GNU Gama style regression files).

Each ``tests/network/expected/<instance>.json`` holds a plan of the instance (its ``stations``, so the
file reads as a plan.json) and the numbers the adjustments of ``run_network`` return for it: per
adjustment the adjusted points (coordinates, sigmas, error ellipse), the redundancy numbers, dof, m0
and the chi-square probability; the registration chain's station errors; and the same design
networks adjusted once more with seeded noise on every observation (``observed=True``), for the
coordinates, residuals, standardised residuals, m0 and the chi-square statistic.

The files were first written by the dense solver (the code before the sparse adjustment); write
them again with the dense solver kept as ``method="dense"``::

    python -m tests.network.expected_results --method dense PLAN.json [PLAN.json ...]

where each plan's file name (``<instance>.json`` or a folder ``<instance>/plan.json``) names the
instance under ``instances/``; ``--registration zone|site`` (default: the site's) is recorded in the file as
``registration``, the scope the numbers hold for (the plants' files: ``zone``, their default before issue 44;
a file without it: the site's default).
"""

from __future__ import annotations

import argparse
import json
import math
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any
from unittest import mock

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
EXPECTED = Path(__file__).resolve().parent / "expected"
#: vectors longer than this are kept as their sum and this many evenly spaced entries
SAMPLE = 400
#: the seed of the noise added to the design observations for the observed adjustment
NOISE_SEED = 0


def vector(v: Sequence[float] | np.ndarray) -> Any:
    """A vector as JSON: in full when short, else its length, sum and ``SAMPLE`` evenly spaced entries."""
    a = np.asarray(v, dtype=float)

    def clean(x: np.ndarray) -> list[float | None]:
        return [None if not math.isfinite(float(y)) else float(y) for y in x]

    if len(a) <= SAMPLE:
        return clean(a)
    idx = np.unique(np.linspace(0, len(a) - 1, SAMPLE).astype(int))
    return {"n": len(a), "sum": float(np.nansum(a)), "index": idx.tolist(), "sample": clean(a[idx])}


def adjustment_numbers(adj: Any) -> dict[str, Any]:
    """The numbers an :class:`~planner.network.adjustment.Adjustment` returns (points, redundancy, tests;
    residuals only for an adjustment of observations: a design has none)."""
    out = {
        "dof": adj.dof,
        "m0": adj.m0,
        "chi2_p": adj.chi2_p,
        "chi2_pass": adj.chi2_pass,
        "n_obs": len(adj.redundancy),
        "points": {
            p.name: [p.x, p.y, p.sigma_x, p.sigma_y, p.ellipse_a, p.ellipse_b, p.ellipse_azimuth_deg]
            for p in adj.points
        },
        "redundancy": vector(adj.redundancy),
    }
    if adj.m0 is not None:
        out.update(residuals=vector(adj.residuals), standardized=vector(adj.standardized))
    return out


def _noisy(obs: Sequence[Any], seed: int) -> list[Any]:
    from planner.network.adjustment import Obs

    e = np.random.default_rng(seed).standard_normal(len(obs))
    return [Obs(o.kind, o.at, o.to, o.value + o.sigma * float(k), o.sigma) for o, k in zip(obs, e)]


def network_numbers(
    site_path: Path | str, plan_path: Path | str, method: str | None = None, registration: str | None = None
) -> dict[str, Any]:
    """Run the network check of the plan on the site and return its numbers (see the module text);
    ``method``: the adjustment's method (None: its default); ``registration``: the scope (None: the site's
    default)."""
    from planner.core.errors import InputError
    from planner.io import load_site
    from planner.io.plan_json import read_plan_stations
    from planner.network import chain, check

    site = load_site(str(site_path))
    stations = read_plan_stations(plan_path, site)
    calls: list[tuple[Any, ...]] = []

    def with_method(real: Callable[..., Any], record: bool) -> Callable[..., Any]:
        def call(coords: Any, fixed: Any, obs: Any, **kw: Any) -> Any:
            if record:
                calls.append((dict(coords), list(fixed), list(obs), dict(kw)))
            return real(coords, fixed, obs, **({**kw, "method": method} if method else kw))

        return call

    with (
        mock.patch.object(check, "adjust", with_method(check.adjust, True)),
        mock.patch.object(chain, "adjust", with_method(chain.adjust, False)),
    ):
        report = check.run_network(site, stations, registration=registration)
    c = report.survey.chain if report.survey is not None else None
    observed: list[dict[str, Any]] = []
    for coords, fixed, obs, kw in calls:
        kw = {**kw, "observed": True, **({"method": method} if method else {})}
        try:
            observed.append(adjustment_numbers(check.adjust(coords, fixed, _noisy(obs, NOISE_SEED), **kw)))
        except InputError as exc:  # a part the design could not adjust either (see failures)
            observed.append({"error": exc.message})
    return {
        "stations_n": len(stations),
        "graph": [report.graph.number_of_nodes(), report.graph.number_of_edges()],
        "failures": list(report.failures),
        "adjustments": [adjustment_numbers(a) for a in report.adjustments],
        "chain": None
        if c is None
        else {"sigma_m": c.sigma_m, "best_tie": c.best_tie, "worst_after_tie_m": c.worst_after_tie_m},
        "sigma_h": report.sigma_h_m,
        "observed": observed,
    }


def write(plan: Path, method: str | None, registration: str | None = None) -> Path:
    """Write ``expected/<instance>.json`` for a plan of ``instances/<instance>.json``, under ``registration``
    (None: the site's default), recorded in the file."""
    from planner.coverage.links import default_registration
    from planner.io import load_site

    name = plan.parent.name if plan.name == "plan.json" else plan.stem
    stations = json.loads(plan.read_text())["stations"]
    keep = [{k: s[k] for k in ("id", "zone", "side", "x", "y", "kind") if k in s} for s in stations]
    EXPECTED.mkdir(exist_ok=True)
    out = EXPECTED / f"{name}.json"
    site_path = ROOT / "instances" / f"{name}.json"
    mode = registration or default_registration(load_site(str(site_path))).mode
    with tempfile.TemporaryDirectory() as folder:
        tmp = Path(folder) / "plan.json"
        tmp.write_text(json.dumps({"stations": keep}))
        numbers = network_numbers(site_path, tmp, method, mode)
    out.write_text(
        dumps(
            {
                "instance": f"instances/{name}.json",
                "method": method or "default",
                "registration": mode,
                "stations": keep,
                "expected": numbers,
            }
        )
    )
    return out


def dumps(obj: Any, depth: int = 0) -> str:
    """JSON with one line per entry down to the second level (diff-friendly, yet small)."""
    if depth >= 2 or not isinstance(obj, (dict, list)) or not obj:
        return json.dumps(obj, separators=(",", ":"))
    pad = " " * (depth + 1)
    if isinstance(obj, dict):
        body = ",\n".join(f"{pad}{json.dumps(k)}: {dumps(v, depth + 1)}" for k, v in obj.items())
        return "{\n" + body + "\n" + " " * depth + "}" + ("\n" if depth == 0 else "")
    body = ",\n".join(f"{pad}{dumps(v, depth + 1)}" for v in obj)
    return "[\n" + body + "\n" + " " * depth + "]"


def main(argv: Sequence[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("plans", nargs="+", type=Path)
    ap.add_argument("--method", default=None, help="the adjustment's method (default: its default)")
    ap.add_argument("--registration", choices=("zone", "site"), default=None, help="default: the site's")
    args = ap.parse_args(argv)
    for plan in args.plans:
        print(write(plan, args.method, args.registration))


if __name__ == "__main__":
    main()
