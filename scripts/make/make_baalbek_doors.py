"""Write the assembled Baalbek temple with doors: ``instances/baalbek_site_doors.json``.

Table 4.3 gives no openings, so in ``instances/baalbek_site.json`` every room is a closed accessible
area of its own. The courts of the sanctuary are of course entered through doorways, but the print does
not say where. This instance ASSUMES one door ``DOOR_M`` wide at the middle of every wall that
``planner assemble`` matched (the wall between two placed rooms, or a room's wall on the outline,
which then opens to the ground outside), and at the middle of the shared part of every collinear
contact (a side lying along part of a placed zone's wall), in the shorter of the two walls. It is a demonstration of site-wide registration, not a
survey of the real doorways.

    python scripts/make/make_baalbek_doors.py [--out instances/baalbek_site_doors.json]
"""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

import numpy as np

from planner.io.load import load_site

ROOT = Path(__file__).resolve().parents[2]
DOOR_M = 3.0
MATCH = re.compile(r"^(\S+) side (\d+) = (\S+) side (\d+)$")
CONTACT = re.compile(r"^(\S+) side (\d+) along (\S+) side (\d+)$")


def doors(source: Path) -> list[dict]:
    """One door at the middle of the first-named wall of every match of the assembly."""
    data = json.loads(source.read_text())
    site = load_site(source)
    out = []
    for m in data["assembly"]["matches"]:
        za, wa, zb, wb = MATCH.match(m["match"]).groups()  # type: ignore[union-attr]
        length = site.zone(za).walls[int(wa) - 1].length_m
        mid = length / 2
        out.append(
            {
                "zone": za,
                "wall": int(wa),
                "s0_m": round(mid - DOOR_M / 2, 3),
                "s1_m": round(mid + DOOR_M / 2, 3),
                "kind": "door",
                "name": f"assumed door {za}/{wa} - {zb}/{wb}",
            }
        )
    for c in data["assembly"].get("contacts", []):
        za, wa, zb, wb = CONTACT.match(c["contact"]).groups()  # type: ignore[union-attr]
        a, b = site.zone(za).walls[int(wa) - 1], site.zone(zb).walls[int(wb) - 1]
        (z, w, short), long_ = ((za, wa, a), b) if a.length_m <= b.length_m else ((zb, wb, b), a)
        t = (np.array(short.end) - np.array(short.start)) / short.length_m
        s = sorted(float((np.array(p) - np.array(short.start)) @ t) for p in (long_.start, long_.end))
        mid = (max(s[0], 0.0) + min(s[1], short.length_m)) / 2
        out.append(
            {
                "zone": z,
                "wall": int(w),
                "s0_m": round(mid - DOOR_M / 2, 3),
                "s1_m": round(mid + DOOR_M / 2, 3),
                "kind": "door",
                "name": f"assumed door {za}/{wa} - {zb}/{wb} (contact)",
            }
        )
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--source", default=str(ROOT / "instances" / "baalbek_site.json"))
    ap.add_argument("--out", default=str(ROOT / "instances" / "baalbek_site_doors.json"))
    args = ap.parse_args()
    source = Path(args.source)
    data = json.loads(source.read_text())
    data["name"] = "baalbek_site_doors"
    data["description"] = (
        data["description"].rstrip(".") + ". With ASSUMED doors: the print gives no openings; "
        f"one {DOOR_M:g} m door at the middle of every wall the assembly matched or found in contact "
        "(scripts/make/make_baalbek_doors.py), to plan the temple as one registration network."
    )
    data["openings"] = doors(source)
    Path(args.out).write_text(json.dumps(data, indent=2) + "\n")
    print(f"wrote {args.out}: {len(data['openings'])} assumed doors")


if __name__ == "__main__":
    main()
