"""The pool a plan was chosen from, named by a fingerprint (:func:`pool_of`): what the best plans known
(``docs/benchmarks/best_known.json``) are compared on, so a gap is printed only between plans of one pool.

The fingerprint is the first 12 hex digits of a SHA-256 over the counts of candidates and targets, the candidates in
pool order (position rounded to 1 mm, zone, scan side, frame) and the targets in order (zone, scan side, the piece's
ends rounded to 1 mm). Nothing else: not the machine, its load, the workers, the run time, nor the candidates' ids or
kinds. Positions are in each zone's frame, so a site moved or drawn anew gets another fingerprint. Pairs are recorded
beside it but not hashed: they follow from the pool and the sight limits, and a last-bit difference of a sight test on
another machine should not make another pool.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from planner.coverage.matrix import CoverageProblem
from planner.coverage.targets import Targets
from planner.site.candidate import Candidate

#: hex digits kept of the SHA-256
DIGITS = 12
#: the version of what is hashed: a change of it is a change of every fingerprint
VERSION = "pool v1"


@dataclass(frozen=True)
class Pool:
    """The size of a plan's coverage problem and its fingerprint (plan.json ``pool``)."""

    candidates: int
    targets: int
    pairs: int
    fingerprint: str

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def _mm(values: ArrayLike) -> NDArray[np.int64]:
    """Millimetres, rounded, as little-endian 64-bit integers (the same bytes on every machine)."""
    return np.rint(np.asarray(values, dtype=np.float64) * 1000.0).astype("<i8")


def pool_fingerprint(candidates: Sequence[Candidate], targets: Targets) -> str:
    """The fingerprint of ``candidates`` (in their order) over ``targets`` (see the module's docstring)."""
    h = hashlib.sha256()
    h.update(f"{VERSION}\n{len(candidates)} candidates\n{len(targets)} targets\n".encode())
    h.update(_mm([(c.x, c.y) for c in candidates]).tobytes())
    h.update(json.dumps([[c.zone, c.side.value, c.frame] for c in candidates]).encode())
    h.update(json.dumps([targets.zone_ids[int(z)] for z in targets.zone]).encode())
    h.update(np.asarray(targets.side, dtype="<i1").tobytes())
    h.update(_mm(targets.a).tobytes())
    h.update(_mm(targets.b).tobytes())
    return h.hexdigest()[:DIGITS]


def pool_of(problem: CoverageProblem) -> Pool:
    """The counts and the fingerprint of a coverage problem's pool."""
    return Pool(
        candidates=len(problem.candidates),
        targets=len(problem.targets),
        pairs=int(problem.by_candidate.nnz),
        fingerprint=pool_fingerprint(problem.candidates, problem.targets),
    )
