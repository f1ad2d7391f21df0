"""Plain set cover: this project's solvers beside OR-Tools' ``set_cover`` module, CP-SAT and CFT (issue 34).

Usage (the default --problems are the 22 of docs/benchmarks/setcover.md, ~48 min in all on its loaded 2-core machine;
it was run in pieces of one or a few problems, listed there, each under 10 min):

    /usr/bin/time -v python scripts/bench/bench_setcover.py --problems scp41 scp51 scp61 scpa1 scpb1 scpc1 scpd1 \\
        --csv docs/benchmarks/results/setcover.csv
    python scripts/bench/bench_setcover.py --solvers cft --cft-bin /tmp/cft-src/build/accft \\
        --csv docs/benchmarks/results/setcover.csv                        # the CFT rows, all 22 problems, ~2 min
    python scripts/bench/bench_setcover.py --solvers pycft pycft-shrink --problems plant_4ha \
        --matrix plant_4ha=/tmp/exp/a4.npz --csv docs/benchmarks/results/setcover.csv  # the project's CFT engine
    python scripts/bench/bench_setcover.py --table docs/benchmarks/results/setcover.csv   # the Markdown table

Problems (registration dropped: cover every target some candidate sees, nothing else):

- ``plant_4ha``, ``plant_16ha``: ``planner export instances/plant_<N>ha.json --format orlib`` (unit costs: stations),
  exported once into ``--cache`` and read back with :func:`planner.solve.orlib.read_orlib`, or, with ``--matrix
  plant_4ha=PATH``, the same candidates x targets matrix saved by ``scipy.sparse.save_npz`` (all-zero columns dropped);
- ``scpXY``: the OR-Library instance from ``--dir`` with its own column costs; ``scpXY-unit``: the same rows and
  columns with every cost 1 (the unicost variant).

Solvers, each run once, one thread, seed ``--seed`` where it takes one:

- ``lp``: the LP relaxation (0 <= x <= 1) by HiGHS through ``scipy.optimize.linprog(method=--lp-method)``;
- ``greedy``: Chvatal's greedy, :func:`planner.solve.greedy.greedy_cover` (cost per newly covered target);
- ``shrink``: the weighted (row-weighting) local search :func:`planner.solve.local_search.shrink` from the greedy's
  cover for ``--moves`` moves, with no overlap links and each candidate its own registration group (so the
  connectivity term is always 0 and only coverage counts, as ``scripts/studies/study_gap.py --plain-moves``); it minimises
  the number of stations, so it runs on unit costs only;
- ``ortools-ss``: OR-Tools ``ElementDegreeSolutionGenerator`` then ``SteepestSearch`` (drops redundant columns);
- ``ortools-gls``: OR-Tools ``GuidedLocalSearch`` from that cover, ``--gls-iterations`` iterations (deterministic:
  neither OR-Tools heuristic draws random numbers, so they take no seed);
- ``milp``: :func:`planner.solve.milp.solve` on CP-SAT (presolve, greedy warm start, 1 worker) stopped after
  ``--cpsat-work`` deterministic seconds, with a wall-clock cap of ``--cpsat-wall`` s; its cover and bound;
- ``cft``: the Caprara-Fischetti-Toth heuristic (1999) of https://github.com/c4v4/cft, built outside this repository
  (``cmake -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build``) and given as ``--cft-bin PATH/accft``
  (skipped with a note without it). Each problem is written as a strict OR-Library "scp" file (row counts on their
  own line: its parser rejects the one-line rows of ``planner export``) with the costs the other solvers see (1 for
  the unit variants), then ``accft -p SCP -s --seed -t --cft-limit -o SOL -v 2`` runs on it (single-threaded; its
  time limit is wall-clock, and it also stops by its own criterion). Its cover is read back from ``SOL`` and checked;
  its Lagrangian lower bound (the last ``lb`` of its log) goes into ``bound``. CPU seconds (user + system) and peak
  RSS are those of the ``accft`` process, as ``/usr/bin/time`` reports them (``os.wait4`` here would count this
  script's RSS at the fork), not of this script; wall seconds are around ``/usr/bin/time``; writing the file is not
  timed;
- ``pycft``: the project's plain-cover engine, :func:`planner.solve.cft.cft_cover` (the same CFT through the ``pycft``
  bindings, in this process), seed ``--seed``, no time limit (it stops by its own criterion); its Lagrangian lower
  bound goes into ``bound``;
- ``pycft-shrink``: ``shrink`` as above (no links, each candidate its own group, ``--moves`` moves, seed ``--seed``)
  started from the ``pycft`` cover instead of the greedy's; unit costs only.

Each solver's time is its own (a search's time leaves out the construction it starts from): CPU seconds of this
process (``resource.getrusage``, user + system; ``accft``'s for ``cft``) and wall seconds. Every cover is checked
(covers every target, value recomputed from the costs). One CSV row per problem and solver (``--csv``, appended).
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import re
import resource
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

ROOT = Path(__file__).resolve().parents[2]
ORLIB = ROOT.parent / "shared" / "benchmarks" / "orlib_scp"
FIELDS = [
    "problem",
    "rows",
    "cols",
    "nnz",
    "cost_type",
    "solver",
    "setting",
    "value",
    "bound",
    "status",
    "cpu_s",
    "wall_s",
    "load_avg",
    "peak_rss_mb",
]
SOLVERS = ("lp", "greedy", "shrink", "ortools-ss", "ortools-gls", "milp", "cft", "pycft", "pycft-shrink")
DEFAULT_PROBLEMS = [
    "scp41",
    "scp42",
    "scp51",
    "scp52",
    "scp61",
    "scp62",
    "scpa1",
    "scpa2",
    "scpb1",
    "scpc1",
    "scpd1",
    "scpnre1",
    "scp41-unit",
    "scp51-unit",
    "scp61-unit",
    "scpa1-unit",
    "scpb1-unit",
    "scpc1-unit",
    "scpd1-unit",
    "scpnre1-unit",
    "plant_4ha",
    "plant_16ha",
]


@dataclass(frozen=True)
class Problem:
    """A plain cover: ``a`` is candidates x targets (bool CSR), every target seen by some candidate."""

    name: str
    a: sp.csr_matrix
    cost: np.ndarray
    cost_type: str


def cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def timed(fn: Callable[[], Any]) -> tuple[Any, float, float]:
    """``fn()``, its CPU seconds (this process) and its wall seconds."""
    c0, t0 = cpu_s(), time.perf_counter()
    out = fn()
    return out, cpu_s() - c0, time.perf_counter() - t0


def exported(area: str, cache: Path) -> Path:
    """The plant's plain cover as an OR-Library file, exported once by ``planner export``."""
    out = cache / f"{area}.txt"
    if not out.exists():
        cache.mkdir(parents=True, exist_ok=True)
        tmp = out.with_suffix(".part")
        cmd = [
            sys.executable,
            "-m",
            "planner",
            "export",
            str(ROOT / "instances" / f"{area}.json"),
            "--format",
            "orlib",
            "--grid-spacing",  # the 10-m grid of the published table (the plain command's 16-ha pool is 4 m now)
            "10",
            "--out",
            str(tmp),
            "--quiet",
        ]
        subprocess.run(cmd, check=True, cwd=ROOT)
        tmp.rename(out)
    return out


