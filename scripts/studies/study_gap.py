"""Where the gap of a tiled plant plan lies: the measurements of docs/studies/plant-gap.md.

On the whole-site matrix that ``planner plan --tiles`` assembles (:func:`planner.tiles.prepare.prepare`: its pool,
candidates that stand nowhere dropped, the overlap relation of the site's registration rule), one run each,
one thread, every count re-checked here (a cover covers every piece; a connected plan is one part):

- ``lp``: the cover LP (registration dropped), :func:`planner.tiles.bound.lp_bound`;
- ``disc R``: the pieces within R m of the site's centre covered alone (every candidate seeing one of them):
  LP and integer optimum (HiGHS through ``scipy.optimize.milp``, ``--disc-time`` s): how large the
  integrality gap is locally;
- ``plain search``: Chvatal's greedy, then the local search with no links (``shrink``) for ``--plain-moves``
  moves: a cover, registration dropped (an upper bound on the plain optimum);
- ``plain scip``: the plain cover by SCIP (PySCIPOpt, 1 thread, ``--scip`` s): its best cover and its bound;
- ``connected seed S``: the connected greedy (20 starts) pruned, then the connected local search for
  ``--connected-moves`` moves with seed S;
- ``--highs``, ``--linked-lp``, ``--rank-cuts``, ``--merge``: the probes of ``scripts/studies/gap_probes.py`` (HiGHS's MIP
  on the plain cover; the LP with a linked station beside each; the LP with local rank cuts; the connected MILP
  over the union of the seeds' plans).

    python scripts/studies/study_gap.py --area 4 --discs 30 50 70 --plain-moves 30000 --scip 600 --seeds 0 1 2 \\
        --csv plant_gap_study.csv

Each row: area, what, setting, stations (or LP value), bound (where one is proven), time_s. The peak RSS of
the whole run (``/usr/bin/time -v``) is added to every row of that run.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import gap_probes as probes

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts" / "bench"))  # the benchmarks' timing helpers

from _timed import append_csv, json_child  # noqa: E402

FIELDS = ["area_ha", "what", "setting", "pieces", "candidates", "value", "bound", "time_s", "peak_rss_mb"]


def site_matrices(area: float) -> tuple[Any, Any, tuple[str, ...], Any]:
    """Coverage (candidates x pieces, bool CSR), overlap adjacency, registration groups and piece midpoints,
    as :func:`planner.tiles.run.plan_by_tiles` has them (its tiles' columns are the site's)."""
    import numpy as np

    from planner.candidates.pool import PoolOptions
    from planner.io.load import load_site
    from planner.plan import PlanOptions
    from planner.tiles.prepare import prepare

    site = load_site(ROOT / "instances" / f"plant_{area:g}ha.json")
    prep = prepare(
        site, PlanOptions(method="milp", pricing=False, pool=PoolOptions(grid_spacing_m=10.0))
    )  # the 10-m grid of the published figures (the plain command's 16-ha pool is 4 m since issue 44's finer grid)
    a = prep.coverage()
    adj, groups, targets = prep.overlap(a), prep.groups, prep.targets
    mid = (np.asarray(targets.a) + np.asarray(targets.b)) / 2.0
    return a, adj, groups, mid


def disc_rows(a: Any, mid: Any, radii: list[float], time_s: float) -> list[dict]:
    """LP and integer optimum of the pieces within each radius of the centre of the pieces' box."""
    import numpy as np
    from scipy.optimize import linprog

    centre = (mid.min(axis=0) + mid.max(axis=0)) / 2.0
    at_all = a.T.tocsr()
    rows = []
    for r in radii:
        cols, at = probes.disc(at_all, mid, centre, r)
        t0 = time.perf_counter()
        lp = linprog(np.ones(cols.size), A_ub=-at, b_ub=-np.ones(at.shape[0]), bounds=(0, 1), method="highs")
        ip, chosen, _ = probes.cover_ip(at, time_s)
        proven = ip.status == 0
        rows.append(
            {
                "what": "disc",
                "setting": f"r={r:g} m, LP {lp.fun:.3f}",
                "pieces": int(at.shape[0]),
                "candidates": int(cols.size),
                "value": int(chosen.size) if chosen.size else "",
                "bound": int(chosen.size) if proven else round(float(getattr(ip, "mip_dual_bound", np.nan)), 3),
                "time_s": round(time.perf_counter() - t0, 1),
            }
        )
    return rows


