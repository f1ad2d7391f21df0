"""Registration-chain accuracy (seed 003): scans registered one to the next, held by ties to control.

- a registration link between scans is a relative position with sigma m_reg = 6.8e-5 R + 0.0081 m (R: the stations'
  distance; the overlap rule decides only WHETHER two scans link);
- a tie: a station that scans k targets set on control points takes the control datum with m_t = sqrt(sum m_c,scan_i^2)
  / k (formula 6), each target's error joining the target centre's error from the control survey, m_c (formula 3,
  :func:`target_centre_sigma_m`), and the scanner's error in finding it, m_scan (formula 4,
  :func:`target_scan_sigma_m`).

Each station's a priori error follows from one least-squares adjustment of the links and ties
(:func:`planner.network.adjustment.adjust`); it grows with the links to the nearest tie.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import networkx as nx

from planner.core.errors import InputError
from planner.network.adjustment import Obs, adjust, relative

#: seed 003: cloud-to-cloud registration error m_reg = REG_A * R + REG_B (m)
REG_A, REG_B = 6.8e-5, 0.0081
#: a control point's own position error (m_P) when the instance does not give one (seed 003's estimate)
DEFAULT_CONTROL_SIGMA_M = 0.002
#: field practice (seed 003): targets 10-20 m from the station, one control point per 25-50 m of chain
TIE_RANGE_M = 20.0
CHAIN_PER_CONTROL_M = 50.0
MIN_CONTROL = 3


def registration_sigma_m(length_m: float) -> float:
    """m_reg of a link between two stations ``length_m`` apart (seed 003)."""
    return REG_A * length_m + REG_B


def target_scan_sigma_m(range_m: float, resolution_deg: float) -> float:
    """m_scan of a target centre found in a scan at ``range_m`` (formula 4, printed in mm; returned in m)."""
    if not (range_m > 0 and resolution_deg > 0):
        raise InputError("range and resolution must be > 0", field="target", value=(range_m, resolution_deg))
    return 0.22 * math.exp(0.03 * range_m) * math.exp(5.9 * range_m**0.615 * resolution_deg) / 1000.0


def target_centre_sigma_m(
    control_sigma_m: float, ts_range_m: float, ts_distance_sigma_m: float, ts_angle_arcsec: float
) -> float:
    """m_c of a target centre coordinated from a control point (formula 3)."""
    rho = 206264.806
    meas2 = ts_distance_sigma_m**2 + 2.0 * (ts_range_m * ts_angle_arcsec / rho) ** 2
    return math.sqrt(control_sigma_m**2 + meas2)


def tie_sigma_m(target_ranges_m: Sequence[float], resolution_deg: float, centre_sigma_m: float) -> float:
    """m_t of a station transformed onto k targets at the given ranges (formula 6, as printed)."""
    k = len(target_ranges_m)
    if k == 0:
        raise InputError("a tie needs at least one target", field="tie")
    return math.sqrt(sum(centre_sigma_m**2 + target_scan_sigma_m(r, resolution_deg) ** 2 for r in target_ranges_m)) / k


@dataclass(frozen=True)
class ChainReport:
    """A priori error of each station and its distance in links from control; the weakest chain; the station where one
    more tie (a control point it scans) lowers the worst error most."""

    sigma_m: dict[str, float]
    links_from_control: dict[str, int]
    weakest_chain: tuple[str, ...]
    best_tie: str | None
    worst_after_tie_m: float | None
    untied: tuple[str, ...]

    @property
    def worst(self) -> tuple[str, float]:
        return max(self.sigma_m.items(), key=lambda kv: kv[1], default=("-", math.nan))

    def lines(self) -> list[str]:
        name, worst = self.worst
        out = [
            f"registration chain: worst station {name} {worst * 1000:.2f} mm, "
            f"{self.links_from_control.get(name, -1)} link(s) from control (chain model: each registration link "
            f"adds its error to the stations beyond it; not the adjustment's a priori error)"
        ]
        by_hops: dict[int, list[float]] = {}
        for s, h in self.links_from_control.items():
            by_hops.setdefault(h, []).append(self.sigma_m[s])
        out += [
            f"  {h} link(s) from control: {len(v)} station(s), error up to {max(v) * 1000:.2f} mm"
            for h, v in sorted(by_hops.items())
        ]
        out.append(f"  weakest chain: {' - '.join(self.weakest_chain)}")
        if self.best_tie is not None and self.worst_after_tie_m is not None:
            out.append(
                f"  one more control point (tie) at {self.best_tie}: worst error {worst * 1000:.2f} -> "
                f"{self.worst_after_tie_m * 1000:.2f} mm"
            )
        if self.untied:
            out.append(f"  not tied to control (no datum): {', '.join(self.untied)}")
        return out


def _observations(
    xy: Mapping[str, tuple[float, float]], links: Sequence[tuple[str, str]], ties: Mapping[str, float]
) -> list[Obs]:
    obs = []
    for u, v in links:
        obs += relative(u, v, xy, registration_sigma_m(math.dist(xy[u], xy[v])))
    for st, s in ties.items():
        obs += [Obs("x", st, None, xy[st][0], s), Obs("y", st, None, xy[st][1], s)]
    return obs


def _sigmas(
    xy: Mapping[str, tuple[float, float]], links: Sequence[tuple[str, str]], ties: Mapping[str, float]
) -> dict[str, float]:
    """A priori position error of every station in a part that holds a tie."""
    g = nx.Graph()
    g.add_nodes_from(xy)
    g.add_edges_from(links)
    out: dict[str, float] = {}
    for comp in nx.connected_components(g):
        if not any(s in ties for s in comp):
            continue
        sub_links = [(u, v) for u, v in links if u in comp]
        order = sorted(comp)  # a fixed order of the unknowns (not set order)
        adj = adjust(
            {s: xy[s] for s in order}, [], _observations(xy, sub_links, {s: ties[s] for s in order if s in ties})
        )
        out.update({p.name: p.position_error for p in adj.points})
    return out


def chain_accuracy(
    xy: Mapping[str, tuple[float, float]],
    links: Sequence[tuple[str, str]],
    ties: Mapping[str, float],
    extra_tie_sigma_m: float | None = None,
) -> ChainReport:
    """Station errors of a registration network held by ``ties`` (station -> m_t), and where one more tie of sigma
    ``extra_tie_sigma_m`` (default: the smallest given) helps most."""
    sigma = _sigmas(xy, links, ties)
    g = nx.Graph()
    g.add_nodes_from(xy)
    g.add_edges_from(links)
    g.add_node("<control>")
    g.add_edges_from(("<control>", s) for s in ties)
    # a tied station is one link (its tie) from control
    hops = {s: d for s, d in nx.single_source_shortest_path_length(g, "<control>").items() if s != "<control>"}
    untied = tuple(sorted(s for s in xy if s not in sigma))
    worst = max(sigma, key=lambda s: sigma[s], default=None)
    chain = tuple(nx.shortest_path(g, "<control>", worst)[1:]) if worst is not None else ()
    best, after = None, None
    s_tie = extra_tie_sigma_m if extra_tie_sigma_m is not None else min(ties.values(), default=None)
    if s_tie is not None and worst is not None:
        for st in sorted(sigma):
            if st in ties:
                continue
            trial = max(_sigmas(xy, links, {**ties, st: s_tie}).values())
            if after is None or trial < after - 1e-12:
                best, after = st, trial
    return ChainReport(sigma, {s: h for s, h in hops.items() if s in sigma}, chain, best, after, untied)


def control_count(chain_length_m: float) -> int:
    """Control points a part needs: at least 3, and one per ``CHAIN_PER_CONTROL_M`` of chain (field rule)."""
    return max(MIN_CONTROL, math.ceil(chain_length_m / CHAIN_PER_CONTROL_M))


def place_ties(
    xy: Mapping[str, tuple[float, float]], links: Sequence[tuple[str, str]], sigma_m: float, count: int
) -> dict[str, float]:
    """Choose ``count`` stations of a connected part to tie to control, one at a time where the worst error is (the
    first: the station nearest the part's centre), so ties spread along the chains."""
    names = sorted(xy)
    cx = sum(p[0] for p in xy.values()) / len(xy)
    cy = sum(p[1] for p in xy.values()) / len(xy)
    ties = {min(names, key=lambda s: math.dist(xy[s], (cx, cy))): sigma_m}
    while len(ties) < min(count, len(names)):
        sigma = _sigmas(xy, links, ties)
        ties[max((s for s in sigma if s not in ties), key=lambda s: sigma[s])] = sigma_m
    return ties