def load(name: str, orlib_dir: Path, cache: Path, matrices: dict[str, Path] | None = None) -> Problem:
    from planner.solve.orlib import read_orlib

    if matrices and name in matrices:  # a saved candidates x targets matrix, unit costs
        a = sp.load_npz(matrices[name]).tocsr().astype(bool)
        a = a[:, np.flatnonzero(a.getnnz(axis=0) > 0)].tocsr()  # every target seen by some candidate
        return Problem(name, a, np.ones(a.shape[0]), "unit")
    if name.startswith("plant_"):
        inst = read_orlib(exported(name, cache))
        return Problem(name, inst.by_candidate.astype(bool).tocsr(), np.asarray(inst.cost, dtype=float), "unit")
    base, _, kind = name.partition("-")
    if kind not in ("", "unit"):
        raise SystemExit(f"unknown problem {name!r}: scpXY, scpXY-unit, plant_4ha or plant_16ha")
    inst = read_orlib(orlib_dir / f"{base}.txt")
    cost = np.ones(inst.shape[0]) if kind == "unit" else np.asarray(inst.cost, dtype=float)
    return Problem(name, inst.by_candidate.astype(bool).tocsr(), cost, "unit" if kind else "orlib")


def checked(p: Problem, selected: Sequence[int], solver: str) -> float:
    """The cost of ``selected``, after checking that it covers every target."""
    sel = np.unique(np.asarray(selected, dtype=np.int64))
    seen = np.zeros(p.a.shape[1], dtype=bool)
    seen[p.a[sel].indices] = True
    if not seen.all():
        raise SystemExit(f"{p.name}: {solver} left {int((~seen).sum())} targets uncovered")
    return float(p.cost[sel].sum())


