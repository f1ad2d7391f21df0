"""The registration of a run (:class:`Registration`): its scope, its rules and its link reach, decided once
(:meth:`Registration.of`, which :func:`planner.plan.problem.resolve` calls) and read by every stage that groups, relates
or checks stations: the planning methods, the tiles, the registration check, the field sheet, the network check and the
report's map, so that all of them find the same pairs."""

from __future__ import annotations

from collections.abc import Hashable, Sequence
from dataclasses import dataclass
from typing import Any

import networkx as nx
import numpy as np
import scipy.sparse as sp

from planner.core.errors import UsageError
from planner.coverage.links import REGISTRATION_MODES, default_registration, registration_groups
from planner.coverage.matrix import CoverageProblem
from planner.coverage.overlap import OverlapRule, overlap_graph, piece_lengths, rule_of
from planner.coverage.sight import Sight
from planner.site.candidate import Candidate
from planner.site.model import Site


@dataclass(frozen=True, kw_only=True)
class Registration:
    """How a run's stations register. ``mode``: ``zone`` (one bundle per zone-side) or ``site`` (one per accessible
    area, linked through openings and stairs), ``reason`` why; ``rule``: the rule the plan must meet (None: none asked
    for, or overlap share 0); ``checked_rule``: the rule its registration is checked and reported on (the planning rule,
    else the site's share); ``reach_m``: how far a link through an opening or a stair reaches (the checked rule's
    ``max_link_m``, else the sight's effective range)."""

    site: Site
    mode: str
    reason: str
    rule: OverlapRule | None
    checked_rule: OverlapRule
    reach_m: float

    def __post_init__(self) -> None:
        if self.mode not in REGISTRATION_MODES:
            known = ", ".join(REGISTRATION_MODES)
            raise UsageError(f"unknown registration mode (known: {known})", field="registration", value=self.mode)

    @classmethod
    def of(
        cls,
        sight: Sight,
        mode: str | None = None,
        rule: OverlapRule | None = None,
        checked: OverlapRule | None = None,
        reason: str | None = None,
    ) -> Registration:
        """The registration of ``sight``'s site: ``mode`` as asked (None: the site's default,
        :func:`planner.coverage.links.default_registration`), the planning ``rule``, and the ``checked`` rule (None: the
        planning rule, else the site's overlap share)."""
        site = sight.site
        if mode is None:
            default = default_registration(site)
            mode, reason = default.mode, default.reason
        checked = checked or rule or rule_of(site.parameters.overlap)
        reach = checked.max_link_m or sight.limits.effective_range_m
        return cls(site=site, mode=mode, reason=reason or "asked for", rule=rule, checked_rule=checked, reach_m=reach)

    def groups(self, candidates: Sequence[Candidate]) -> tuple[tuple[Hashable, ...], sp.csr_matrix | None]:
        """The registration group of each candidate and the links through openings and stairs (None in ``zone`` mode):
        :func:`planner.coverage.links.registration_groups` at this scope and reach."""
        return registration_groups(self.site, candidates, self.mode, self.reach_m)

    def _graphs(
        self, stations: Sequence[Candidate], by_candidate: sp.csr_matrix, lengths: np.ndarray
    ) -> list[tuple[Hashable, list[int], nx.Graph]]:
        """Each group's label, its stations (indices into ``stations``, the rows of ``by_candidate``) and their overlap
        graph under the checked rule."""
        labels, links = self.groups(stations)
        xy = np.array([s.xy for s in stations], dtype=float).reshape(-1, 2)
        groups: dict[Hashable, list[int]] = {}
        for i, label in enumerate(labels):
            groups.setdefault(label, []).append(i)
        return [
            (label, nodes, overlap_graph(by_candidate, lengths, nodes, self.checked_rule, xy, links))
            for label, nodes in groups.items()
        ]

    def relation(self, stations: Sequence[Candidate], coverage: CoverageProblem) -> nx.Graph:
        """The registration relation of ``stations`` (node = index into them; ``coverage``: theirs, rows in their
        order): each edge has ``shared_m`` (wall both see) and ``fraction`` (of the smaller station's covered wall). The
        field sheet, the network check and the report's map read the plan's pairs here."""
        lengths = piece_lengths(coverage.targets.s0_m, coverage.targets.s1_m)
        covered = np.asarray(coverage.by_candidate.astype(np.float64) @ lengths).ravel()
        g = nx.Graph()
        g.add_nodes_from(range(len(stations)))
        for _, _, sub in self._graphs(stations, coverage.by_candidate, lengths):
            for u, v, data in sub.edges(data=True):
                small = min(covered[u], covered[v])
                g.add_edge(u, v, shared_m=data["shared_m"], fraction=data["shared_m"] / small if small > 0 else 0.0)
        return g

    def check(self, coverage: CoverageProblem, selected: Sequence[int]) -> tuple[dict[str, int], dict[int, list[int]]]:
        """The components of each registration group's chosen stations (``selected``: rows of ``coverage``) under the
        checked rule, computed afresh with networkx (independent of any solver), and each station's registration
        partners (candidate indices)."""
        selected = tuple(selected)
        chosen = [coverage.candidates[i] for i in selected]
        lengths = piece_lengths(coverage.targets.s0_m, coverage.targets.s1_m)
        sub = coverage.by_candidate[list(selected)] if selected else coverage.by_candidate[:0]
        out, partners = {}, {}
        for label, nodes, g in self._graphs(chosen, sub, lengths):
            out[self._key(label, [chosen[k] for k in nodes])] = nx.number_connected_components(g)
            partners.update({selected[n]: sorted(selected[m] for m in g.neighbors(n)) for n in nodes})
        return out, partners

    def _key(self, label: Any, stations: Sequence[Candidate]) -> str:
        """A group's name in the check: ``zone/side``, or ``area k`` with up to four of its zone-sides."""
        if self.mode == "zone":
            return "/".join(label)
        names = sorted({f"{s.zone}/{s.side.value}" for s in stations})
        return f"area {label[1]} ({', '.join(names[:4])}{', ...' if len(names) > 4 else ''})"

    def line(self) -> str:
        """The rule and scope, with why, in one line."""
        rule = self.rule
        text = (
            f"overlap {rule.overlap:.0%}"
            + (f", at least {rule.min_shared_m:g} m shared" if rule.min_shared_m else "")
            + (f", links up to {rule.max_link_m:g} m" if rule.max_link_m else "")
            if rule
            else "none"
        )
        return f"registration rule: {text}; scope {self.mode} ({self.reason})"
