"""An assembled site written as a JSON instance (``planner assemble --out``)."""

from __future__ import annotations

import os

from planner.site.assemble import AssemblyReport


def assembled_instance(source: dict, source_dir: str, out_dir: str, report: AssemblyReport) -> dict:
    """A JSON instance (as a dict) with the report's placements, table CSV paths made relative to ``out_dir``, and an
    ``assembly`` record of the matches (kept for the reader, not read back)."""
    data = dict(source)
    zones = []
    for entry in data.get("zones", []):
        if isinstance(entry, dict) and "table_csv" in entry:
            entry = dict(entry, table_csv=os.path.relpath(os.path.join(source_dir, entry["table_csv"]), out_dir))
        zones.append(entry)
    data["zones"] = zones
    data["placements"] = {
        z: {
            "origin": [round(p.origin[0], 6), round(p.origin[1], 6)],
            "rotation_deg": round(p.rotation_deg, 8),
            **({"source": report.sources[z]} if z in report.sources else {}),
        }
        for z, p in report.placements.items()
    }
    data["assembly"] = {
        "anchor": report.anchor,
        "tolerance_m": report.tolerance_m,
        "wall_thickness_m": report.wall_thickness_m,
        "matches": [
            {
                "match": m.label,
                "residual_mm": round(m.residual_m * 1000, 2),
                "tolerance_mm": round(m.tolerance_m * 1000, 1),
            }
            for m in report.used
        ],
        "contacts": [
            {"contact": c.label, "overlap_m": round(c.overlap_m, 3), "residual_mm": round(c.residual_m * 1000, 2)}
            for c in report.contacts
        ],
        "refused": [f"{m.label}: {why}" for m, why in report.refused],
        "unplaced": [f"{z}: {why}" for z, why in report.unplaced],
    }
    return data