def run_lp(p: Problem, method: str) -> dict:
    from scipy.optimize import linprog

    at = p.a.T.tocsr().astype(float)
    lp, c, w = timed(lambda: linprog(p.cost, A_ub=-at, b_ub=-np.ones(at.shape[0]), bounds=(0, 1), method=method))
    return {
        "solver": "lp",
        "setting": method,
        "value": round(float(lp.fun), 3) if lp.status == 0 else "",
        "status": "optimal" if lp.status == 0 else lp.message,
        "cpu_s": c,
        "wall_s": w,
    }


def run_greedy(p: Problem) -> tuple[dict, list[int]]:
    from planner.solve.greedy import greedy_cover

    g, c, w = timed(lambda: greedy_cover(p.a, weights=p.cost))
    chosen = list(g.selected)
    return {
        "solver": "greedy",
        "setting": "Chvatal",
        "value": checked(p, chosen, "greedy"),
        "status": "feasible",
        "cpu_s": c,
        "wall_s": w,
    }, chosen


def run_shrink(
    p: Problem, start: list[int], moves: int, seed: int, solver: str = "shrink", origin: str = "greedy"
) -> dict:
    from planner.solve.local_search import shrink

    n = p.a.shape[0]
    no_links = sp.csr_matrix((n, n), dtype=bool)
    own_group = tuple(range(n))  # one group per candidate: no link is ever needed
    found, c, w = timed(lambda: shrink(p.a, no_links, own_group, start, moves=moves, seed=seed))
    last = found.history[-1][0] if found.history else 0
    return {
        "solver": solver,
        "setting": f"{moves} moves from {origin} {len(start)}, seed {seed}, last gain at {last}",
        "value": checked(p, found.selected, solver),
        "status": "feasible",
        "cpu_s": c,
        "wall_s": w,
    }


def ortools_model(p: Problem) -> Any:
    from ortools.set_cover.python import set_cover

    model = set_cover.SetCoverModel()
    a = p.a
    for j in range(a.shape[0]):
        model.add_empty_subset(float(p.cost[j]))
        for e in a.indices[a.indptr[j] : a.indptr[j + 1]].tolist():
            model.add_element_to_last_subset(e)
    return model


def run_ortools(p: Problem, iterations: int) -> list[dict]:
    from ortools.set_cover.python import set_cover

    model, build_c, _ = timed(lambda: ortools_model(p))
    inv = set_cover.SetCoverInvariant(model)

    def degree_then_steepest() -> bool:
        ok = set_cover.ElementDegreeSolutionGenerator(inv).next_solution()
        steepest = set_cover.SteepestSearch(inv)
        steepest.set_max_iterations(max(model.num_subsets, 1))
        return ok and steepest.next_solution()

    ok, c1, w1 = timed(degree_then_steepest)
    ss = np.flatnonzero(inv.is_selected())
    rows = [
        {
            "solver": "ortools-ss",
            "setting": f"element degree + steepest (model built in {build_c:.1f} CPU s)",
            "value": checked(p, ss, "ortools-ss"),
            "status": "feasible" if ok else "failed",
            "cpu_s": c1,
            "wall_s": w1,
        }
    ]

    def gls() -> bool:
        search = set_cover.GuidedLocalSearch(inv)
        search.initialize()  # its penalty factor comes from the cost of the cover loaded now
        search.set_max_iterations(iterations)
        return search.next_solution()

    ok, c2, w2 = timed(gls)
    rows.append(
        {
            "solver": "ortools-gls",
            "setting": f"{iterations} iterations from ortools-ss {len(ss)}",
            "value": checked(p, np.flatnonzero(inv.is_selected()), "ortools-gls"),
            "status": "feasible" if ok else "failed",
            "cpu_s": c2,
            "wall_s": w2,
        }
    )
    return rows