def greedy_cover(a: Any) -> list[int]:
    """Chvatal's greedy on every piece some candidate sees (ties: lowest index)."""
    import numpy as np

    open_ = np.asarray(a.sum(axis=0)).ravel() > 0
    chosen: list[int] = []
    af = a.astype(np.float64).tocsr()
    while open_.any():
        j = int(np.argmax(af @ open_.astype(np.float64)))
        chosen.append(j)
        open_[a.indices[a.indptr[j] : a.indptr[j + 1]]] = False
    return chosen


def plain_search_row(a: Any, moves: int) -> dict:
    import numpy as np
    import scipy.sparse as sp

    from planner.solve.local_search import shrink

    n = a.shape[0]
    t0 = time.perf_counter()
    start = greedy_cover(a)
    found = shrink(a, sp.csr_matrix((n, n), dtype=bool), tuple(str(j) for j in range(n)), start, moves=moves, seed=0)
    seen = np.asarray(a[list(found.selected)].sum(axis=0)).ravel() > 0
    assert np.array_equal(seen, np.asarray(a.sum(axis=0)).ravel() > 0), "plain search lost a piece"
    return {
        "what": "plain search",
        "setting": f"greedy {len(start)}, {moves} moves",
        "value": len(found.selected),
        "bound": "",
        "time_s": round(time.perf_counter() - t0, 1),
    }


def scip_row(a: Any, time_s: float) -> dict:
    import numpy as np
    from pyscipopt import Model, quicksum

    at = a.T.tocsr()
    m = Model()
    m.hideOutput(True)
    m.setParam("limits/time", time_s)
    m.setParam("randomization/randomseedshift", 0)
    m.setParam("lp/threads", 1)
    x = [m.addVar(vtype="B", obj=1.0) for _ in range(a.shape[0])]
    for t in np.flatnonzero(np.diff(at.indptr) > 0):
        m.addCons(quicksum(x[j] for j in at.indices[at.indptr[t] : at.indptr[t + 1]]) >= 1)
    t0 = time.perf_counter()
    m.optimize()
    best = int(round(m.getObjVal())) if m.getNSols() else ""
    return {
        "what": "plain scip",
        "setting": f"{time_s:g} s, {m.getStatus()}",
        "value": best,
        "bound": round(m.getDualbound(), 3),
        "time_s": round(time.perf_counter() - t0, 1),
    }


def connected_rows(
    a: Any, adj: Any, groups: tuple[str, ...], moves: int, seeds: list[int], plans: list | None = None
) -> list[dict]:
    """The connected greedy pruned, then the connected local search per seed; each seed's plan is appended to
    ``plans`` when given."""
    import numpy as np

    from planner.solve.connectivity import components, connected_greedy, group_members
    from planner.solve.local_search import shrink
    from planner.tiles.stitch import stitch

    t0 = time.perf_counter()
    grown = connected_greedy(a, adj, groups, np.ones(a.shape[0]), np.ones(a.shape[1], dtype=bool), 20)
    assert grown is not None, "no connected greedy plan"
    start = stitch(a, adj, groups, [grown]).selected
    rows = [
        {
            "what": "connected greedy",
            "setting": "20 starts, pruned",
            "value": len(start),
            "bound": "",
            "time_s": round(time.perf_counter() - t0, 1),
        }
    ]
    for seed in seeds:
        t0 = time.perf_counter()
        found = shrink(a, adj, groups, start, moves=moves, seed=seed)
        parts = [len(components(adj, m)) for m in group_members(groups, found.selected).values()]
        assert all(p == 1 for p in parts), "connected search split a registration group"
        if plans is not None:
            plans.append(found.selected)
        rows.append(
            {
                "what": "connected search",
                "setting": f"seed {seed}, {moves} moves",
                "value": len(found.selected),
                "bound": "",
                "time_s": round(time.perf_counter() - t0, 1),
            }
        )
    return rows


