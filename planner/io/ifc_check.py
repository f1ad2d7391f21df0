"""Whole-file checks of an IFC-SPF file, before and after IfcOpenShell reads it.

IfcOpenShell reads a damaged file without a word: a file cut short loads as the entities before the cut, an instance it
cannot parse is left out (with everything after it, when a parenthesis is lost), and a reference to an entity that is
not in the file reads as ``$`` (null). A model read so plans some of its rooms, or its rooms without their walls. So the
text is checked first (the ISO-10303-21 frame: header, data section, end marker; every instance a ``#N=NAME(...);``
statement; every reference defined), then the model against the text (every instance read), then the spatial structure
(every wall, column, door ... stands in a storey, and the ones that shape rooms have a shape). Each failure is one
InputError naming the file and the instance.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from planner.core.errors import InputError
from planner.core.fileio import check_size

#: the end marker of an ISO-10303-21 (STEP physical) file
END_MARKER = "END-ISO-10303-21;"
#: the products that must stand in the spatial structure: spaces, what the reader cuts from rooms, doors
PLACED_TYPES = (
    "IfcSpace",
    "IfcWall",
    "IfcColumn",
    "IfcStair",
    "IfcFurnishingElement",
    "IfcBuildingElementProxy",
    "IfcDoor",
)
#: a quoted string (a quote inside is doubled) or a comment: blanked before the structure is read
_STRING_OR_COMMENT = re.compile(r"'(?:[^']|'')*'|/\*.*?\*/", re.S)
#: ``#N=NAME(...)``, or a complex instance ``#N=(NAME(...)NAME(...))`` (ISO 10303-21's external mapping)
_INSTANCE = re.compile(r"\s*#(\d+)\s*=\s*(?:([A-Za-z][A-Za-z0-9_]*)\s*\((.*)\)|(\(.*\)))\s*", re.S)
_REFERENCE = re.compile(r"#(\d+)")


def spf_instances(path: Path) -> dict[int, str]:
    """The instances of the file's DATA section (id: entity name), after checking the file is whole: it starts with
    ``ISO-10303-21;``, has a HEADER and a DATA section each closed by ``ENDSEC;``, ends with ``END-ISO-10303-21;``, each
    instance is one ``#N=NAME(...);`` with balanced parentheses, no id is given twice and every referenced id is
    defined."""
    file = str(path)
    check_size(path)
    if not path.is_file():
        raise InputError("not a file", file=file)
    try:
        text = path.read_bytes().decode("latin-1")  # SPF is 8-bit text (non-ASCII escaped); latin-1 reads any byte
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror}", file=file) from None
    if not text.strip():
        raise InputError("empty file", file=file)
    if not text.lstrip().startswith("ISO-10303-21;"):
        raise InputError("not an IFC file (an IFC-SPF file starts with ISO-10303-21;)", file=file)
    if not text.rstrip().endswith(END_MARKER):
        raise InputError(f"the file ends before its end marker {END_MARKER}: it is cut short", file=file)
    body = _STRING_OR_COMMENT.sub(lambda m: "''" if m.group().startswith("'") else " ", text)
    if "'" in body.replace("''", ""):
        raise InputError("a text (in single quotes) is not closed: the file is damaged", file=file)
    frame = re.fullmatch(
        r"\s*ISO-10303-21;\s*HEADER;(.*?)ENDSEC;\s*DATA\s*(?:\([^()]*\))?\s*;(.*)ENDSEC;\s*END-ISO-10303-21;\s*",
        body,
        re.S,
    )
    if frame is None:
        raise InputError(
            "no HEADER; ... ENDSEC; DATA; ... ENDSEC; sections before the end marker: the file is damaged", file=file
        )
    return _data_instances(frame.group(2), file)


def _data_instances(data: str, file: str) -> dict[int, str]:
    """The instances of a DATA section (strings and comments blanked), each checked (see :func:`spf_instances`)."""
    names: dict[int, str] = {}
    refs: dict[int, int] = {}
    statements = data.split(";")
    if statements[-1].strip():
        raise InputError(
            "the DATA section ends inside an instance (no ;)", file=file, field="text", value=_cut(statements[-1])
        )
    for stmt in statements[:-1]:
        m = _INSTANCE.fullmatch(stmt)
        args = m.group(3) if m and m.group(2) else m.group(4) if m else ""
        if m is None or not _balanced(args):
            raise InputError(
                "not an entity instance #N=NAME(...);", file=file, row=_row(stmt), field="text", value=_cut(stmt)
            )
        n = int(m.group(1))
        if n in names:
            raise InputError("entity id given twice", file=file, row=f"#{n}", value=m.group(2))
        names[n] = m.group(2).upper() if m.group(2) else "complex instance"
        for r in _REFERENCE.findall(args):
            refs.setdefault(int(r), n)
    missing = sorted(set(refs) - set(names))
    if missing:
        r = missing[0]
        raise InputError(
            f"#{r} is referenced but not defined ({len(missing)} such): lines of the file are missing",
            file=file,
            row=f"#{refs[r]}",
            value=f"#{r}",
        )
    if not names:
        raise InputError("the DATA section holds no entity", file=file)
    return names


def _balanced(args: str) -> bool:
    """Whether the parentheses of an instance's arguments (strings blanked) nest properly."""
    depth = 0
    for ch in re.findall(r"[()]", args):
        depth += 1 if ch == "(" else -1
        if depth < 0:
            return False
    return depth == 0


