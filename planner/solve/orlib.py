"""Reader of OR-Library set-covering files (Beasley 1987, 1990).

Format: m (rows) n (columns); the n column costs; then for each row the number of columns covering it followed by
those columns (1-based). Rows are the targets, columns the candidates.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import scipy.sparse as sp

from planner.core.errors import InputError
from planner.core.fileio import read_text
from planner.solve.instance import CoverInstance


def read_orlib(path: Path | str) -> CoverInstance:
    name = str(path)
    tokens = read_text(Path(path)).split()
    try:
        nums = np.array([int(t) for t in tokens], dtype=np.int64)
    except ValueError as exc:
        raise InputError(f"not an OR-Library set-cover file ({exc})", file=name) from None
    if nums.size < 2:
        raise InputError("missing the header 'm n'", file=name)
    m, n = int(nums[0]), int(nums[1])
    pos = 2
    cost = nums[pos : pos + n].astype(float)
    pos += n
    rows, cols = [], []
    for r in range(m):
        if pos >= nums.size:
            raise InputError(f"ends before row {r + 1} of {m}", file=name, row=r + 1)
        k = int(nums[pos])
        members = nums[pos + 1 : pos + 1 + k]
        if len(members) != k or np.any(members < 1) or np.any(members > n):
            raise InputError(f"bad column list ({k} columns announced)", file=name, row=r + 1)
        rows.append(np.full(k, r))
        cols.append(members - 1)
        pos += 1 + k
    by_target = sp.csr_matrix(
        (np.ones(sum(len(c) for c in cols), dtype=bool), (np.concatenate(rows), np.concatenate(cols))), shape=(m, n)
    )
    return CoverInstance(by_candidate=by_target.T.tocsr(), cost=cost, name=Path(path).stem)
