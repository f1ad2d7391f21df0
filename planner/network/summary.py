"""The network check as text for the terminal (:meth:`planner.network.check.NetworkReport.summary`): the network's size
and ties, the a priori station error, the notes (alike ones folded into one line with a count,
:func:`planner.core.text.fold_alike`), Monte Carlo, the accuracy check per zone-side as an aligned table in the site's
order, and the network as a scanner survey."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from planner.core.text import fold_alike, table

if TYPE_CHECKING:
    from planner.network.check import NetworkReport


def network_summary(report: NetworkReport, accuracy: bool = True) -> str:
    """``report`` in lines a person reads, one fact a line; ``accuracy``: include the accuracy check's verdict and its
    table per zone-side (the report shows them as its own table, and leaves them out here)."""
    worst = max(report.station_sigma_m.items(), key=lambda kv: kv[1], default=("-", float("nan")))
    c = report.check
    lines = [
        f"network: {report.graph.number_of_nodes()} nodes, {report.graph.number_of_edges()} edges, "
        f"{len(report.diagnostics.components)} part(s), control points {len(report.control)} "
        f"({sum(cp.proposed for cp in report.control)} proposed)",
        f"stations untied to control: {', '.join(report.diagnostics.untied_stations) or 'none'}; "
        f"articulation points: {len(report.diagnostics.articulation_points)}",
        f"a priori station error (least-squares adjustment of the design network): worst {worst[0]} "
        f"{worst[1] * 1000:.2f} mm, network RMS {report.network_rms_m * 1000:.2f} mm"
        if report.station_sigma_m
        else "a priori station error (least-squares adjustment of the design network): none, no part adjusted",
    ]
    names = [str(n) for n in report.graph.nodes] + [str(z["zone"]) for z in report.check.get("zones", [])]
    lines += [f"  not adjusted: {f}" for f in fold_alike(report.failures, names)]
    lines += [f"  note: {n}" for n in fold_alike(report.notes, names)]
    for k, m in enumerate(report.monte_carlo, 1):
        # stations alone, to compare with the a priori network RMS above; all adjusted points beside it
        st = [v for name, v in m.rms.items() if name in report.station_sigma_m]
        st_rms = math.sqrt(float(np.mean(np.square(st)))) if st else float("nan")
        part = f", network part {k} of {len(report.monte_carlo)}" if len(report.monte_carlo) > 1 else ""
        lines.append(
            f"Monte Carlo ({m.runs} runs{part}): station RMS {st_rms * 1000:.2f} mm over {len(st)} stations "
            f"(all {len(m.rms)} adjusted points, control and traverse points included: {m.mean_rms * 1000:.2f} mm)"
        )
    worst_e = (
        f"worst e {c['worst_e_m'] * 1000:.2f} mm" if c["worst_e_m"] is not None else "no piece with a finite error"
    )
    if c.get("untied_targets"):
        worst_e += (
            f" where tied to control; {c['untied_targets']} pieces seen by untied stations only (no finite error)"
        )
    unseen = f"; {c['unseen_targets']} pieces seen by no station" if c.get("unseen_targets") else ""
    survey = report.survey.lines() if report.survey is not None else []
    if not accuracy:
        return "\n".join(lines + survey)
    lines.append(
        f"accuracy check at {c['sigma_req_m'] * 1000:g} mm ({c.get('precision', 'single')} precision): {'PASS' if c['pass'] else 'FAIL'} "
        f"({c['failing_targets']} of {c['targets']} seen pieces fail; {worst_e}{unseen})"
    )
    rows = [
        (
            z["zone"],
            z["side"],
            "pass" if z["pass"] else "FAIL",
            "untied station" if z["untied"] else f"{z['worst_e_m'] * 1000:.2f}",
        )
        for z in c["zones"]
    ]
    lines += table(["zone", "side", "check", "worst e mm"], rows, right=[False, False, False, True])
    lines += [f"  fix: {s}" for s in c["suggestions"]]
    return "\n".join(lines + survey)
