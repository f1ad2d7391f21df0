"""What a re-plan needs from its plan, kept beside plan.json (``replan.npz``, written by ``planner plan --out``): the
pool's candidates, their coverage of the wall pieces (CSR, with the worst slant range and incidence of each pair),
the registration group and links of each candidate, and the rows of the plan's own stations. With it ``planner
replan`` only filters and re-solves; without it (or where it no longer fits the site and options) the pool is built
again, and the command says so. The overlap relation is not kept: it is a pairwise function of the rows' coverage,
groups and links (:func:`relation_of`), made by the re-plan over the candidates the edits leave (fewer pairs than the
whole pool's, and off the plan's own path).

Its ``key`` names what it was made for: the instance, the wall pieces (:func:`planner.coverage.fingerprint.
pool_fingerprint` of no candidates over the targets: the site's walls and openings at the target spacing) and the
options that decide coverage and the relation (limits, rule, scope, spacing). A file whose key differs from the
one the re-plan computes is not used."""

from __future__ import annotations

import json
import zipfile
from collections.abc import Hashable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from planner.coverage.fingerprint import pool_fingerprint
from planner.coverage.matrix import CoverageProblem, build_coverage
from planner.coverage.overlap import overlap_adjacency
from planner.coverage.targets import Targets
from planner.plan.problem import Problem
from planner.site.candidate import Candidate, CandidateKind
from planner.site.model import ScanSide

#: the file's name in a plan's folder, and its format tag
FILE_NAME = "replan.npz"
FORMAT = "planner-replan/2"
KINDS = tuple(CandidateKind)
#: deflate level of the file: 1 writes the pool in about 60 % of the default level's time, 4 % larger
ZIP_LEVEL = 1
SIDES = (ScanSide.INSIDE, ScanSide.OUTSIDE, ScanSide.BOTH)


@dataclass(frozen=True, kw_only=True, eq=False)
class ReplanData:
    """The pool of a plan as a re-plan takes it: ``coverage`` (candidates x the site's wall pieces), each
    candidate's registration ``groups`` and ``links`` through openings (None in zone scope), ``plan_rows`` (the
    plan's stations as rows of the pool, in plan.json order) and the ``key`` it was made for."""

    coverage: CoverageProblem
    groups: tuple[Hashable, ...]
    links: sp.csr_matrix | None
    plan_rows: tuple[int, ...]
    key: dict[str, Any]


def data_key(problem: Problem, targets: Targets) -> dict[str, Any]:
    """What a replan.npz is made for (see the module text): equal keys, the same pool and relation."""
    o, lim, rule = problem.options, problem.limits, problem.rule
    return {
        "format": FORMAT,
        "instance": problem.site.name,
        "targets": pool_fingerprint((), targets),
        "target_spacing_m": o.target_spacing_m,
        "max_slant_range_m": lim.max_slant_range_m,
        "theta_max_deg": lim.theta_max_deg,
        "incidence_3d": lim.incidence_3d,
        "precision": None if lim.precision is None else ("combined" if lim.precision.combined else "single"),
        "registration": problem.registration.mode,
        "rule": None if rule is None else [rule.overlap, rule.min_shared_m, rule.max_link_m],
        "reach_m": problem.registration.reach_m,
    }


def pool_with_stations(
    pool: CoverageProblem, stations: Sequence[Candidate], problem: Problem
) -> tuple[CoverageProblem, tuple[int, ...]]:
    """``pool`` without the candidates that stand nowhere, with the ``stations`` that are not in it (by position,
    zone and side) appended and those that are under their own ids; and the rows of the stations."""
    keep = [k for k in range(len(pool.candidates)) if k not in pool.excluded]
    cands = [pool.candidates[k] for k in keep]
    by = pool.by_candidate[keep]
    slant, inc = pool.slant_m[keep], pool.incidence_deg[keep]
    at = {(round(c.x, 6), round(c.y, 6), c.zone, c.side, c.frame): k for k, c in enumerate(cands)}
    rows: list[int] = []
    extra: list[Candidate] = []
    for s in stations:
        k = at.get((round(s.x, 6), round(s.y, 6), s.zone, s.side, s.frame))
        if k is None:
            k = len(cands) + len(extra)
            extra.append(s)
        else:  # the plan's station under its own id
            cands[k] = s
        rows.append(k)
    if extra:
        more = build_coverage(problem.site, extra, pool.targets, problem.limits)
        cands += list(more.candidates)
        by = sp.vstack([by, more.by_candidate]).tocsr()
        slant, inc = sp.vstack([slant, more.slant_m]).tocsr(), sp.vstack([inc, more.incidence_deg]).tocsr()
    return _problem(tuple(cands), pool.targets, by, slant, inc, pool), tuple(rows)


