"""Hours on site in report.html: the "Hours on site" section of a plan with scan settings: the objective and spacing,
each station's setting, the set-up + scan time with its bound, the spacing check and, for a field-time plan, the
trade-off table and figure. Empty for a plan without settings."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from planner.figures.base import png_bytes
from planner.figures.tradeoff_fig import tradeoff_figure
from planner.plan.hours import no_gain_reason
from planner.plan.outcome import Outcome
from planner.report.markup import esc as _e
from planner.report.markup import image, scroll


def _h(seconds: Any) -> str:
    return "-" if not isinstance(seconds, (int, float)) else f"{seconds / 3600:.2f}"


def hours_section(o: Outcome) -> str:
    """The section's HTML (empty where plan.json has no ``hours``)."""
    h = o.meta.get("hours")
    if not isinstance(h, Mapping):
        return ""
    bound = h.get("setup_scan_bound") or {}
    spacing = h.get("max_point_spacing_m")
    gap = bound.get("gap")
    scope = "every (station, setting) pair of the pool" if h.get("objective") == "field-time" else "these stations"
    lines = [
        ("objective", _e(h.get("objective"))),
        ("point spacing", "none" if spacing is None else f"at most {1e3 * float(spacing):g} mm on every wall"),
        (
            "set-up + scan",
            f"{_h(h.get('setup_scan_s'))} h (set-up {_h(h.get('setup_s'))} h, scan {_h(h.get('scan_s'))} h)",
        ),
        (
            "its bound",
            "-"
            if bound.get("bound_s") is None
            else f"{_h(bound.get('bound_s'))} h over {scope}"
            + ("" if gap is None else f", gap {100 * float(gap):.2f} %"),
        ),
    ]
    check = h.get("spacing")
    if isinstance(check, Mapping):
        worst = check.get("worst_m")
        lines.append(
            (
                "spacing verified",
                f"{float(check.get('percent', 0.0)):.3f} % of the points every {check.get('sampling_m')} m; coarsest "
                + ("-" if worst is None else f"{1e3 * float(worst):.2f} mm"),
            )
        )
    rows = "".join(f'<tr><td class="l">{_e(k)}</td><td class="l">{v}</td></tr>' for k, v in lines)
    out = ["<h2>Hours on site</h2>", scroll(f"<table>{rows}</table>")]
    trade = h.get("tradeoff")
    if isinstance(trade, Mapping):
        out.append(_tradeoff(trade))
    return "".join(out)


def _tradeoff(t: Mapping[str, Any]) -> str:
    rows = list(t.get("rows") or [])
    counted = any(r.get("sessions") is not None for r in rows)
    head: tuple[str, ...] = ("plan", "stations", "set-up h", "scan h", "walking h", "targets h", "total h")
    head += ("sessions", "settings") if counted else ("settings",)
    th = "".join(f'<th class="{"l" if k in (0, len(head) - 1) else ""}">{_e(c)}</th>' for k, c in enumerate(head))
    body = "".join(
        "<tr>"
        + f'<td class="l">{_e(r["label"])}{" <b>(kept)</b>" if r["label"] == t.get("kept") else ""}</td>'
        + f"<td>{'-' if r.get('stations') is None else r['stations']}</td>"
        + "".join(f"<td>{_h(r.get(k))}</td>" for k in ("setup_s", "scan_s", "walking_s", "targets_s", "total_s"))
        + (f"<td>{'-' if r.get('sessions') is None else r['sessions']}</td>" if counted else "")
        + f'<td class="l">{_e(r.get("settings") or r.get("note") or "")}</td></tr>'
        for r in rows
    )
    gain = t.get("gain_s")
    said = (
        f"<p>Gain over the best plan at one setting ({_e(t.get('best_single'))}): {_h(gain)} h.</p>"
        if isinstance(gain, (int, float))
        else f"<p>{_e(_no_gain(rows))}</p>"
    )
    cap = "hours on site per plan: set-up, scan, walking (the field sheet's route) and targets"
    fig = image(png_bytes(tradeoff_figure(rows, str(t.get("kept")))), cap)
    return f"<h3>Trade-off: stations and hours</h3>{scroll(f'<table><tr>{th}</tr>{body}</table>')}{said}{fig}"


def _no_gain(rows: list[dict[str, Any]]) -> str:
    """Why no gain is printed, in the summary's words (:func:`planner.plan.hours.no_gain_reason`)."""
    singles = [r for r in rows if str(r.get("label", "")).startswith("one setting")]
    reason = no_gain_reason(any(r.get("stations") is not None for r in singles))
    return f"{reason[0].upper()}{reason[1:]}."
