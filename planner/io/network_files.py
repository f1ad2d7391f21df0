"""Reading control points and field observations for the network check."""

from __future__ import annotations

from typing import Any

from planner.core.checks import no_repeats
from planner.core.errors import InputError, located_in
from planner.core.fileio import known_keys, read_json, to_float
from planner.network.adjustment import ANGLE_UNITS, KINDS, LENGTH_UNITS, Obs, adjust
from planner.network.check import NetworkReport
from planner.site.model import ControlPoint

#: the keys of a control point entry
CONTROL_KEYS = {"name", "x", "y", "z", "sigma_x_mm", "sigma_y_mm"}


def read_control(path: str) -> list[ControlPoint]:
    """A JSON list of {name, x, y, z?, sigma_x_mm?, sigma_y_mm?} (sigmas 0: fixed)."""
    data = read_json(path)
    if not isinstance(data, list) or not data:
        raise InputError("must be a non-empty list of control points", file=path)
    out = []
    for k, d in enumerate(data, 1):
        where: dict[str, Any] = dict(file=path, row=f"control[{k}]")
        if not isinstance(d, dict) or "name" not in d:
            raise InputError("needs a name, x and y", **where)
        known_keys(d, CONTROL_KEYS, **where)
        with located_in(path):  # a point's own check (coordinates within +-1e8 m) names the file too
            out.append(
                ControlPoint(
                    str(d["name"]),
                    to_float(d.get("x"), field="x", **where),
                    to_float(d.get("y"), field="y", **where),
                    sigma_x_m=to_float(d.get("sigma_x_mm", 0), field="sigma_x_mm", **where) / 1000,
                    sigma_y_m=to_float(d.get("sigma_y_mm", 0), field="sigma_y_mm", **where) / 1000,
                )
            )
    no_repeats((c.name for c in out), what="control point name", field="name", row="control[{}]", file=path)
    return out


def adjust_observations(report: NetworkReport, path: str) -> str:
    """Adjust field observations ({angle_unit, length_unit, observations: [{kind, at, to, value, sigma}]}) on the
    network's design coordinates; returns a text summary with m_0, the chi-square test and the largest standardised
    residual."""
    data = read_json(path)
    if not isinstance(data, dict) or not isinstance(data.get("observations"), list):
        raise InputError("needs an object with a list 'observations'", file=path)
    au, lu = data.get("angle_unit", "deg"), data.get("length_unit", "m")
    if au not in ANGLE_UNITS or lu not in LENGTH_UNITS:
        raise InputError("unknown unit", file=path, field="angle_unit/length_unit", value=f"{au}/{lu}")
    g = report.graph
    coords = {n: (d["x"], d["y"]) for n, d in g.nodes(data=True)}
    obs = []
    for k, o in enumerate(data["observations"], 1):
        where: dict[str, Any] = dict(file=path, row=f"observations[{k}]")
        if not isinstance(o, dict) or o.get("kind") not in KINDS or o.get("at") not in coords:
            raise InputError(
                "needs a kind and a known point 'at'", **where, value=o.get("kind") if isinstance(o, dict) else o
            )
        value, sigma = (to_float(o.get(key), field=key, **where) for key in ("value", "sigma"))
        obs.append(Obs(o["kind"], o["at"], o.get("to"), value, sigma))
    fixed = [c.name for c in report.control if c.sigma_x_m == 0 and c.sigma_y_m == 0]
    adj = adjust(coords, fixed, obs, observed=True, angle_unit=au, length_unit=lu)
    lines = [
        f"adjustment of {len(obs)} observations: m0 {adj.m0:.3f}, dof {adj.dof}, chi-square p {adj.chi2_p:.3f} "
        f"({'pass' if adj.chi2_pass else 'FAIL'})"
        if adj.m0 is not None
        else "adjustment: no redundancy"
    ]
    w = adj.worst_residual()
    if w is not None:
        o = obs[w[0]]
        lines.append(
            f"largest standardised residual {w[1]:+.2f} on {o.kind} {o.at}->{o.to}"
            + (" (suspect: |w| > 3.29)" if abs(w[1]) > 3.29 else "")
        )
    lines += [f"  {p.name}: x {p.x:.4f} y {p.y:.4f} sigma {p.position_error * 1000:.2f} mm" for p in adj.points]
    return "\n".join(lines)