def run_milp(p: Problem, work_s: float, wall_s: float, seed: int) -> dict:
    from planner.solve.instance import CoverInstance
    from planner.solve.milp import MilpOptions, solve

    inst = CoverInstance(by_candidate=p.a, cost=p.cost, name=p.name)
    opts = MilpOptions(backend="cpsat", time_limit_s=wall_s, work_limit=work_s, seed=seed, threads=1, overlap=None)
    r, c, w = timed(lambda: solve(inst, opts))
    work = r.info.get("work", {})
    value = checked(p, r.selected, "milp") if r.selected else ""
    setting = f"{work_s:g} det-s (used {work.get('used', '?')}), wall cap {wall_s:g} s" + (
        ", WALL CAP HIT" if r.wall_cap_hit else ""
    )
    return {
        "solver": "milp",
        "setting": setting,
        "value": value,
        "bound": "" if r.bound is None else round(float(r.bound), 3),
        "status": r.status.value,
        "cpu_s": c,
        "wall_s": w,
    }


def run_pycft(p: Problem, seed: int) -> tuple[dict, list[int]]:
    """The project's engine, :func:`planner.solve.cft.cft_cover`: CFT through ``pycft``, no time limit."""
    from planner.solve.cft import cft_cover

    unit = bool(np.all(p.cost == 1.0))
    r, c, w = timed(lambda: cft_cover(p.a, None if unit else p.cost, seed=seed))
    chosen = list(r.selected)
    return {
        "solver": "pycft",
        "setting": f"cft_cover seed {seed}, heur_iters 250, no time limit (own criterion, {r.time_s:.1f} s), re-checked",
        "value": checked(p, chosen, "pycft"),
        "bound": round(r.lower_bound, 3),
        "status": "feasible",
        "cpu_s": c,
        "wall_s": w,
    }, chosen


def write_scp(p: Problem, path: Path) -> None:
    """``p`` as an OR-Library "scp" file: rows (targets) and columns (candidates), the column costs, then per row its
    number of columns on a line of its own and those columns (1-based), 12 numbers a line."""

    def lines(values: Sequence[str]) -> list[str]:
        return [" " + " ".join(values[i : i + 12]) + " " for i in range(0, len(values), 12)]

    by_target = p.a.T.tocsr()
    out = [f" {by_target.shape[0]} {by_target.shape[1]} "]
    out += lines([f"{c:.17g}" for c in p.cost.tolist()])
    for i in range(by_target.shape[0]):
        cols = by_target.indices[by_target.indptr[i] : by_target.indptr[i + 1]]
        out.append(f" {len(cols)} ")
        out += lines([str(j + 1) for j in sorted(cols.tolist())])
    path.write_text("\n".join(out) + "\n")


def run_cft(p: Problem, binary: Path, limit_s: float, seed: int, workdir: Path) -> dict:
    """One run of the CFT binary (``accft``) on ``p``: its cover read back and checked, its own CPU, wall and RSS."""
    inst, sol, log, usage = (workdir / f"{p.name}{ext}" for ext in (".txt", ".sol", ".log", ".time"))
    write_scp(p, inst)
    sol.unlink(missing_ok=True)
    cmd = [str(binary), "-i", str(inst), "-p", "SCP", "-s", str(seed), "-t", f"{limit_s:g}", "-o", str(sol), "-v", "2"]
    with log.open("w") as out:
        t0 = time.perf_counter()
        proc = subprocess.Popen(
            ["/usr/bin/time", "-f", "%U %S %M", "-o", str(usage), *cmd],
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,  # its own process group, so the guard below stops accft too
        )
        # its limit is checked between phases: allow it 2 min more, then stop it
        guard = threading.Timer(limit_s + 120, lambda: os.killpg(proc.pid, signal.SIGKILL))
        guard.start()
        proc.wait()
        guard.cancel()
        wall = time.perf_counter() - t0
    text = log.read_text()
    times = usage.read_text().split() if usage.exists() else []
    user, system, rss_kb = times[-3:] if len(times) >= 3 else ("nan", "0", "0")  # nan: killed with /usr/bin/time
    best = re.findall(r"CFT> Best solution (\S+) time (\S+)s", text)
    lbs = re.findall(r"REFN>\s*\d+: Best solution \S+, lb (\S+),", text)
    row = {
        "solver": "cft",
        "cpu_s": float(user) + float(system),
        "wall_s": wall,
        "peak_rss_mb": round(int(rss_kb) / 1024),  # accft's own peak
        "bound": lbs[-1] if lbs else "",
    }
    if proc.returncode != 0 or not best or not sol.exists():
        tail = " | ".join(text.strip().splitlines()[-2:])
        return {**row, "setting": f"accft exit {proc.returncode}: {tail}", "value": "", "status": "failed"}
    tokens = sol.read_text().split()
    value = checked(p, [int(t) for t in tokens[1:]], "cft")
    if abs(value - float(tokens[0])) > 1e-6 * max(1.0, value):
        raise SystemExit(f"{p.name}: cft says its cover costs {tokens[0]}, it costs {value}")
    own_s = float(best[-1][1])
    stop = "its time limit" if own_s >= limit_s else "its own criterion"
    setting = f"-s {seed} -t {limit_s:g} (wall), stopped by {stop} at {own_s:.1f} s, cover re-checked"
    return {**row, "setting": setting, "value": value, "status": "feasible"}


