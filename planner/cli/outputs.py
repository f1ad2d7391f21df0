"""Outputs written whole or not at all: every output folder or file a command line names is checked usable before
the command runs (without creating it), the command writes into a staging folder beside it, and only when the
command succeeds is each file moved into place with :func:`os.replace` (the folder created then).

A failed run (an exception, an exit code other than 0, outputs that disagree) leaves every target as it was: a
folder that did not exist is not created, an existing one keeps its old files, and a half-written file is never
visible under its final name. :func:`staged_outputs` is the one mechanism; :func:`planner.cli.main.main` wraps
every command in it, so the commands write where ``args`` tells them (the staging paths) and print as before:
while the command runs, standard output and error name the paths the user gave, not the staging ones.

An output file is staged under a hidden name beside it. The staging folder of output folders mirrors the folder
it is made in (the deepest existing folder common to them, one staging folder for all where they share a file
system; inside the target where that exists already), so that relative links between outputs (the report's link
to the field sheet) are the same as between the targets. The files a command reads back from its own output
folder (:data:`READ_BACK`) are copied into the staging folder first, and moved back only if the command rewrote
them. Then :func:`planner.report.consistency.check_outputs`, where installed, compares the staged folders.

A command that writes a new plan.json into a folder (:data:`NEW_PLAN`) supersedes the plan there: the earlier plan's
outputs (:data:`PLAN_FILES`) that the run does not rewrite would disagree with the new plan.json, so they are not read
back, and the commit moves them, with the earlier plan.json, into ``DIR/superseded.N`` (N the next free number) and
says so. The folder then holds only the new plan's outputs, and nothing is deleted.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import os
import sys
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TextIO

from planner.core.errors import ExitCode, UsageError

__all__ = ["OUTPUTS", "READ_BACK", "Staging", "Target", "staged_outputs"]

#: the outputs of each command: (option dest, flag, a file rather than a folder); ``report`` and ``field`` write
#: into the plan's folder when ``--out`` is not given
OUTPUTS: dict[str, tuple[tuple[str, str, bool], ...]] = {
    "plan": (("out", "--out", False), ("report", "--report", False), ("field", "--field", False)),
    "network": (("out", "--out", False),),
    "report": (("out", "--out", False),),
    "field": (("out", "--out", False),),
    "replan": (("out", "--out", False),),
    "export": (("out", "--out", True),),
    "assemble": (("out", "--out", True),),
}

#: the files a command may read back from its own output folder (the report links the field sheet found there)
READ_BACK = ("field.html", "field.json")

#: the targets a command writes a new plan.json into: (command, option dest)
NEW_PLAN = frozenset({("plan", "out"), ("replan", "out")})
#: the earlier plan's outputs (relative to its folder) that a new plan supersedes there; not replan.npz (the plan
#: rewrites it, and a re-plan into the plan's folder starts from it again) nor a re-plan's history (plan.N.json)
PLAN_FILES = (
    "plan.json",
    "network.json",
    "report.html",
    "plan.dxf",
    "plan.geojson",
    "stations.csv",
    *(f"{sub}field.{ext}" for sub in ("", "sheet/") for ext in ("html", "csv", "geojson", "json", "pdf")),
)
#: the folders the superseded outputs go into: ``DIR/superseded.N``
SUPERSEDED = "superseded"

#: the staging folders' name prefix (hidden; removed when the command ends)
PREFIX = ".planner-staging-"


@dataclass(frozen=True, kw_only=True)
class Target:
    """One output the command line names: ``dest`` of ``args``, as given (``shown``), where it goes (``path``,
    absolute), whether it is a file, and the existing folder its staging copy mirrors (``base``)."""

    dest: str
    flag: str
    shown: str
    path: Path
    is_file: bool
    base: Path
    #: the command writes a new plan.json here (:data:`NEW_PLAN`): the earlier plan's outputs are superseded
    supersedes: bool = False


def targets_of(args: argparse.Namespace) -> list[Target]:
    """The outputs ``args`` names, each checked usable (nothing is created).

    Raises
    ------
    UsageError
        An empty path, a folder given for a file or a file for a folder, a path under a file, a missing folder for
        an output file, or a folder this user cannot write (exit 2), naming the flag and the path.
    """
    out = []
    for dest, flag, is_file in OUTPUTS.get(str(getattr(args, "command", "")), ()):
        given = getattr(args, dest, None)
        if given is None and command_default(args, dest) is None:
            continue
        shown = str(given) if given is not None else str(command_default(args, dest))
        if not shown.strip():
            raise UsageError(f"is empty: name a {'file' if is_file else 'folder'}", field=flag, value=shown)
        path = Path(os.path.abspath(shown))
        base = _usable_file(flag, shown, path) if is_file else _usable_folder(flag, shown, path)
        new = (str(getattr(args, "command", "")), dest) in NEW_PLAN
        out.append(
            Target(dest=dest, flag=flag, shown=str(Path(shown)), path=path, is_file=is_file, base=base, supersedes=new)
        )
    return out


def command_default(args: argparse.Namespace, dest: str) -> str | None:
    """Where ``planner report``, ``planner field`` and ``planner replan`` write without ``--out``: the plan's
    folder."""
    if (
        dest == "out"
        and getattr(args, "command", None) in ("report", "field", "replan")
        and getattr(args, "out", None) is None
    ):
        return str(Path(args.plan).parent)
    return None


def _usable_folder(flag: str, shown: str, path: Path) -> Path:
    """The existing folder that the output folder ``path`` is or will be made in, checked writable."""
    if path.exists() and not path.is_dir():
        raise UsageError("is a file, not a folder: name a folder", field=flag, value=shown)
    base = path
    while not base.exists():
        base = base.parent
    if not base.is_dir():
        raise UsageError(f"cannot be used as an output folder ({base} is a file)", field=flag, value=shown)
    if not os.access(base, os.W_OK | os.X_OK):
        raise UsageError(f"cannot be used as an output folder (cannot write in {base})", field=flag, value=shown)
    return base


def _usable_file(flag: str, shown: str, path: Path) -> Path:
    """The existing folder an output file ``path`` goes into, checked writable."""
    if path.is_dir():
        raise UsageError("is a folder: name a file", field=flag, value=shown)
    if not path.parent.is_dir():
        raise UsageError(f"cannot be written: no folder {path.parent}", field=flag, value=shown)
    if not os.access(path.parent, os.W_OK | os.X_OK):
        raise UsageError(f"cannot be written (cannot write in {path.parent})", field=flag, value=shown)
    return path.parent


@dataclass(kw_only=True)
class Staging:
    """The staging of one run (:func:`staged_outputs`; filled in as the staging is made, hence not frozen):
    ``roots`` maps each base folder to its staging folder, ``files`` each output file to its hidden name beside it,
    ``seeded`` the files copied in from the targets to their (size, mtime) when copied."""

    targets: list[Target]
    roots: dict[Path, Path] = field(default_factory=dict)
    files: dict[Path, Path] = field(default_factory=dict)
    seeded: dict[Path, tuple[int, int]] = field(default_factory=dict)

    def staged(self, t: Target) -> Path:
        """Where the command writes target ``t`` instead."""
        if t.is_file:
            return self.files[t.path]
        return self.roots[t.base] / os.path.relpath(t.path, t.base)

    def names(self) -> list[tuple[str, str]]:
        """(staging path, path as given) pairs, longest first, for renaming what the command prints."""
        pairs = [(str(self.staged(t)), t.shown) for t in self.targets]
        return sorted(pairs, key=lambda p: -len(p[0]))

    def commit(self, code: int) -> int:
        """Move the staged files into place when ``code`` is 0 and the outputs agree; return the exit code."""
        if code != ExitCode.OK:
            return code
        messages = inconsistencies(list(dict.fromkeys(self.staged(t) for t in self.targets if not t.is_file)))
        if messages:
            for m in messages:
                print(f"planner: inconsistent outputs: {m}", file=sys.stderr)
            return int(ExitCode.INTERNAL)
        for t in self.targets:
            if not t.is_file:
                t.path.mkdir(parents=True, exist_ok=True)
            if t.supersedes:
                self._supersede(t)
        for base, root in self.roots.items():
            for src in sorted(p for p in root.rglob("*") if p.is_file() or p.is_symlink()):
                if self.seeded.get(src) == _stamp(src):
                    continue  # read back, not rewritten
                dest = base / src.relative_to(root)
                dest.parent.mkdir(parents=True, exist_ok=True)
                os.replace(src, dest)
        for final, staged in self.files.items():
            if staged.exists():
                os.replace(staged, final)
        return code

    def _supersede(self, t: Target) -> None:
        """Move the earlier plan's outputs in target folder ``t`` that this run does not rewrite, with the earlier
        plan.json, into ``t/superseded.N`` (nothing moves where no such output is left); say where."""
        staged = self.staged(t)
        stale = [n for n in PLAN_FILES[1:] if (t.path / n).is_file() and not (staged / n).exists()]
        if not stale:
            return
        taken = [
            int(p.name.split(".", 1)[1]) for p in t.path.glob(f"{SUPERSEDED}.*") if p.name.split(".", 1)[1].isdigit()
        ]
        into = t.path / f"{SUPERSEDED}.{max(taken, default=0) + 1}"
        moved = (["plan.json"] if (t.path / "plan.json").is_file() else []) + stale
        for name in moved:
            (into / name).parent.mkdir(parents=True, exist_ok=True)
            os.replace(t.path / name, into / name)
        shown = Path(t.shown) / into.name
        print(
            f"planner: note: the earlier plan's {', '.join(moved)} moved to {shown} (superseded by this plan)",
            file=sys.stderr,
        )


def _stamp(path: Path) -> tuple[int, int]:
    s = path.stat()
    return s.st_size, s.st_mtime_ns


def inconsistencies(folders: Sequence[Path]) -> list[str]:
    """What :func:`planner.report.consistency.check_outputs` finds disagreeing among the staged output folders
    (nothing where that check is not installed, or no folder is written)."""
    if not folders:
        return []
    name = "planner.report.consistency"
    try:
        module = importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name != name:
            raise
        return []
    return [str(m) for m in module.check_outputs(list(folders))]


def _bases(targets: list[Target]) -> list[Target]:
    """The targets with one common base where they share a writable folder on one file system (relative links
    between them then hold in the staging folder too), else each with its own."""
    bases = {t.base for t in targets if not t.is_file}
    if len(bases) < 2:
        return targets
    common = Path(os.path.commonpath([str(b) for b in bases]))
    devices = {b.stat().st_dev for b in bases | {common}}
    if len(devices) > 1 or not os.access(common, os.W_OK | os.X_OK):
        return targets
    return [t if t.is_file else replace(t, base=common) for t in targets]


@contextlib.contextmanager
def staged_outputs(args: argparse.Namespace) -> Iterator[Staging]:
    """Check the outputs ``args`` names, point ``args`` at staging folders for the ``with`` block and print the
    given paths for them; :meth:`Staging.commit` moves the files into place. The staging folders are removed when
    the block ends, whatever happened; a target is touched only by the commit.

    Raises
    ------
    UsageError
        An output the command cannot write (:func:`targets_of`), before anything is created.
    """
    stage = Staging(targets=_bases(targets_of(args)))
    if not stage.targets:
        yield stage
        return
    import shutil  # here, not at the top: a command that writes nothing starts without them
    import tempfile

    saved = {t.dest: getattr(args, t.dest) for t in stage.targets}
    try:
        for base in sorted({t.base for t in stage.targets if not t.is_file}):
            stage.roots[base] = Path(tempfile.mkdtemp(prefix=PREFIX, dir=base))
        for t in stage.targets:
            if t.is_file:  # beside the file: relative paths it records are those from the target's folder
                stage.files[t.path] = _free_name(t.path)
        for t in stage.targets:
            _prepare(stage, t)
            setattr(args, t.dest, str(stage.staged(t)))
        names = stage.names()
        with (
            contextlib.redirect_stdout(Renamed(sys.stdout, names)),
            contextlib.redirect_stderr(Renamed(sys.stderr, names)),
        ):
            yield stage
    finally:
        for dest, value in saved.items():
            setattr(args, dest, value)
        for root in stage.roots.values():
            shutil.rmtree(root, ignore_errors=True)
        for staged in stage.files.values():
            staged.unlink(missing_ok=True)


def _free_name(path: Path) -> Path:
    """A hidden name beside ``path`` that no file has (the command creates the file)."""
    import tempfile

    fd, name = tempfile.mkstemp(prefix=PREFIX, suffix=f"-{path.name}", dir=path.parent)
    os.close(fd)
    os.unlink(name)
    return Path(name)


def _prepare(stage: Staging, t: Target) -> None:
    """Make the staging folder of ``t``, with copies of the files read back from it."""
    import shutil

    if t.is_file:
        return
    staged = stage.staged(t)
    staged.mkdir(parents=True, exist_ok=True)
    if not t.path.is_dir() or any(o.supersedes and o.path == t.path for o in stage.targets):
        return  # a new plan's folder: the sheet there is the earlier plan's
    for name in READ_BACK:
        if (t.path / name).is_file() and not (staged / name).exists():
            shutil.copy2(t.path / name, staged / name)
            stage.seeded[staged / name] = _stamp(staged / name)


class Renamed(io.TextIOBase):
    """A text stream that writes through to ``stream`` with each staging path replaced by the path as given."""

    def __init__(self, stream: TextIO, names: list[tuple[str, str]]) -> None:
        super().__init__()
        self._stream = stream
        self._names = names

    def write(self, s: str) -> int:
        text = s
        for staged, shown in self._names:
            text = text.replace(staged + os.sep, "" if shown == "." else shown + os.sep).replace(staged, shown)
        self._stream.write(text)
        return len(s)

    def flush(self) -> None:
        self._stream.flush()

    def isatty(self) -> bool:
        return self._stream.isatty()

    def fileno(self) -> int:
        return self._stream.fileno()

    @property
    def encoding(self) -> str:  # type: ignore[override]
        return str(getattr(self._stream, "encoding", "utf-8"))