def _problem(
    cands: tuple[Candidate, ...], targets: Targets, by: Any, slant: Any, inc: Any, like: Any
) -> CoverageProblem:
    by = sp.csr_matrix(by, dtype=bool)
    return CoverageProblem(
        candidates=cands,
        targets=targets,
        by_candidate=by,
        by_target=by.T.tocsr(),
        slant_m=sp.csr_matrix(slant),
        incidence_deg=sp.csr_matrix(inc),
        excluded={},
        limits=like.limits,
    )


def relation_of(problem: Problem, coverage: CoverageProblem, groups: Sequence[Hashable], links: Any) -> Any:
    """The overlap relation of ``coverage``'s candidates under the problem's rule (None: no rule)."""
    if problem.rule is None:
        return None
    t = coverage.targets
    xy = np.array([c.xy for c in coverage.candidates], dtype=float).reshape(-1, 2)
    adj, _ = overlap_adjacency(coverage.by_candidate, t.s1_m - t.s0_m, problem.rule, groups, xy, links)
    return adj


def make_replan_data(problem: Problem, pool: CoverageProblem, stations: Sequence[Candidate]) -> ReplanData:
    """The re-plan's data of a plan: ``pool`` (the coverage the plan was chosen from, as built) with the plan's
    ``stations`` added where they are not in it, their registration groups and links."""
    cov, rows = pool_with_stations(pool, stations, problem)
    groups, links = problem.registration.groups(cov.candidates)
    key = data_key(problem, cov.targets)
    return ReplanData(coverage=cov, groups=tuple(groups), links=links, plan_rows=rows, key=key)


def write_replan_data(data: ReplanData, site_zones: Sequence[str], folder: str | Path) -> Path:
    """Write ``replan.npz`` into ``folder`` (``site_zones``: the site's zone ids, in order)."""
    cov, groups = data.coverage, data.groups
    labels = list(dict.fromkeys(groups))
    c = cov.candidates
    zone_ids = list(site_zones)
    frames = list(dict.fromkeys(x.frame for x in c))
    arrays: dict[str, Any] = {
        "key": np.array(json.dumps(data.key)),
        "xy": np.array([x.xy for x in c], dtype=float).reshape(-1, 2),
        "zone": np.array([zone_ids.index(x.zone) for x in c], dtype=np.int32),
        "side": np.array([SIDES.index(x.side) for x in c], dtype=np.int8),
        "frame": np.array([frames.index(x.frame) for x in c], dtype=np.int32),
        "kind": np.array([KINDS.index(x.kind) for x in c], dtype=np.int8),
        "ids": np.array(json.dumps([x.id for x in c])),
        "names": np.array(json.dumps({"zones": zone_ids, "frames": frames, "groups": [_label(g) for g in labels]})),
        "group": np.array([labels.index(g) for g in groups], dtype=np.int32),
        "plan_rows": np.array(data.plan_rows, dtype=np.int64),
        **_csr("cover", cov.by_candidate),
        "slant": _on_pattern(cov.slant_m, cov.by_candidate),
        "incidence": _on_pattern(cov.incidence_deg, cov.by_candidate),
    }
    if data.links is not None:
        arrays.update(_csr("links", sp.triu(data.links, format="csr")))
    path = Path(folder) / FILE_NAME
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=ZIP_LEVEL) as zf:
        for name, array in arrays.items():  # what np.savez_compressed writes, at a quicker level
            with zf.open(f"{name}.npy", "w", force_zip64=True) as fh:
                np.lib.format.write_array(fh, np.asanyarray(array), allow_pickle=False)
    return path