def bench(p: Problem, args: argparse.Namespace) -> list[dict]:
    rows: list[dict] = []
    solvers = set(args.solvers)

    def emit(row: dict) -> None:
        row.update(
            problem=p.name,
            rows=p.a.shape[1],
            cols=p.a.shape[0],
            nnz=p.a.nnz,
            cost_type=p.cost_type,
            load_avg=round(os.getloadavg()[0], 2),
        )
        row.setdefault("peak_rss_mb", round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024))
        row["cpu_s"], row["wall_s"] = round(row["cpu_s"], 2), round(row["wall_s"], 2)
        rows.append(row)
        print(
            f"{p.name:12s} {row['solver']:12s} {row['value']!s:>9s} bound {row.get('bound', '')!s:>8s} "
            f"{row['cpu_s']:8.2f} CPU s {row['wall_s']:8.2f} s  {row['setting']}",
            flush=True,
        )

    if "lp" in solvers:
        emit(run_lp(p, args.lp_method))
    start: list[int] = []
    if solvers & {"greedy", "shrink"}:
        row, start = run_greedy(p)
        emit(row)
    if "shrink" in solvers and np.all(p.cost == 1.0):
        emit(run_shrink(p, start, args.moves, args.seed))
    if solvers & {"ortools-ss", "ortools-gls"}:
        for row in run_ortools(p, args.gls_iterations):
            emit(row)
    if "milp" in solvers:
        emit(run_milp(p, args.cpsat_work, args.cpsat_wall, args.seed))
    if "cft" in solvers and args.cft_bin is not None:
        emit(run_cft(p, args.cft_bin, args.cft_limit, args.seed, args.cft_dir))
    if solvers & {"pycft", "pycft-shrink"}:
        row, cft_start = run_pycft(p, args.seed)
        emit(row)
        if "pycft-shrink" in solvers and np.all(p.cost == 1.0):
            emit(run_shrink(p, cft_start, args.moves, args.seed, solver="pycft-shrink", origin="pycft"))
    return rows


def append_csv(path: Path, rows: list[dict]) -> None:
    new = not path.exists()
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        if new:
            w.writeheader()
        w.writerows({k: r.get(k, "") for k in FIELDS} for r in rows)


def _num(v: str) -> str:
    if v == "":
        return "-"
    x = float(v)
    return f"{x:.0f}" if x == math.floor(x) else f"{x:.1f}"


