"""What a re-plan changed against the plan it repairs (:class:`Changes`: stations kept, added, dropped and moved,
walls lost), and which gaps of its verification lie outside the walls it lost (:func:`reachable_gaps`: none for a
sound re-plan)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from planner.coverage.targets import SIDE_NAME
from planner.io.edits import Edits
from planner.plan.verify import Gap, VerifyReport
from planner.site.candidate import Candidate

if TYPE_CHECKING:
    from planner.replanning.rest import RestProblem
    from planner.replanning.source import PlanSource

#: how far (m) a gap of the verification may reach past a lost piece and still be that piece's (the verification
#: samples points, the plan covers pieces: a gap ends at the last point sampled)
GAP_TOL_M = 0.15


@dataclass(frozen=True, kw_only=True)
class Changes:
    """Station ids kept (planned, not done, planned again), added (new), dropped (planned, not done, not planned
    again; blocked ones among them) and moved (done where they really stood, with the distance), and the wall
    length lost by zone/side."""

    done: tuple[str, ...]
    kept: tuple[str, ...]
    added: tuple[str, ...]
    dropped: tuple[str, ...]
    blocked: tuple[str, ...]
    moved: tuple[tuple[str, float], ...]
    lost_m: dict[str, float]

    def lines(self) -> list[str]:
        moved = ", ".join(f"{i} {d:.2f} m" for i, d in self.moved)
        lost = sum(self.lost_m.values())
        return [
            f"changes: {len(self.done)} done, {len(self.kept)} kept, {len(self.added)} added, {len(self.dropped)} "
            f"dropped ({len(self.blocked)} blocked), {len(self.moved)} moved" + (f" ({moved})" if moved else ""),
            f"  added: {', '.join(self.added) or 'none'}",
            f"  dropped: {', '.join(self.dropped) or 'none'}",
            f"  walls lost: {lost:.1f} m"
            + (f" ({', '.join(f'{k} {v:.1f} m' for k, v in self.lost_m.items())})" if lost else ""),
        ]

    def to_dict(self) -> dict[str, Any]:
        return {
            "done": list(self.done),
            "kept": list(self.kept),
            "added": list(self.added),
            "dropped": list(self.dropped),
            "blocked": list(self.blocked),
            "moved": [{"station": i, "distance_m": round(d, 3)} for i, d in self.moved],
            "walls_lost_m": {k: round(v, 3) for k, v in self.lost_m.items()},
        }


def changes_of(
    source: PlanSource, edits: Edits, done: Sequence[Candidate], new: Sequence[Candidate], rest: RestProblem
) -> Changes:
    """The changes of a re-plan whose stations are ``done`` and ``new`` (see :class:`Changes`)."""
    done_ids = {s.id for s in done}
    new_ids = {s.id for s in new}
    planned = [s.id for s in source.planned]
    moved = tuple((e.station.id, math.dist(e.xy, e.station.xy)) for e in edits.done if e.moved)
    return Changes(
        done=tuple(s.id for s in done),
        kept=tuple(i for i in planned if i not in done_ids and i in new_ids),
        added=tuple(s.id for s in new if s.id not in set(planned)),
        dropped=tuple(i for i in planned if i not in done_ids and i not in new_ids),
        blocked=tuple(e.station.id for e in edits.blocked),
        moved=moved,
        lost_m=dict(rest.lost.by_zone),
    )


def reachable_gaps(verification: VerifyReport, rest: RestProblem) -> list[Gap]:
    """The gaps of ``verification`` not inside the pieces the re-plan lost (within :data:`GAP_TOL_M`)."""
    t = rest.coverage.targets
    is_lost = np.zeros(len(t), dtype=bool)
    is_lost[list(rest.lost.pieces)] = True
    merged: dict[tuple[str, str, int], list[tuple[float, float]]] = {}
    for k in np.lexsort((t.s0_m, t.wall, t.side, t.zone)):  # along each wall face: runs of lost pieces
        key = (t.zone_ids[int(t.zone[k])], SIDE_NAME[int(t.side[k])], int(t.wall[k]))
        spans = merged.setdefault(key, [])
        if not is_lost[k]:
            spans.append((math.nan, math.nan))  # a piece still seen ends a run
        elif spans and not math.isnan(spans[-1][0]):
            spans[-1] = (spans[-1][0], float(t.s1_m[k]))  # the run goes on (across an opening, where no piece is)
        else:
            spans.append((float(t.s0_m[k]), float(t.s1_m[k])))
    return [
        g
        for g in verification.gaps
        if not any(
            lo - GAP_TOL_M <= g.from_m and g.to_m <= hi + GAP_TOL_M
            for lo, hi in merged.get((g.zone, g.side, g.wall), [])
        )
    ]
