"""Monte Carlo accuracy of a network design (seed 003): simulate, adjust, repeat."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from planner.network.adjustment import ANGLE_UNITS, LENGTH_UNITS, Obs, adjust
from planner.network.lsq_sparse import Design

#: observation errors are drawn from N(0, sigma) truncated at +-3 sigma (seed 003)
TRUNCATE = 3.0


@dataclass(frozen=True)
class MonteCarlo:
    runs: int
    rms: dict[str, float]  # per point: sqrt(mean(dx^2 + dy^2)) over the runs
    spread: dict[str, float]  # per point: standard deviation of the position error over the runs

    @property
    def mean_rms(self) -> float:
        return math.sqrt(float(np.mean([v**2 for v in self.rms.values()]))) if self.rms else 0.0


def monte_carlo(
    coords: Mapping[str, tuple[float, float]],
    fixed: Sequence[str],
    observations: Sequence[Obs],
    *,
    runs: int = 100,
    seed: int = 0,
    angle_unit: str = "rad",
    length_unit: str = "m",
) -> MonteCarlo:
    """Draw every observation as truth + truncated normal error, adjust, and measure the point errors."""
    if runs < 1:
        raise ValueError("runs must be >= 1")
    rng = np.random.default_rng(seed)
    truth = adjust(coords, fixed, observations, angle_unit=angle_unit, length_unit=length_unit)
    names = [p.name for p in truth.points]
    # the error-free values of every observation at the design coordinates (orientation 0)
    ka, kl = ANGLE_UNITS[angle_unit], LENGTH_UNITS[length_unit]
    xy = np.array([(c[0] * kl, c[1] * kl) for c in coords.values()], dtype=float).reshape(-1, 2)
    _, exact = Design(list(coords), names, observations).jacobian(xy)
    scale = np.array([ka if o.kind == "direction" else kl for o in observations])
    sig = np.array([o.sigma for o in observations])
    errors: dict[str, list[float]] = {n: [] for n in names}
    for _ in range(runs):
        e = rng.standard_normal(len(sig))
        while np.any(np.abs(e) > TRUNCATE):
            bad = np.abs(e) > TRUNCATE
            e[bad] = rng.standard_normal(int(bad.sum()))
        sim = [
            Obs(o.kind, o.at, o.to, exact[i] / scale[i] + sig[i] * e[i], o.sigma) for i, o in enumerate(observations)
        ]
        adj = adjust(coords, fixed, sim, observed=True, angle_unit=angle_unit, length_unit=length_unit)
        for p in adj.points:
            x0, y0 = coords[p.name]
            errors[p.name].append(math.hypot(p.x - x0, p.y - y0))
    rms = {n: math.sqrt(float(np.mean(np.square(v)))) for n, v in errors.items()}
    spread = {n: float(np.std(v)) for n, v in errors.items()}
    return MonteCarlo(runs, rms, spread)
