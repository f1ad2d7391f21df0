"""``planner replan PLAN.json EDITS.json --out DIR``: a plan repaired on site (:func:`planner.replanning.run.replan`), written
with its history: DIR/plan.json (the new plan, with ``replan``: what changed), DIR/plan.N.json and edits.N.json (N
the next free index; plan.0.json the plan first repaired), the field sheet of the stations left (field.html, .csv,
.geojson, .json; field.pdf with --pdf) in DIR/sheet, and the plan's replan.npz, so that the next re-plan starts from it too.
The earlier plan's outputs in DIR that this run does not rewrite (its field sheet, report, network, exports) move to
DIR/superseded.N (:mod:`planner.cli.outputs`): DIR holds one plan's outputs."""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from planner.cli.option_types import POSITIVE
from planner.core.errors import ExitCode, UsageError
from planner.core.text import dumps

if TYPE_CHECKING:  # loaded when the command runs (a fast --help: docs/startup.md)
    from planner.field.run import FieldPlan
    from planner.replanning.run import Replan

#: the subfolder of --out the sheet of the stations left goes into (its field.json lists those only, plan.json every
#: station: the outputs' consistency check compares a folder's field.json with its plan.json)
SHEET_FOLDER = "sheet"
#: how many solutions the routing of a re-plan's sheet tries (the plan's sheet: 1000): seconds count on site
REPLAN_SOLUTION_LIMIT = 200


class _OutFolder(argparse.Action):
    """``--out DIR``: kept twice, as ``out`` (the folder the command writes, staged by :mod:`planner.cli.outputs`)
    and ``history`` (the folder itself, whose plan.N.json the next index is counted from)."""

    def __call__(self, parser: Any, namespace: argparse.Namespace, values: Any, option_string: Any = None) -> None:
        namespace.out = values
        namespace.history = values


def add_replan_parser(sub: Any) -> None:
    """Register ``planner replan``."""
    r = sub.add_parser(
        "replan",
        help="repair a plan on site after edits (stations done, blocked or moved, obstacles, closed areas and "
        "zones): the rest re-planned in seconds, a new field sheet from where the crew stands",
    )
    r.add_argument("plan", help="plan.json written by planner plan --out (its replan.npz makes it fast)")
    r.add_argument("edits", help="edits.json (format planner-edits/1; docs/field.md, 'Re-planning on site')")
    r.add_argument("--site", help="the site file (default: the one recorded in the plan)")
    r.add_argument(
        "--out",
        metavar="DIR",
        action=_OutFolder,
        help="folder for plan.json, plan.N.json, edits.N.json and the field sheet in DIR/sheet (default: the plan's "
        "folder)",
    )
    r.add_argument(
        "--work-limit",
        type=POSITIVE,
        default=None,
        metavar="S",
        help="CP-SAT work (deterministic seconds) of the re-plan's solve (default 0.5: seconds on site)",
    )
    r.add_argument(
        "--solution-limit",
        type=int,
        default=REPLAN_SOLUTION_LIMIT,
        metavar="N",
        help=f"routing of the sheet: stop after N solutions (default {REPLAN_SOLUTION_LIMIT})",
    )
    r.add_argument("--pdf", action="store_true", help="also write field.pdf (a few seconds more)")
    r.add_argument("--quiet", action="store_true", help="no progress bars")
    r.set_defaults(func=cmd_replan, history=None)


def next_index(folder: str | Path) -> int:
    """The next free history index of ``folder``: one past the largest N of its plan.N.json and edits.N.json (1
    where there is none)."""
    taken = [0]
    for p in Path(folder).glob("*.json") if Path(folder).is_dir() else ():
        parts = p.name.split(".")
        if len(parts) == 3 and parts[0] in ("plan", "edits") and parts[1].isdigit():
            taken.append(int(parts[1]))
    return max(taken) + 1


