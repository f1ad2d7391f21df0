"""Reading control points and field observations for the network check."""

from __future__ import annotations

from typing import Any

from planner.core.checks import no_repeats
from planner.core.errors import InputError, located_in
from planner.core.fileio import known_keys, read_json, to_float
from planner.network.adjustment import ANGLE_UNITS, KINDS, LENGTH_UNITS, Obs, adjust
from planner.network.check import NetworkReport
from planner.site.model import ControlPoint

#: the keys of a control point entry, of an observation file and of an observation
CONTROL_KEYS = {"name", "x", "y", "z", "sigma_x_mm", "sigma_y_mm"}
OBSERVATION_FILE_KEYS = {"angle_unit", "length_unit", "observations"}
OBSERVATION_KEYS = {"kind", "at", "to", "value", "sigma"}


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
        if isinstance(d["name"], bool) or not isinstance(d["name"], (str, int)) or not str(d["name"]).strip():
            raise InputError("must be a text or a whole number", **where, field="name", value=_shown(d["name"]))
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
    known_keys(data, OBSERVATION_FILE_KEYS, file=path)
    au, lu = data.get("angle_unit", "deg"), data.get("length_unit", "m")
    for key, value, units in (("angle_unit", au, ANGLE_UNITS), ("length_unit", lu, LENGTH_UNITS)):
        if not isinstance(value, str) or value not in units:
            shown = value if isinstance(value, (str, int, float)) else type(value).__name__
            raise InputError(f"unknown unit (known: {', '.join(units)})", file=path, field=key, value=shown)
    g = report.graph
    coords = {n: (d["x"], d["y"]) for n, d in g.nodes(data=True)}
    obs = [_observation(o, k, coords, path) for k, o in enumerate(data["observations"], 1)]
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


def _shown(value: Any) -> Any:
    """A JSON value as a message shows it: text and numbers as found, a list or an object by its kind."""
    return value if isinstance(value, (str, int, float)) or value is None else type(value).__name__


def _observation(o: Any, k: int, coords: dict[Any, Any], path: str) -> Obs:
    """One observation {kind, at, to (not for x and y), value, sigma}, its points named as text."""
    where: dict[str, Any] = dict(file=path, row=f"observations[{k}]")
    if not isinstance(o, dict):
        raise InputError("must be an object {kind, at, to, value, sigma}", **where, value=_shown(o))
    known_keys(o, OBSERVATION_KEYS, **where)
    kind = o.get("kind")
    if not isinstance(kind, str) or kind not in KINDS:
        raise InputError(f"unknown kind (known: {', '.join(KINDS)})", **where, field="kind", value=_shown(kind))
    for key in ("at", "to"):
        point = o.get(key)
        if point is not None and not isinstance(point, str):
            raise InputError("must be a point name (text)", **where, field=key, value=_shown(point))
    if o.get("at") not in coords:
        raise InputError("names no point of the network", **where, field="at", value=_shown(o.get("at")))
    if kind in ("x", "y") and o.get("to") is not None:
        raise InputError(f"an {kind} observation is of one point: give no 'to'", **where, field="to", value=o["to"])
    value, sigma = (to_float(o.get(key), field=key, **where) for key in ("value", "sigma"))
    return Obs(kind, o["at"], o.get("to"), value, sigma)
