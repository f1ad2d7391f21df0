"""Do a command's outputs agree? :func:`check_outputs` reads what was written in some folders (``plan.json``,
``field.json``, ``network.json``, ``report.html``; any of them may be missing) and lists where they disagree, so that
a claim is printed only where a check stands behind it:

- **registration pairs**: the network check's registration links are the plan's pairs (plan.json's
  ``registration.links`` where it records them, else the network check's are the reference), the report map's links
  are those of them within one storey (the map draws a storey at a time); the field sheet's links (those the crew
  registers on, a spanning forest) are plan pairs joining the same parts;
- **coverage**: the share plan.json claims is the share its own per-zone counts give, for the walls and for floors and
  ceilings; the report's verification says the same share and the same word;
- **complete** only where nothing was left out (no uncovered stretch or misplaced station; no floor or ceiling patch
  left out, every sample point covered);
- **optimal** only where the status is optimal, and an optimal status only with no gap to its bound;
- **stations**: every file names the plan's stations, and each station's label, where a file gives one, is the
  plan's.

It reads and compares only (no geometry is recomputed), so it is fast, and it never raises: a file it cannot read is
one message.
"""

from __future__ import annotations

import html
import json
import math
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

#: the files a command writes that are checked, by name
FILES = ("plan.json", "field.json", "network.json", "report.html")
#: a relative gap at most this is none (as :data:`planner.solve.result.GAP_TOL`)
GAP_TOL = 1e-6
#: two shares (in %) closer than this agree (the files print three decimals)
PERCENT_TOL = 5e-4

Pair = tuple[str, str]


def check_outputs(folders: Sequence[Path]) -> list[str]:
    """Where the outputs written in ``folders`` disagree, one message each (empty: they agree, or there is nothing to
    compare). Never raises: a file that cannot be read or parsed is a message of its own."""
    found: dict[str, list[Path]] = {name: [] for name in FILES}
    for folder in dict.fromkeys(Path(f) for f in folders):
        for name in FILES:
            path = folder / name
            if path.is_file():
                found[name].append(path)
    out: list[str] = []
    data: dict[Path, Any] = {}
    for name, paths in found.items():
        for path in paths:
            try:
                text = path.read_text(encoding="utf-8")
                data[path] = text if name.endswith(".html") else json.loads(text)
            except (OSError, UnicodeDecodeError, ValueError) as err:
                out.append(f"{path}: cannot be read ({type(err).__name__}: {err})")
    plans = [(p, d) for p in found["plan.json"] if isinstance(d := data.get(p), dict)]
    for path, claims in plans:
        out += _guard(path, _plan_claims, claims)
    plan = plans[0][1] if plans else None
    out += _guard("registration pairs", _pairs, found, data, plan)
    if plan is not None:
        for name in ("field.json", "network.json", "report.html"):
            for path in found[name]:
                out += _guard(path, _against_plan, name, data.get(path), plan)
    return out


def _guard(where: Path | str, check: Callable[..., list[str]], *args: Any) -> list[str]:
    """``check(*args)``'s messages prefixed with ``where``; a file of an unexpected shape is a message, not an
    exception (a file of any shape must give a message, never a traceback)."""
    try:
        return [f"{where}: {m}" for m in check(*args)]
    except Exception as err:
        return [f"{where}: unexpected content ({type(err).__name__}: {err})"]


def _num(x: Any) -> float | None:
    return float(x) if isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) else None


def _share(rows: Iterable[Mapping[str, Any]]) -> tuple[int, int]:
    """(covered, points) summed over per-zone rows."""
    rows = list(rows)
    return sum(int(r.get("covered", 0)) for r in rows), sum(int(r.get("points", 0)) for r in rows)


