"""The station list for the field: ``ID,X,Y,Z`` in metres, with comment lines saying what they are."""

from __future__ import annotations

from pathlib import Path

from planner.core.checks import argument
from planner.plan.outcome import Outcome
from planner.plan.plan_dict import StationNumbering


def write_stations_csv(outcome: Outcome, path: Path | str, crs: str | None = None) -> Path:
    """Write ``#`` comment lines, the header row ``ID,X,Y,Z`` and one row per station (metres, 3 decimals), by
    number: data row k is station no. k, its ID the station's label, as every file and figure of the plan give them
    (:class:`~planner.plan.plan_dict.StationNumbering`; a comment line says how they are numbered).

    X, Y are in the frame of each station's zone (the frame is named in the comments when a site has more than one, or
    the projected CRS ``crs`` the site was read in); Z is the height of the scanner's centre above the floor, the
    instrument height IH, since a site carries no terrain model.
    """
    argument(outcome, Outcome, "outcome")
    site, p = outcome.site, outcome.site.parameters
    numbering = StationNumbering.recorded(outcome.meta, outcome.stations)
    frames = sorted({s.frame for s in outcome.stations})
    lines = [
        f"# tls-planner station list: {site.name} ({outcome.meta.get('method', '?')}, {len(outcome.stations)} stations)",
        f"# instrument {outcome.validation.scanner.name}; units metres; X, Y in "
        f"{'the projected CRS ' + crs if crs else 'the zone frame'}; "
        f"Z = instrument height above the floor ({p.instrument_height_m:.3f} m)",
        f"# frames: {', '.join(frames)}"
        + ("" if len(frames) == 1 else " (each table zone has its own frame: vertex 1 at 0,0, side 1 along +X)"),
        f"# rows by station number (row k: station no. k), {numbering.legend}",
        "ID,X,Y,Z",
    ]
    lines += [
        f"{numbering.label(s.id)},{s.x:.3f},{s.y:.3f},{p.instrument_height_m:.3f}"
        for s in numbering.ordered(outcome.stations)
    ]
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    return out
