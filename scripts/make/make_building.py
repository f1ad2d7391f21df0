"""Write a JSON instance of a building of small rooms in an L-shaped outline (the issue-12 test building).

The L has a 44 x 12 m wing along x and a 12 x 30 m wing up the y axis, walls 4.2 m high, interior walls
0.3 m thick. Each wing is cut into two rows of rooms whose widths (2-7 m) are drawn from a seeded
generator; every room is an inside zone, the outline an outside zone, all in the site frame.

    python scripts/make/make_building.py [--seed 0] [--out instances/building23.json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

WALL_M = 0.3
HEIGHT_M = 4.2


def _cuts(length: float, rng: np.random.Generator) -> list[tuple[float, float]]:
    """Split [0, length] into rooms 2-7 m wide (inner widths), walls of WALL_M between them."""
    out, x = [], WALL_M
    while length - x > 2.0 + WALL_M:
        w = float(rng.uniform(2.0, 7.0))
        if length - WALL_M - (x + w) < 2.0 + WALL_M:  # the rest would be too narrow: take it all
            w = length - WALL_M - x
        out.append((round(x, 2), round(x + w, 2)))
        x += w + WALL_M
    return out


def building(seed: int) -> dict:
    rng = np.random.default_rng(seed)
    rooms = []
    # wing A: x in [12, 44], y in [0, 12], two rows (the corner block x < 12 belongs to wing B)
    rows_a = [(WALL_M, 6.0 - WALL_M / 2), (6.0 + WALL_M / 2, 12.0 - WALL_M)]
    for y0, y1 in rows_a:
        for x0, x1 in _cuts(32.0, rng):
            rooms.append([[12 + x0, y0], [12 + x1, y0], [12 + x1, y1], [12 + x0, y1]])
    # wing B: x in [0, 12], y in [0, 30], two columns
    cols_b = [(WALL_M, 6.0 - WALL_M / 2), (6.0 + WALL_M / 2, 12.0 - WALL_M)]
    for x0, x1 in cols_b:
        for y0, y1 in _cuts(30.0, rng):
            rooms.append([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
    zones = [
        {
            "id": f"R{k:02d}",
            "scan_side": "inside",
            "coordinates": [[round(a, 3), round(b, 3)] for a, b in r],
            "height_m": HEIGHT_M,
        }
        for k, r in enumerate(rooms, 1)
    ]
    outline = [[0, 0], [44, 0], [44, 12], [12, 12], [12, 30], [0, 30]]
    zones.append({"id": "outline", "scan_side": "outside", "coordinates": outline, "height_m": HEIGHT_M})
    return {
        "format": "tls-planner/1",
        "name": f"building{len(rooms)}",
        "description": (
            f"A generated building (scripts/make/make_building.py --seed {seed}): {len(rooms)} rooms 2-7 m "
            "across in an L-shaped outline, walls 4.2 m, interior walls 0.3 m."
        ),
        "source": "scripts/make/make_building.py",
        "instrument": "dissertation-tables",
        "parameters": {"theta_max_deg": 68, "overlap": 0.30},
        "zones": zones,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    data = building(a.seed)
    out = Path(a.out or f"instances/{data['name']}.json")
    out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {out}: {len(data['zones']) - 1} rooms")


if __name__ == "__main__":
    main()
