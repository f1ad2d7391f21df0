"""Whole-file checks of an ASCII DXF file before ezdxf reads it.

A DXF file is a list of group-code/value pairs, two lines each, ending with the pair ``0``/``EOF``. A file cut short
lacks that end marker; a line dropped or added shifts every pair after it, so that values stand where group codes
should and numbers where names should. ezdxf reads some such files without a word (a tag it does not expect is read
past), so the pairs are checked first: every group code a whole number in DXF's range, every value of a numeric group
code a number, the last pair ``0``/``EOF``. Each failure is one InputError naming the file and the line. A binary DXF
is left to ezdxf.
"""

from __future__ import annotations

import re
from pathlib import Path

from planner.core.errors import InputError

#: group codes whose value is a real number, and those whose value is a whole number (the DXF reference's ranges)
FLOAT_CODES = ((10, 59), (110, 149), (210, 239), (460, 469), (1010, 1059))
INT_CODES = ((60, 99), (160, 179), (270, 289), (370, 389), (400, 409), (420, 429), (440, 459), (1060, 1071))
_INT = re.compile(r"[+-]?[0-9]+")
_FLOAT = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")
#: the value of group code 0: a section or entity name (3DFACE, LWPOLYLINE, ACAD_PROXY_ENTITY)
_NAME = re.compile(r"[A-Za-z0-9_]*[A-Za-z][A-Za-z0-9_]*")
BINARY_SENTINEL = b"AutoCAD Binary DXF"
#: the entities the reader reads whose points and vertex counts are checked
POINT_KINDS = frozenset(("LWPOLYLINE", "POLYLINE", "VERTEX", "CIRCLE", "TEXT", "MTEXT", "INSERT"))


def _in(code: int, ranges: tuple[tuple[int, int], ...]) -> bool:
    return any(lo <= code <= hi for lo, hi in ranges)


def check_dxf_pairs(data: bytes, file: str) -> None:
    """Refuse an ASCII DXF whose group-code/value pairs are broken or that does not end with ``0``/``EOF``."""
    if data.startswith(BINARY_SENTINEL):
        return
    lines = (
        data.removeprefix(b"\xef\xbb\xbf").decode("latin-1").splitlines()
    )  # the structure is ASCII; names in any code page pass through
    while lines and not lines[-1].strip():
        lines.pop()
    if not lines:
        raise InputError("empty file", file=file)
    if lines[0].strip() not in ("0", "999"):  # a DXF starts with a section (0 SECTION) or a comment (999)
        raise InputError("not a DXF file (an ASCII DXF starts with the pair 0 SECTION)", file=file)
    if len(lines) < 2 or lines[-2].strip() != "0" or lines[-1].strip() != "EOF":
        raise InputError(
            "not a readable DXF file: it ends without its end marker (group 0 EOF): it is cut short", file=file
        )
    record: list[tuple[int, str, int]] = []  # the pairs of the entity being read: (code, value, line)
    for k in range(0, len(lines) - 1, 2):
        raw, value = lines[k].strip(), lines[k + 1].strip()
        where = dict(file=file, row=f"line {k + 1}")
        if not _INT.fullmatch(raw) or not -5 <= int(raw) <= 1071:
            raise InputError(
                "not a readable DXF file: not a group code (a whole number from -5 to 1071), the pairs are shifted "
                "(a line lost?)",
                **where,
                field="group code",
                value=_shown(raw),
            )
        code = int(raw)
        if code == 0 and not _NAME.fullmatch(value):
            raise InputError(
                "not a readable DXF file: group code 0 needs a section or entity name (the pairs shifted?)",
                file=file,
                row=f"line {k + 2}",
                field="value",
                value=_shown(value),
            )
        if code == 0:
            _check_record(record, file)
            record = []
        record.append((code, value, k + 1))
        kind = "real number" if _in(code, FLOAT_CODES) else "whole number" if _in(code, INT_CODES) else None
        pattern = _FLOAT if kind == "real number" else _INT
        if kind and not pattern.fullmatch(value):
            raise InputError(
                f"not a readable DXF file: group code {code} needs a {kind} (the pairs shifted, or the value damaged)",
                file=file,
                row=f"line {k + 2}",
                field="value",
                value=_shown(value),
            )
    if len(lines) % 2:
        raise InputError(
            "not a readable DXF file: an odd number of lines, group codes and values do not pair up (a line lost?)",
            file=file,
        )


def _check_record(record: list[tuple[int, str, int]], file: str) -> None:
    """An entity the reader reads has every point whole (an x group 1n with its y group 2n), and an LWPOLYLINE as many
    vertices as its count (group 90) says: two lines lost together keep the pairs aligned, but not these counts."""
    if not record or record[0][1] not in POINT_KINDS:
        return
    kind, line = record[0][1], record[0][2]
    codes = [c for c, _, _ in record]
    for x in (*range(10, 19), *range(1010, 1014)):
        if codes.count(x) != codes.count(x + 10):
            raise InputError(
                f"not a readable DXF file: {kind} has {codes.count(x)} x values (group {x}) and {codes.count(x + 10)} "
                f"y values (group {x + 10}): lines are missing",
                file=file,
                row=f"line {line}",
            )
    counts = [v for c, v, _ in record if c == 90]
    if kind == "LWPOLYLINE" and counts and int(counts[0]) != codes.count(10):
        raise InputError(
            f"not a readable DXF file: LWPOLYLINE has {codes.count(10)} vertices, its count (group 90) says "
            f"{int(counts[0])}: lines are missing",
            file=file,
            row=f"line {line}",
        )


def _shown(text: str) -> str:
    return text if len(text) <= 40 else text[:37] + "..."


def read_dxf_bytes(path: Path, file: str) -> bytes:
    """The file's bytes (its size checked by the caller), as an InputError when it cannot be read."""
    try:
        return path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror}", file=file) from None
