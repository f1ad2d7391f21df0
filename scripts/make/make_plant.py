"""Write a JSON instance of a generated industrial plant (the issue-14 large sites).

The plant is a square of ``--area-ha`` hectares cut into cells of 33 m. Each cell holds one
object, drawn from a seeded generator: a building (rectangle 10-20 x 8-16 m, 6-15 m high), a tank
(a 16-gon of radius 4-8 m, 8-14 m high) or a pipe rack (24-27 x 3-4 m, 6-8 m high, laid along x
or y). Every object is an outside-scanned zone: its outer faces are the targets. Small equipment
(boxes of 1.5-2.5 m, 2 m high, about one cell in three) are obstacles: they block sight and
stations but are not scanned. The 5.5 m or wider strips between objects are the roads (the
accessible area: the boundary less objects, equipment and no-go areas); one no-go area (a
5 x 5 m excavation) per 4 cells, on a road crossing. Parameters: Leica P30, theta_max 70 deg,
overlap 30 %, slant range limited to 60 m (MAX_RANGE_M). An 8 m ring road runs around the cells inside the boundary.

    python scripts/make/make_plant.py --area-ha 4 --seed 0 [--out instances/plant_4ha.json]
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

CELL_M = 33.0
TANK_SIDES = 16
#: slant range limit of a plant survey: the P30 reaches 240 m, but plant scans are registered cloud to
#: cloud, which degrades beyond 30-70 m (seed 003), and a plant's clutter hides most long sight lines
MAX_RANGE_M = 60.0
#: a ring road around the cells, inside the boundary
ROAD_M = 8.0


def _r(v: float) -> float:
    return round(float(v), 2)


def _rect(cx: float, cy: float, w: float, h: float) -> list[list[float]]:
    return [
        [_r(cx - w / 2), _r(cy - h / 2)],
        [_r(cx + w / 2), _r(cy - h / 2)],
        [_r(cx + w / 2), _r(cy + h / 2)],
        [_r(cx - w / 2), _r(cy + h / 2)],
    ]


def _object(kind: str, cx: float, cy: float, rng: np.random.Generator) -> tuple[list[list[float]], float]:
    """Outline (counter-clockwise) and height of one object centred near (cx, cy)."""
    if kind == "tank":
        r = rng.uniform(4.0, 8.0)
        a = 2 * math.pi * np.arange(TANK_SIDES) / TANK_SIDES
        return [[_r(cx + r * math.cos(t)), _r(cy + r * math.sin(t))] for t in a], _r(rng.uniform(8.0, 14.0))
    if kind == "rack":
        w, h = rng.uniform(24.0, 27.0), rng.uniform(3.0, 4.0)
        if rng.random() < 0.5:
            w, h = h, w
        return _rect(cx, cy, w, h), _r(rng.uniform(6.0, 8.0))
    return _rect(cx, cy, rng.uniform(10.0, 20.0), rng.uniform(8.0, 16.0)), _r(rng.uniform(6.0, 15.0))


def plant(area_ha: float, seed: int) -> dict:
    """The instance as a dict (deterministic for ``area_ha`` and ``seed``)."""
    if not area_ha > 0:
        raise ValueError(f"--area-ha must be > 0, got {area_ha}")
    rng = np.random.default_rng(seed)
    n = max(1, round(math.sqrt(area_ha * 10_000.0) / CELL_M))
    side = n * CELL_M
    zones, obstacles, no_go = [], [], []
    kinds = ("building", "tank", "rack")
    for i in range(n):
        for j in range(n):
            cx, cy = (i + 0.5) * CELL_M, (j + 0.5) * CELL_M
            kind = kinds[int(rng.choice(3, p=[0.45, 0.35, 0.20]))]
            jx, jy = rng.uniform(-1.5, 1.5, size=2)
            xy, h = _object(kind, cx + jx, cy + jy, rng)
            zones.append(
                {"id": f"{kind[0].upper()}{i:02d}{j:02d}", "scan_side": "outside", "coordinates": xy, "height_m": h}
            )
            if rng.random() < 1 / 3:  # equipment in a corner of the cell, clear of the object and the roads
                s = rng.uniform(1.5, 2.5)
                corner = rng.choice(4)
                ex = i * CELL_M + (4.0 if corner % 2 == 0 else CELL_M - 4.0)
                ey = j * CELL_M + (4.0 if corner < 2 else CELL_M - 4.0)
                obstacles.append({"name": f"equipment {i:02d}{j:02d}", "polygon": _rect(ex, ey, s, s), "height_m": 2.0})
    for i in range(1, n, 2):
        for j in range(1, n, 2):
            no_go.append({"name": f"excavation {i:02d}{j:02d}", "polygon": _rect(i * CELL_M, j * CELL_M, 5.0, 5.0)})
    return {
        "format": "tls-planner/1",
        "name": f"plant_{area_ha:g}ha",
        "description": (
            f"A generated plant (scripts/make/make_plant.py --area-ha {area_ha:g} --seed {seed}): "
            f"{n} x {n} cells of {CELL_M:g} m, one building, tank or pipe rack per cell scanned from "
            "outside, small equipment as obstacles, roads between the cells as the accessible area, "
            "excavations as no-go areas; an 8 m ring road inside the boundary."
        ),
        "source": "scripts/make/make_plant.py",
        "instrument": "leica-p30",
        "parameters": {"theta_max_deg": 70, "overlap": 0.30, "max_slant_range_m": MAX_RANGE_M},
        "zones": zones,
        "obstacles": obstacles,
        "no_go": no_go,
        "boundary": [
            [-ROAD_M, -ROAD_M],
            [_r(side + ROAD_M), -ROAD_M],
            [_r(side + ROAD_M), _r(side + ROAD_M)],
            [-ROAD_M, _r(side + ROAD_M)],
        ],
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--area-ha", type=float, required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    data = plant(args.area_ha, args.seed)
    out = args.out or Path("instances") / f"plant_{args.area_ha:g}ha.json"
    lines = ",\n".join(json.dumps(z, separators=(",", ":")) for z in data["zones"])
    body = {k: v for k, v in data.items() if k != "zones"}
    text = json.dumps(body, indent=1, separators=(",", ": ")).rstrip("}").rstrip()
    out.write_text(text + f',\n "zones": [\n{lines}\n ]\n}}\n')
    print(
        f"wrote {out}: {len(data['zones'])} objects, {len(data['obstacles'])} obstacles, {len(data['no_go'])} no-go areas"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
