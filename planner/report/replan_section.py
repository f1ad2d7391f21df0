"""What a re-plan changed, in report.html: the "Re-plan" section of a plan.json written by ``planner replan`` (its
``replan``): the stations done, kept, added, dropped (blocked ones said so) and moved, by number and label, the
walls lost with their lengths by zone, and the rest's station count with its bound and the bound's scope. Empty for
a plan that is no re-plan."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

from planner.report.markup import esc as _e
from planner.report.markup import scroll


def replan_section(meta: Mapping[str, Any], number: Callable[[str], int] | None = None) -> str:
    """The section's HTML (empty where ``meta``, a plan.json's data, has no ``replan``); ``number``: a station id's
    number in the report (0: none; default the number plan.json records). A dropped station is not in this plan:
    it is named by its label alone."""
    r = meta.get("replan")
    if not isinstance(r, Mapping) or not isinstance(r.get("changes"), Mapping):
        return ""
    c = r["changes"]
    recorded = {str(s.get("id")): s.get("number") for s in meta.get("stations") or [] if isinstance(s, Mapping)}

    def name(sid: Any) -> str:
        n = number(str(sid)) if number is not None else recorded.get(str(sid))
        return _e(f"{n} {sid}" if isinstance(n, int) and n > 0 else sid)

    def names(ids: Sequence[Any]) -> str:
        return ", ".join(name(i) for i in ids) or "none"

    blocked = set(c.get("blocked") or [])
    dropped = [f"{name(i)}{' (blocked)' if i in blocked else ''}" for i in c.get("dropped") or []]
    moved = [f"{name(m.get('station'))} {float(m.get('distance_m', 0.0)):.2f} m" for m in c.get("moved") or []]
    lost = {str(k): float(v) for k, v in (c.get("walls_lost_m") or {}).items()}
    rest = r.get("rest") or {}
    bound = rest.get("bound")
    lines = [
        ("done", f"{len(c.get('done') or [])}: {names(c.get('done') or [])}"),
        ("kept", f"{len(c.get('kept') or [])}: {names(c.get('kept') or [])}"),
        ("added", f"{len(c.get('added') or [])}: {names(c.get('added') or [])}"),
        ("dropped", f"{len(dropped)}: {', '.join(dropped) or 'none'}"),
        ("moved", f"{len(moved)}: {', '.join(moved) or 'none'}"),
        (
            "walls lost",
            f"{sum(lost.values()):.1f} m"
            + (f" ({', '.join(f'{_e(z)} {m:.1f} m' for z, m in lost.items())})" if lost else ""),
        ),
        (
            "the rest",
            f"{_e(rest.get('stations', '-'))} stations to go; "
            + ("no bound" if bound is None else f"bound {_e(bound)} (scope: {_e(rest.get('bound_scope', 'pool'))})"),
        ),
    ]
    rows = "".join(f'<tr><td class="l">{_e(k)}</td><td class="l">{v}</td></tr>' for k, v in lines)
    return "".join(["<h2>Re-plan</h2>", scroll(f"<table>{rows}</table>")])
