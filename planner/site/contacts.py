"""Zones placed by collinear contacts: sides that lie along (a part of) walls of zones already placed.

A room whose side lengths equal no other zone's side can still be fixed by where its walls run. A *contact* is a side of
the unplaced zone and a side of a placed zone that run along one line (within ``angle_deg`` and ``offset_m``; opposite
directions for two rooms, the same for a room and the outline) and overlap by at least half the shorter. Two
non-parallel contacts fix a placement, but a right-angled corner fits any rectangle, so a zone is placed only when:

- at least ``MIN_CONTACTS`` contacts hold at the fitted placement, in at least two directions;
- its interior overlaps no placed room and stays inside the outline;
- every other placement held by as many contacts fits at least ``RMS_RATIO`` times worse (RMS of the line residuals);
  else it is ambiguous and left unplaced.

The placement is fitted by least squares (the distances of the shorter segment's ends from the longer segment's line,
other zones held); a contact's residual is the larger of its two. A zone that fails a rule stays in its own frame, with
the reason reported.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from planner.site.model import Wall, Zone
from planner.site.placement import Placement, interiors_clash, misfit, normal_sign, tangent_normal

#: contacts a placement needs (a corner alone, two contacts, fits any room)
MIN_CONTACTS = 3
#: the chosen placement's RMS residual must be this many times smaller than any rival's with as many contacts
RMS_RATIO = 2.0
#: sides this many degrees apart count as parallel directions
PARALLEL_DEG = 30.0


@dataclass(frozen=True)
class Contact:
    """Side ``wall`` of ``zone`` lies along side ``other_wall`` of the placed zone ``other``."""

    zone: str
    wall: int
    other: str
    other_wall: int
    length_m: float
    other_length_m: float
    overlap_m: float
    residual_m: float = math.nan

    @property
    def label(self) -> str:
        return f"{self.zone} side {self.wall} along {self.other} side {self.other_wall}"


def _dir(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    return math.atan2(b[1] - a[1], b[0] - a[0])


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _site_walls(zones: dict[str, Zone], placed: dict[str, Placement]) -> list[tuple[Zone, Wall, NDArray[np.float64]]]:
    return [
        (zones[z], w, p.ends(w)) for z, p in placed.items() for w in zones[z].outer_walls if normal_sign(zones[z]) != 0
    ]


def _target_angle(zone: Zone, other: Zone, ends: NDArray[np.float64]) -> float:
    """Direction the unplaced zone's side must run along the placed side ``ends``."""
    d = _dir(ends[0], ends[1])
    return d if normal_sign(zone) != normal_sign(other) else _wrap(d + math.pi)


def _contact(
    zone: Zone,
    w: Wall,
    p: Placement,
    other: Zone,
    ow: Wall,
    ends: NDArray[np.float64],
    angle_deg: float,
    offset_m: float,
) -> Contact | None:
    mine = p.ends(w)
    if abs(_wrap(_dir(mine[0], mine[1]) - _target_angle(zone, other, ends))) > math.radians(angle_deg):
        return None
    t, n = tangent_normal(ends)
    if np.max(np.abs((mine - ends[0]) @ n)) > offset_m:
        return None
    s = sorted((mine - ends[0]) @ t)
    overlap = min(s[1], float(np.hypot(*(ends[1] - ends[0])))) - max(s[0], 0.0)
    if overlap < 0.5 * min(w.length_m, ow.length_m):
        return None
    return Contact(zone.id, w.index, other.id, ow.index, w.length_m, ow.length_m, float(overlap))


def contacts_at(
    zone: Zone, p: Placement, zones: dict[str, Zone], placed: dict[str, Placement], angle_deg: float, offset_m: float
) -> list[Contact]:
    """Every contact of ``zone`` placed at ``p`` with the placed zones."""
    walls = _site_walls(zones, placed)
    found = (
        _contact(zone, w, p, other, ow, ends, angle_deg, offset_m)
        for other, ow, ends in walls
        for w in zone.outer_walls
    )
    return [c for c in found if c is not None]


def _line_residuals(
    zone: Zone, p: Placement, cs: list[Contact], zones: dict[str, Zone], placed: dict[str, Placement]
) -> NDArray[np.float64]:
    """Perpendicular distances of the shorter segment's ends from the longer one's line, per contact."""
    out = []
    for c in cs:
        mine = p.ends(zone.outer_walls[c.wall - 1])
        theirs = placed[c.other].ends(zones[c.other].outer_walls[c.other_wall - 1])
        short, long_ = (mine, theirs) if c.length_m <= c.other_length_m else (theirs, mine)
        out += list((short - long_[0]) @ tangent_normal(long_)[1])
    return np.asarray(out, dtype=float)


def _refine(
    zone: Zone, p: Placement, cs: list[Contact], zones: dict[str, Zone], placed: dict[str, Placement]
) -> Placement:
    def unpack(v: NDArray[np.float64]) -> Placement:
        return Placement((float(v[0]), float(v[1])), float(np.degrees(v[2])))

    x0 = np.array([*p.origin, math.radians(p.rotation_deg)])
    res = least_squares(lambda v: _line_residuals(zone, unpack(v), cs, zones, placed), x0, xtol=1e-12, ftol=1e-12)
    return unpack(res.x).wrapped()