def cmd_replan(args: argparse.Namespace) -> int:
    if args.solution_limit < 1:
        raise UsageError("must be a whole number >= 1", field="--solution-limit", value=args.solution_limit)
    from planner.field.run import FieldOptions
    from planner.io.replan_data import FILE_NAME
    from planner.replanning.run import replan
    from planner.replanning.solve_rest import REPLAN_WORK_S

    folder = Path(args.out or Path(args.plan).parent)
    history = Path(args.history or Path(args.plan).parent)
    options = FieldOptions(solution_limit=args.solution_limit)
    work = args.work_limit or REPLAN_WORK_S
    r = replan(args.plan, args.edits, site=args.site, work_limit_s=work, field_options=options)
    if not r.pool_from.startswith(FILE_NAME):
        print(f"planner: note: the pool was {r.pool_from}; `planner plan --out DIR` keeps it", file=sys.stderr)
    print("\n".join(r.lines()))
    folder.mkdir(parents=True, exist_ok=True)
    n = next_index(history)
    # re-planned in the plan's own folder: the plan read is kept as plan.(N-1).json there (plan.0.json the first time),
    # and plan.json becomes the new plan, so the new plan names the history file as the one it came from
    in_place = Path(args.plan).resolve() == (history / "plan.json").resolve()
    source = str(Path(args.plan).parent / f"plan.{n - 1}.json") if in_place else None
    written = _history(r, folder, history, n, source)
    if r.sheet is not None:
        written += _sheet(r.sheet, folder / SHEET_FOLDER, args.pdf)
    source_npz = Path(args.plan).parent / FILE_NAME
    if source_npz.is_file() and source_npz.resolve() != (history / FILE_NAME).resolve():
        shutil.copyfile(source_npz, folder / FILE_NAME)
        written.append(folder / FILE_NAME)
    for path in written:
        print(f"wrote {path}")
    return ExitCode.OK


def plan_dict(r: Replan, source: str | None = None) -> dict[str, Any]:
    """The new plan.json: the plan's fields (:func:`planner.plan.plan_dict.plan_to_dict`), its stations numbered
    as the new sheet walks them (the done ones after, each with ``"status": "done"``, at the position where it stood),
    and ``replan``: what was repaired and what changed (``from_plan``: ``source`` where given, the history file the
    plan read is kept as)."""
    from planner.plan.plan_dict import StationNumbering, plan_to_dict

    plan = r.plan()
    order = [] if r.sheet is None else [r.sheet.stations[k].id for k in r.sheet.order]
    numbering = StationNumbering.walking(plan.stations, order)
    out = plan_to_dict(plan, numbering)
    done = {s.id for s in r.done}
    for row in out["stations"]:  # where they stood: the next re-plan keeps them done (planner.io.edits.with_plan_done)
        if row["id"] in done:
            row["status"] = "done"
    what = r.to_dict()
    return {**out, "replan": what if source is None else {**what, "from_plan": source}}


def _history(r: Replan, folder: Path, history: Path, n: int, source: str | None) -> list[Path]:
    """plan.json, plan.N.json and edits.N.json (and plan.0.json, the plan first repaired, where the history has
    none) written into ``folder``; ``source``: :func:`plan_dict`'s."""
    text = dumps(plan_dict(r, source))
    out = []
    if not (history / "plan.0.json").exists():
        (folder / "plan.0.json").write_text(Path(r.source.path).read_text())
        out.append(folder / "plan.0.json")
    for name, content in (
        ("plan.json", text),
        (f"plan.{n}.json", text),
        (f"edits.{n}.json", dumps(r.edits.raw or {})),
    ):
        (folder / name).write_text(content)
        out.append(folder / name)
    return out


def _sheet(fp: FieldPlan, folder: Path, pdf: bool) -> list[Path]:
    """The field sheet's files (:func:`planner.field.sheet.write_sheet`'s, the PDF only where asked)."""
    import csv
    import io

    from planner.field.page import render_html
    from planner.field.record import HEADER, rows, to_dict
    from planner.field.sheet import geojson

    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / f"field.{ext}" for ext in ("html", "csv", "geojson", "json")]
    paths[0].write_text(render_html(fp))
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerows([HEADER, *rows(fp)])
    paths[1].write_text(buf.getvalue())
    paths[2].write_text(dumps(geojson(fp)))
    paths[3].write_text(dumps(to_dict(fp)))
    if pdf:
        from planner.field.pdf import write_pdf

        paths.append(folder / "field.pdf")
        write_pdf(fp, paths[-1])
    return paths