def table(path: Path, orlib_dir: Path) -> str:
    """The Markdown table of a results CSV: one line per problem (OR-Library costs, unit costs, plants), the
    published optimum where there is one, value (CPU s) per solver."""
    optima: dict[str, str] = {}
    known = orlib_dir / "known_optima.csv"
    if known.exists():
        optima = {r["instance"]: r["published_optimum"] for r in csv.DictReader(known.open())}
    by: dict[str, dict[str, dict[str, str]]] = {}
    for r in csv.DictReader(path.open()):
        by.setdefault(r["problem"], {})[r["solver"]] = r

    def order(name: str) -> tuple[int, int, str]:
        kind = 2 if name.startswith("plant_") else 1 if name.endswith("-unit") else 0
        base = name.removesuffix("-unit")
        return kind, int(by[name][next(iter(by[name]))]["nnz"]) if kind == 2 else 0, base[:4] + base[4:].rjust(3)

    head = (
        "| problem | rows x cols | costs | optimum | LP | greedy | shrink | OR-Tools ED+SS | OR-Tools GLS "
        "| CFT | CFT (pycft) | pycft + shrink | CP-SAT MILP | CP-SAT bound |"
    )
    out = [head, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name in sorted(by, key=order):
        s = by[name]
        any_row = next(iter(s.values()))

        def cell(solver: str, s: dict[str, dict[str, str]] = s) -> str:
            r = s.get(solver)
            return "-" if r is None else f"{_num(r['value'])} ({float(r['cpu_s']):.1f} s)"

        lp = s.get("lp")
        lp_cell = "-" if lp is None else f"{float(lp['value']):.2f}"
        milp = s.get("milp")
        bound = "-"
        if milp is not None:
            bound = _num(milp["bound"]) + (" (optimal)" if milp["status"] == "optimal" else "")
        opt = optima.get(name, "-") if any_row["cost_type"] == "orlib" else "-"
        out.append(
            f"| {name} | {any_row['rows']} x {any_row['cols']} | {any_row['cost_type']} | {opt} | {lp_cell} | "
            f"{cell('greedy')} | {cell('shrink')} | {cell('ortools-ss')} | {cell('ortools-gls')} | {cell('cft')} | "
            f"{cell('pycft')} | {cell('pycft-shrink')} | {cell('milp')} | {bound} |"
        )
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument(
        "--problems",
        nargs="+",
        default=DEFAULT_PROBLEMS,
        help="scpXY (OR-Library costs), scpXY-unit (unit costs), plant_4ha, plant_16ha",
    )
    ap.add_argument("--solvers", nargs="+", default=list(SOLVERS), choices=SOLVERS)
    ap.add_argument("--dir", type=Path, default=ORLIB, help="folder of the OR-Library scp*.txt files")
    ap.add_argument("--cache", type=Path, default=Path("/tmp/bench_setcover"), help="folder of the plant exports")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--moves", type=int, default=30_000, help="moves of the local search (shrink)")
    ap.add_argument("--gls-iterations", type=int, default=1_000_000)
    ap.add_argument("--cpsat-work", type=float, default=300.0, help="CP-SAT deterministic seconds")
    ap.add_argument("--cpsat-wall", type=float, default=540.0, help="CP-SAT wall-clock cap, s")
    ap.add_argument("--lp-method", default="highs-ipm", help="scipy linprog method (HiGHS)")
    ap.add_argument(
        "--cft-bin", type=Path, metavar="PATH", help="the accft binary of c4v4/cft (cft is skipped without)"
    )
    ap.add_argument("--cft-limit", type=float, default=60.0, help="CFT's time limit (its -t, wall-clock), s")
    ap.add_argument(
        "--cft-dir", type=Path, help="keep CFT's problem, solution and log files here (default: a temp dir)"
    )
    ap.add_argument(
        "--matrix",
        nargs="+",
        default=[],
        metavar="NAME=NPZ",
        help="read problem NAME (unit costs) from a saved candidates x targets matrix instead of exporting it",
    )
    ap.add_argument("--csv", type=Path, help="append one row per problem and solver")
    ap.add_argument("--table", type=Path, metavar="CSV", help="print the Markdown table of a results CSV and exit")
    args = ap.parse_args()
    if args.table:
        print(table(args.table, args.dir))
        return
    sys.path.insert(0, str(ROOT))
    if "cft" in args.solvers and args.cft_bin is None:
        print("note: cft skipped, no --cft-bin given (build https://github.com/c4v4/cft, pass its accft)", flush=True)
    with tempfile.TemporaryDirectory(prefix="bench_setcover_cft_") as tmp:
        if args.cft_dir is None:
            args.cft_dir = Path(tmp)
        args.cft_dir.mkdir(parents=True, exist_ok=True)
        for name in args.problems:
            matrices = {k: Path(v) for k, _, v in (m.partition("=") for m in args.matrix)}
            rows = bench(load(name, args.dir, args.cache, matrices), args)
            if args.csv:
                append_csv(args.csv, rows)
    r = resource.getrusage(resource.RUSAGE_SELF)
    print(f"peak RSS of this process {r.ru_maxrss / 1024:.0f} MB, CPU {r.ru_utime + r.ru_stime:.1f} s")


if __name__ == "__main__":
    main()