def _plan_claims(plan: Mapping[str, Any]) -> list[str]:
    """plan.json against itself: each claimed share is its counts' share, "complete" only where nothing is left out,
    "optimal" only with the status optimal and no gap."""
    out: list[str] = []
    v = plan.get("verification")
    if isinstance(v, Mapping):
        covered, points = _share(v.get("zones") or [])
        share, claimed = (100.0 * covered / points if points else 100.0), _num(v.get("percent"))
        if claimed is not None and abs(claimed - share) > PERCENT_TOL:
            out.append(f"verification claims {claimed:.3f} % covered, its zones count {share:.3f} %")
        left = covered < points or bool(v.get("gaps")) or bool(v.get("misplaced"))
        if v.get("complete") is True and left:
            out.append("verification claims complete, yet points are uncovered or stations misplaced")
        if v.get("complete") is False and not left:
            out.append("verification claims incomplete with every point covered and no station misplaced")
    s = plan.get("surfaces")
    if isinstance(s, Mapping):
        out += _surface_claims(s)
    out += _status_claims(plan)
    return out


def _surface_claims(s: Mapping[str, Any]) -> list[str]:
    """The floors and ceilings' share, their "complete" and the patches left out."""
    out: list[str] = []
    v = s.get("verification") or {}
    zones = v.get("zones") or []
    covered, points = _share(zones)
    claimed = _num(v.get("percent"))
    if claimed is not None and points and abs(claimed - 100.0 * covered / points) > PERCENT_TOL:
        out.append(f"surfaces claim {claimed:.3f} % covered, their zones count {100.0 * covered / points:.3f} %")
    unseen = int((s.get("unseen_patches") or {}).get("count") or 0)
    if v.get("complete") is True:
        if unseen:
            out.append(f"surfaces claim complete, yet {unseen} patch(es) were left out (seen by no candidate)")
        if covered < points:
            out.append(f"surfaces claim complete, yet {points - covered:,} of {points:,} points are not covered")
        if not zones:
            out.append("surfaces claim complete, yet no floor or ceiling was verified")
    for z in zones:
        if int(z.get("covered", 0)) + int(z.get("left_out", 0)) > int(z.get("points", 0)):
            out.append(f"surfaces: {z.get('zone')}/{z.get('type')} counts points left out as covered")
    return out


def _status_claims(plan: Mapping[str, Any]) -> list[str]:
    """ "optimal" only with the status optimal and no gap; the field-time objective's status likewise."""
    out: list[str] = []
    status, gap = plan.get("status"), _num(plan.get("gap"))
    if status == "optimal" and gap is not None and gap > GAP_TOL:
        out.append(f"status optimal, yet {gap:.4%} above its bound")
    timing = ((plan.get("hours") or {}).get("setup_scan_bound")) or {}
    t_status, t_gap = timing.get("status"), _num(timing.get("gap"))
    if t_status == "optimal" and t_gap is not None and t_gap > GAP_TOL:
        out.append(f"set-up + scan status optimal, yet {t_gap:.4%} above its bound")
    if (plan.get("hours") or {}).get("objective") == "field-time" and t_status and status != t_status:
        out.append(f"objective field-time: status {status}, yet set-up + scan (what was minimised) is {t_status}")
    return out


def _pair(a: Any, b: Any) -> Pair:
    a, b = str(a), str(b)
    return (a, b) if a <= b else (b, a)


def _pairs_of(name: str, content: Any) -> set[Pair] | None:
    """The registration pairs a file records (None: it records none)."""
    if name == "plan.json":
        links = (content.get("registration") or {}).get("links")
        if links is None:
            return None
        return {_pair(*_ends(x)) for x in links}
    if name == "field.json":
        links = content.get("links")
        return None if links is None else {_pair(*_ends(x)) for x in links}
    if name == "network.json":
        survey = (content.get("survey") or {}).get("links")
        if survey is not None:
            return {_pair(*_ends(x)) for x in survey}
        edges = content.get("edges")
        if edges is None:
            return None
        return {_pair(e["from"], e["to"]) for e in edges if "registration" in (e.get("kinds") or ())}
    layers = re.findall(r'data-layer="links">(.*?)</g>', content, re.S)  # one per storey
    if not layers:
        return None
    return {
        _pair(html.unescape(a), html.unescape(b))
        for layer in layers
        for a, b in re.findall(r'data-a="([^"]*)" data-b="([^"]*)"', layer)
    }