def _row(stmt: str) -> str | None:
    m = re.match(r"\s*(#\d+)", stmt)
    return m.group(1) if m else None


def _cut(stmt: str) -> str:
    s = " ".join(stmt.split())
    return s if len(s) <= 40 else s[:37] + "..."


def check_model(model: Any, instances: dict[int, str], file: str) -> None:
    """Refuse a model IfcOpenShell read only in part (an instance of an entity the schema does not know, or one it
    could not parse, is left out silently), and one whose walls, columns, doors ... stand in no storey (the spaces
    would miss them)."""
    read = {e.id() for e in model}
    lost = sorted(set(instances) - read)
    if lost:
        n = lost[0]
        raise InputError(
            f"IfcOpenShell could not read {len(lost)} instance(s) (an entity unknown to the schema "
            f"{model.schema} or malformed attributes)",
            file=file,
            row=f"#{n}",
            field="entity",
            value=instances[n],
        )
    import ifcopenshell.util.element as ue

    for space in model.by_type("IfcSpace"):
        parent = _storey_of(space)
        if parent is not None and not parent.is_a("IfcBuildingStorey"):
            raise InputError(
                f"the space stands in {parent.is_a()} {parent.Name or parent.GlobalId!r}, in no storey: the planner "
                "reads the spaces of storeys (aggregate it into an IfcBuildingStorey)",
                file=file,
                row=f"#{space.id()}",
                field="IfcSpace",
                value=space.LongName or space.Name or space.GlobalId,
            )
    for kind in PLACED_TYPES:
        for e in model.by_type(kind):
            if ue.get_container(e) is None and ue.get_aggregate(e) is None:
                raise InputError(
                    "stands in no storey (no IfcRelContainedInSpatialStructure holds it): the spaces would miss it",
                    file=file,
                    row=f"#{e.id()}",
                    field=e.is_a(),
                    value=e.Name or e.GlobalId,
                )


def _storey_of(element: Any) -> Any:
    """The storey an element stands in (through containment and aggregation), else the element it stands in (an
    IfcBuilding, an IfcSite), else None."""
    import ifcopenshell.util.element as ue

    parent, above = element, None
    for _ in range(64):  # a cycle in a damaged model ends here
        parent = ue.get_container(parent) or ue.get_aggregate(parent)
        if parent is None or parent.is_a("IfcBuildingStorey"):
            return parent or above
        above = above or parent
    return above