def one(args: argparse.Namespace) -> list[dict]:
    from planner.tiles.bound import lp_bound

    a, adj, groups, mid = site_matrices(args.area)
    t0 = time.perf_counter()
    rows = [
        {
            "what": "lp",
            "setting": "cover LP",
            "value": round(lp_bound(a), 3),
            "bound": "",
            "time_s": round(time.perf_counter() - t0, 1),
        }
    ]
    rows += disc_rows(a, mid, args.discs, args.disc_time)
    if args.plain_moves:
        rows.append(plain_search_row(a, args.plain_moves))
    if args.scip:
        rows.append(scip_row(a, args.scip))
    if args.highs:
        rows.append(probes.highs_row(a, args.highs))
    if args.linked_lp:
        rows.append(probes.linked_lp_row(a, adj))
    if args.rank_cuts:
        rows.append(probes.rank_cut_row(a, mid, args.rank_cuts[0], args.rank_cuts[1], args.disc_time))
    plans: list = []
    if args.seeds:
        rows += connected_rows(a, adj, groups, args.connected_moves, args.seeds, plans)
    if args.merge and plans:
        rows.append(probes.merge_row(a, adj, groups, plans, args.merge))
    for r in rows:
        r.setdefault("pieces", a.shape[1])
        r.setdefault("candidates", int((a.getnnz(axis=1) > 0).sum()))
        r["area_ha"] = args.area
    return rows


def _child_args(args: argparse.Namespace) -> list[str]:
    """The options of this run, for its child under ``/usr/bin/time -v``."""
    out = [
        "--area",
        f"{args.area:g}",
        "--disc-time",
        f"{args.disc_time:g}",
        "--plain-moves",
        str(args.plain_moves),
        "--scip",
        f"{args.scip:g}",
        "--connected-moves",
        str(args.connected_moves),
    ]
    out += ["--highs", f"{args.highs:g}", "--merge", f"{args.merge:g}"] + (["--linked-lp"] if args.linked_lp else [])
    if args.rank_cuts:
        out += ["--rank-cuts", *(f"{r:g}" for r in args.rank_cuts)]
    if args.discs:
        out += ["--discs", *(f"{r:g}" for r in args.discs)]
    if args.seeds:
        out += ["--seeds", *(str(s) for s in args.seeds)]
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--area", type=float, default=4)
    ap.add_argument("--discs", type=float, nargs="*", default=[], metavar="R")
    ap.add_argument("--disc-time", type=float, default=120.0)
    ap.add_argument("--plain-moves", type=int, default=0)
    ap.add_argument("--scip", type=float, default=0.0, metavar="S")
    ap.add_argument("--seeds", type=int, nargs="*", default=[])
    ap.add_argument("--connected-moves", type=int, default=20000)
    ap.add_argument("--highs", type=float, default=0.0, metavar="S", help="plain cover by HiGHS's MIP for S s")
    ap.add_argument("--linked-lp", action="store_true", help="cover LP with a linked station beside each")
    ap.add_argument(
        "--rank-cuts",
        type=float,
        nargs=2,
        default=None,
        metavar=("R", "STEP"),
        help="cover LP with a rank cut per disc of R m every STEP m (each disc's optimum: --disc-time s)",
    )
    ap.add_argument(
        "--merge",
        type=float,
        default=0.0,
        metavar="W",
        help="connected MILP (W s of CP-SAT work) over the union of the --seeds plans",
    )
    ap.add_argument("--csv", type=Path, default=None, help="append the rows to this CSV")
    ap.add_argument("--one", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--json", type=Path, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        args.json.write_text(json.dumps({"rows": one(args)}))
        return 0
    out = json_child(__file__, ["--one", *_child_args(args)], "study")
    rows = [dict(r, peak_rss_mb=out["peak_rss_mb"]) for r in out["rows"]]
    for r in rows:
        print(json.dumps(r), flush=True)
    if args.csv:
        append_csv(args.csv, FIELDS, rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