def _ends(x: Any) -> Pair:
    """The two stations of a recorded link: a pair, or a mapping with ``a``/``b`` (``from``/``to``)."""
    if isinstance(x, Mapping):
        return (x["a"], x["b"]) if "a" in x else (x["from"], x["to"])
    a, b = x
    return a, b


def _pairs(found: Mapping[str, list[Path]], data: Mapping[Path, Any], plan: Mapping[str, Any] | None) -> list[str]:
    """Every file's registration pairs against the plan's: plan.json's where it records them, else the network
    check's, else the report's. The report's map draws the pairs within one frame (storey) only, so it is compared
    with those; the field sheet records the links the crew registers on, a spanning forest of the pairs: each of its
    links is a plan pair, and they join the same parts."""
    read: dict[str, list[tuple[str, set[Pair], bool]]] = {name: [] for name in FILES}
    out: list[str] = []
    if plan is not None and (own := _pairs_of("plan.json", plan)) is not None:
        read["plan.json"].append(("plan.json", own, True))
    for name in FILES[1:]:
        for path in found[name]:
            content = data.get(path)
            if content is None or (name != "report.html" and not isinstance(content, Mapping)):
                continue
            try:
                got = _pairs_of(name, content)
            except Exception as err:  # a link of an unexpected shape: named, never raised
                out.append(f"{path}: unexpected registration links ({type(err).__name__}: {err})")
                continue
            if got is not None:  # an order that does not honour registration cuts the sheet's chain, and it says so
                whole = name != "field.json" or content.get("registration_order_honoured") is not False
                read[name].append((str(path), got, whole))
    source = next((name for name in ("plan.json", "network.json", "report.html") if read[name]), None)
    if source is None:
        return out
    ref_name, ref, _ = read[source][0]
    frame = _frames(plan)
    if source == "report.html":  # a view of the pairs within a frame: the others are compared within frames too
        whose = f"{ref_name}'s (pairs within a storey)"
    else:
        whose = "the plan's" if source == "plan.json" else f"{ref_name}'s"
    for name in ("network.json", "report.html"):
        for where, got, _ in read[name]:
            want = _within(ref, frame) if name == "report.html" else ref
            if (where, got) != (ref_name, ref) and got != want:
                out.append(f"{where}: {len(got)} registration pair(s), {whose} {len(want)}; {_diff(want, got)}")
    for where, got, whole in read["field.json"]:
        seen = _within(got, frame) if source == "report.html" else got
        if not seen <= ref:
            out.append(f"{where}: registration links that are no pair of {whose}: {_diff(ref, seen, extra_only=True)}")
        elif whole and source != "report.html" and _parts(got, ref) != _parts(ref, got):
            out.append(f"{where}: its registration links join other parts than {whose} {len(ref)} pair(s)")
    return out


def _frames(plan: Mapping[str, Any] | None) -> dict[str, str]:
    """Each station's frame (storey), from plan.json's stations and zones (empty without a plan)."""
    if plan is None:
        return {}
    zone_frame = {str(z.get("id")): str(z.get("frame")) for z in plan.get("zones") or [] if isinstance(z, Mapping)}
    return {str(s["id"]): zone_frame.get(str(s.get("zone")), "") for s in plan.get("stations") or []}


def _within(pairs: set[Pair], frame: Mapping[str, str]) -> set[Pair]:
    """The pairs whose two stations stand in one frame (all of them where the frames are not known)."""
    return {(a, b) for a, b in pairs if frame.get(a) == frame.get(b)}


def _diff(ref: set[Pair], got: set[Pair], extra_only: bool = False) -> str:
    extra = ", ".join(f"{a} & {b}" for a, b in sorted(got - ref)) or "none"
    if extra_only:
        return extra
    return f"missing {', '.join(f'{a} & {b}' for a, b in sorted(ref - got)) or 'none'}; extra {extra}"


def _parts(pairs: set[Pair], other: set[Pair]) -> set[frozenset[str]]:
    """The connected parts of ``pairs`` over the stations both pair sets name (union-find)."""
    parent = {s: s for pair in pairs | other for s in pair}

    def root(s: str) -> str:
        while parent[s] != s:
            parent[s] = parent[parent[s]]
            s = parent[s]
        return s

    for a, b in pairs:
        parent[root(a)] = root(b)
    groups: dict[str, set[str]] = {}
    for s in parent:
        groups.setdefault(root(s), set()).add(s)
    return {frozenset(g) for g in groups.values()}