def _on_pattern(m: sp.csr_matrix, by: sp.csr_matrix) -> NDArray[np.float32]:
    """The values of ``m`` at the pairs of ``by`` (in its CSR order), as float32."""
    if np.array_equal(m.indptr, by.indptr) and np.array_equal(m.indices, by.indices):
        return np.asarray(m.data, dtype=np.float32)
    coo = by.tocoo()
    return np.asarray(m[coo.row, coo.col], dtype=np.float32).ravel()


def _label(group: Any) -> list[Any]:
    """A group label (a tuple) as JSON takes it."""
    return [_plain(x) for x in group]


def _plain(x: Any) -> Any:
    """A group label's part as JSON takes it (a numpy integer as a Python one)."""
    return x.item() if hasattr(x, "item") else x


def _csr(name: str, m: sp.csr_matrix) -> dict[str, NDArray[Any]]:
    m = sp.csr_matrix(m)
    return {
        f"{name}_indptr": m.indptr.astype(np.int64),
        f"{name}_indices": m.indices.astype(np.int32),
        f"{name}_shape": np.array(m.shape, dtype=np.int64),
    }


def _bool_csr(z: Any, name: str, symmetric: bool) -> sp.csr_matrix | None:
    if f"{name}_indptr" not in z:
        return None
    ind = z[f"{name}_indices"]
    m = sp.csr_matrix((np.ones(len(ind), dtype=bool), ind, z[f"{name}_indptr"]), shape=tuple(z[f"{name}_shape"]))
    return (m + m.T).tocsr() if symmetric else m


def read_replan_data(path: str | Path, problem: Problem, targets: Targets) -> ReplanData | str:
    """The replan.npz at ``path`` for ``problem`` over ``targets``, or why it cannot be used (a line: missing,
    unreadable, made for another site or options)."""
    p = Path(path)
    if not p.is_file():
        return f"no {FILE_NAME} beside the plan"
    try:
        with np.load(p, allow_pickle=False) as z:
            return _read(dict(z.items()), problem, targets)
    except (OSError, ValueError, KeyError) as err:
        return f"{p} cannot be read ({type(err).__name__}: {err})"


def _read(z: dict[str, Any], problem: Problem, targets: Targets) -> ReplanData | str:
    key = json.loads(str(z["key"]))
    want = data_key(problem, targets)
    if key != want:
        diff = sorted(k for k in want if key.get(k) != want[k])
        return f"{FILE_NAME} was made for another site or options (differs in {', '.join(diff)})"
    names = json.loads(str(z["names"]))
    ids = json.loads(str(z["ids"]))
    xy, zone, side, frame, kind = z["xy"], z["zone"], z["side"], z["frame"], z["kind"]
    cands = tuple(
        Candidate(
            id=ids[k],
            zone=names["zones"][int(zone[k])],
            side=SIDES[int(side[k])],
            frame=names["frames"][int(frame[k])],
            x=float(xy[k, 0]),
            y=float(xy[k, 1]),
            kind=KINDS[int(kind[k])],
        )
        for k in range(len(ids))
    )
    by = _bool_csr(z, "cover", False)
    assert by is not None
    indptr, indices = by.indptr, by.indices
    slant = sp.csr_matrix((z["slant"].astype(float), indices, indptr), shape=by.shape)
    inc = sp.csr_matrix((z["incidence"].astype(float), indices, indptr), shape=by.shape)
    cov = CoverageProblem(
        candidates=cands,
        targets=targets,
        by_candidate=by,
        by_target=by.T.tocsr(),
        slant_m=slant,
        incidence_deg=inc,
        excluded={},
        limits=problem.limits,
    )
    labels = [tuple(g) for g in names["groups"]]
    groups = tuple(labels[int(g)] for g in z["group"])
    return ReplanData(
        coverage=cov,
        groups=groups,
        links=_bool_csr(z, "links", True),
        plan_rows=tuple(int(r) for r in z["plan_rows"]),
        key=key,
    )