def _seeds(zone: Zone, zones: dict[str, Zone], placed: dict[str, Placement], angle_deg: float) -> list[Placement]:
    """Placements that lay two non-parallel sides of ``zone`` on the lines of two placed sides."""
    walls = _site_walls(zones, placed)
    out = []
    for w1, w2 in itertools.permutations(zone.outer_walls, 2):
        a1, a2 = _dir(np.array(w1.start), np.array(w1.end)), _dir(np.array(w2.start), np.array(w2.end))
        if abs(math.sin(a1 - a2)) < math.sin(math.radians(PARALLEL_DEG)) or w1.index > w2.index:
            continue
        for (o1, ow1, e1), (o2, ow2, e2) in itertools.product(walls, walls):
            if ow1 is ow2:
                continue
            rot = _wrap(_target_angle(zone, o1, e1) - a1)
            if abs(_wrap(_target_angle(zone, o2, e2) - a2 - rot)) > math.radians(angle_deg):
                continue
            r = Placement((0.0, 0.0), math.degrees(rot))
            rows, rhs = [], []
            for w, e in ((w1, e1), (w2, e2)):
                n = tangent_normal(e)[1]
                mid = r.apply([(np.array(w.start) + np.array(w.end)) / 2])[0]
                rows.append(n)
                rhs.append(float(n @ (e[0] - mid)))
            origin = np.linalg.solve(np.array(rows), np.array(rhs))
            out.append(Placement((float(origin[0]), float(origin[1])), math.degrees(rot)))
    return out


def place_by_contacts(
    zone: Zone,
    zones: dict[str, Zone],
    placed: dict[str, Placement],
    *,
    angle_deg: float = 1.0,
    offset_m: float = 0.5,
    consistency_m: float = 0.10,
) -> tuple[Placement | None, list[Contact], str]:
    """The placement of ``zone`` held by collinear contacts (see the module text), its contacts with
    residuals, and a reason (why it was placed, or why not)."""
    if normal_sign(zone) <= 0:
        return None, [], "only rooms (scanned inside) are placed by contacts"
    found: list[tuple[Placement, list[Contact]]] = []
    for seed in _seeds(zone, zones, placed, angle_deg):
        cs = contacts_at(zone, seed, zones, placed, angle_deg, offset_m)
        if len(cs) < 2:
            continue
        p = _refine(zone, seed, cs, zones, placed)
        cs = contacts_at(zone, p, zones, placed, angle_deg, offset_m)
        if len(cs) < MIN_CONTACTS or not _two_directions(zone, cs):
            continue
        if any(interiors_clash(zone, p, zones[z], q) for z, q in placed.items()):
            continue
        p = _refine(zone, p, cs, zones, placed)
        if not any(misfit(p, q, zone) <= consistency_m for q, _ in found):
            found.append((p, cs))
    if not found:
        why = f"no placement holds {MIN_CONTACTS} or more of its sides along placed walls without overlapping"
        return None, [], why + " a placed zone; left in its own frame"
    scored = sorted(
        ((len(cs), _rms(zone, p, cs, zones, placed), p, cs) for p, cs in found), key=lambda f: (-f[0], f[1])
    )
    n, rms, p, cs = scored[0]
    rivals = [f for f in scored[1:] if f[0] == n]
    if rivals and rivals[0][1] < RMS_RATIO * rms:
        why = f"ambiguous: {len(rivals) + 1} placements are held by {n} contacts each and fit about as well"
        return None, [], why + f" (RMS {rms * 1000:.0f} and {rivals[0][1] * 1000:.0f} mm); left in its own frame"
    r = _line_residuals(zone, p, cs, zones, placed).reshape(-1, 2)
    cs = [replace(c, residual_m=float(np.max(np.abs(k)))) for c, k in zip(cs, r)]
    why = f"placed by {n} collinear contacts, RMS {rms * 1000:.0f} mm"
    if rivals:
        why += (
            f"; {len(rivals)} other placement(s) with {n} contacts fit at RMS {rivals[0][1] * 1000:.0f} mm "
            f"or worse (more than {RMS_RATIO:g} x)"
        )
    others = [f for f in scored[1:] if f[0] < n]
    why += f"; the next placement has {others[0][0]} contacts" if others else ""
    return p, cs, why


def _rms(zone: Zone, p: Placement, cs: list[Contact], zones: dict[str, Zone], placed: dict[str, Placement]) -> float:
    return float(np.sqrt(np.mean(np.square(_line_residuals(zone, p, cs, zones, placed)))))


def _two_directions(zone: Zone, cs: list[Contact]) -> bool:
    """True when two of the contacts' sides are at least ``PARALLEL_DEG`` apart (they fix both translations)."""
    walls = [zone.outer_walls[c.wall - 1] for c in cs]
    ang = [_dir(np.array(w.start), np.array(w.end)) for w in walls]
    return any(abs(math.sin(a - b)) >= math.sin(math.radians(PARALLEL_DEG)) for a, b in itertools.combinations(ang, 2))


def place_unmatched(
    zones: dict[str, Zone], placed: dict[str, Placement], todo: list[str]
) -> tuple[dict[str, tuple[Placement, str]], list[Contact], dict[str, str]]:
    """Zones of ``todo`` placed by contacts, in rounds (a zone placed may hold the next); the placements
    with their reasons, the contacts used, and why each zone left over was not placed."""
    done: dict[str, tuple[Placement, str]] = {}
    used: list[Contact] = []
    why_not: dict[str, str] = {}
    while True:
        now = {**placed, **{z: p for z, (p, _) in done.items()}}
        tries = {z: place_by_contacts(zones[z], zones, now) for z in todo if z not in done}
        why_not.update({z: t[2] for z, t in tries.items() if t[0] is None})
        ok = [(z, t[0], t[1], t[2]) for z, t in tries.items() if t[0] is not None]
        if not ok:
            break
        # one zone per round, the best held (most contacts); the others are tried again against it
        z, p, cs, why = max(ok, key=lambda t: len(t[2]))
        assert p is not None
        done[z] = (p, why + ": " + ", ".join(c.label for c in cs))
        used += cs
        why_not.pop(z, None)
    return done, used, why_not