def _plan_stations(plan: Mapping[str, Any]) -> dict[str, str]:
    """The plan's station ids and their labels (the id where the file gives none)."""
    return {str(s["id"]): str(s.get("label", s["id"])) for s in plan.get("stations") or []}


def _against_plan(name: str, content: Any, plan: Mapping[str, Any]) -> list[str]:
    """A field sheet, network check or report against the plan: its stations and labels; the report's claims."""
    if content is None:
        return []
    want = _plan_stations(plan)
    if name == "field.json":
        rows = content.get("setups") or []
        got = {str(r["station"]): str(r.get("label", r["station"])) for r in rows if "station" in r}
    elif name == "network.json":
        rows = [n for n in content.get("nodes") or [] if n.get("kind") == "station"]
        got = {str(n["id"]): str(n.get("label", n["id"])) for n in rows}
    else:
        got = _report_stations(content)
    out = _station_messages(want, got)
    if name == "report.html":
        out += _report_claims(content, plan)
    return out


def _report_stations(text: str) -> dict[str, str]:
    """The report map's stations: id -> label (``data-station-label`` or ``data-label`` where given, else the id)."""
    out: dict[str, str] = {}
    for tag in re.findall(r'<g class="sm-st[^"]*"[^>]*>', text):
        sid = re.search(r'data-id="([^"]*)"', tag)
        if sid is None:
            continue
        label = re.search(r'data-(?:station-)?label="([^"]*)"', tag)
        out[html.unescape(sid[1])] = html.unescape(label[1] if label else sid[1])
    return out


def _station_messages(want: Mapping[str, str], got: Mapping[str, str]) -> list[str]:
    if not got:
        return []
    out = []
    if set(got) != set(want):
        missing, extra = sorted(set(want) - set(got)), sorted(set(got) - set(want))
        out.append(
            f"stations differ from plan.json's: missing {', '.join(missing) or 'none'}; extra {', '.join(extra) or 'none'}"
        )
    out += [
        f"station {k} labelled {got[k]!r}, plan.json {want[k]!r}"
        for k in sorted(set(got) & set(want))
        if got[k] != want[k]
    ]
    return out


def _report_claims(text: str, plan: Mapping[str, Any]) -> list[str]:
    """The report's headline status and its verification's word and share, against plan.json."""
    out: list[str] = []
    head = re.search(r"</h1><p>\d+ stations by [^(<]*\(([a-z_ ]+?)[,)]", text)
    status = str(plan.get("status"))
    if head and head[1].split()[0] != status.split()[0]:
        out.append(f"headline says {head[1]!r}, plan.json's status is {status!r}")
    ver = re.search(r"<h2>Verification</h2><p><span[^>]*>(\w+)</span>: ([\d.]+) %", text)
    v = plan.get("verification") or {}
    if ver and isinstance(v, Mapping):
        if (ver[1] == "complete") != bool(v.get("complete")):
            out.append(f"verification says {ver[1]!r}, plan.json's complete is {v.get('complete')}")
        claimed = _num(v.get("percent"))
        if claimed is not None and abs(float(ver[2]) - claimed) > 10 * PERCENT_TOL:
            out.append(f"verification says {ver[2]} %, plan.json {claimed:.3f} %")
    sv = (plan.get("surfaces") or {}).get("verification") or {}
    surf = re.search(r"<h2>Floors and ceilings</h2>.*?<span[^>]*>([\w ]+)</span>: ([\d.]+) %", text, re.S)
    if surf and sv:
        if (surf[1] == "complete") != bool(sv.get("complete")):
            out.append(f"floors and ceilings say {surf[1]!r}, plan.json's complete is {sv.get('complete')}")
        claimed = _num(sv.get("percent"))
        if claimed is not None and abs(float(surf[2]) - claimed) > 10 * PERCENT_TOL:
            out.append(f"floors and ceilings say {surf[2]} %, plan.json {claimed:.3f} %")
    return out
