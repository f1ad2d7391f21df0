"""Plan the KIT AC20-FZK-Haus as one building (walls, floors, ceilings) and draw each storey with its stations.

Usage::

    python scripts/studies/fzk_storey_figures.py [--fzk PATH] [--out docs/figures]

Runs ``planner plan FZK --storey all --surfaces walls,floors,ceilings --out TMP`` (the model is not committed:
docs/ifc.md says where to put it), reads the stations from TMP/plan.json and writes one PNG per storey,
``ifc_fzk_storeys_<storey>.png`` (rooms filled, blocks hatched, doors orange, passages olive, stations as
triangles), printing the stations per storey and room.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from collections import Counter
from pathlib import Path
from types import SimpleNamespace

from planner.cli import main as planner_main
from planner.figures.base import png_bytes
from planner.figures.storey_fig import storey_figure
from planner.io.ifc_in import IfcOptions, read_ifc_site

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fzk", default=str(ROOT / "instances/external/AC20-FZK-Haus.ifc"))
    ap.add_argument("--out", default=str(ROOT / "docs/figures"))
    args = ap.parse_args()
    fzk, out = Path(args.fzk), Path(args.out)
    if not fzk.is_file():
        sys.exit(f"{fzk}: not present (not committed; docs/ifc.md)")
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        cmd = ["plan", str(fzk), "--storey", "all", "--surfaces", "walls,floors,ceilings", "--quiet", "--out", tmp]
        if planner_main(cmd) != 0:
            sys.exit("planner plan failed")
        plan = json.loads((Path(tmp) / "plan.json").read_text())
    site = read_ifc_site(fzk, IfcOptions(storey="all"))
    frame_of = {z.id: z.frame for z in site.zones}
    stations = [
        SimpleNamespace(id=s["id"].rsplit("/", 1)[-1], zone=s["zone"], frame=frame_of[s["zone"]], x=s["x"], y=s["y"])
        for s in plan["stations"]
    ]
    for frame in dict.fromkeys(z.frame for z in site.zones):
        mine = [s for s in stations if s.frame == frame]
        rooms = [z for z in site.zones if z.frame == frame]
        title = (
            f"{fzk.name} --storey all, walls + floors + ceilings: {frame}, {len(rooms)} room{'s' * (len(rooms) != 1)}, "
            f"{len(mine)} of {len(stations)} stations"
        )
        png = out / f"ifc_fzk_storeys_{frame.lower()}.png"
        png.write_bytes(png_bytes(storey_figure(site, stations, frame, title)))
        per_room = Counter(s.zone.rsplit("/", 1)[-1] for s in mine)
        print(f"{frame}: {len(mine)} ({', '.join(f'{k} {v}' for k, v in sorted(per_room.items()))}) -> {png}")


if __name__ == "__main__":
    main()
