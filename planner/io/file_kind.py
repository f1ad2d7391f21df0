"""Which kind of file a path names: a site, a plan.json, a field sheet, a network report, control points... judged
from the suffix and, for JSON and CSV, from the top of the file, before any reader runs.

The command line asks this first so that a file given in the wrong place (a site where a plan belongs, a plan
where a site belongs) is said as such, in one line, instead of the reader's complaint about a key it does not
know. Only the standard library and :mod:`planner.core` are imported here: the answer comes before numpy,
shapely or the planning stack load (docs/startup.md).

A JSON file of up to :data:`HEAD_BYTES` is parsed whole (:func:`planner.core.fileio.read_json`: invalid JSON is
refused here, in the words its reader would use); of a larger one only the first :data:`HEAD_BYTES` are scanned
for the top-level keys, so that a big file is not parsed twice.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from planner.core.errors import InputError
from planner.core.fileio import read_json

__all__ = ["EXPECTED", "HEAD_BYTES", "KINDS", "SITE_SUFFIXES", "file_kind"]

#: the suffixes of site files and what they hold: the formats :func:`planner.io.load.load_site` reads
SITE_SUFFIXES = {
    ".json": "JSON instance",
    ".csv": "table CSV",
    ".dxf": "DXF drawing",
    ".geojson": "GeoJSON",
    ".pol": "AGPLIB polygon",
    ".ifc": "IFC building model",
}

#: each kind :func:`file_kind` answers, as a message names a file of it ("x is ...")
KINDS = {
    "site": "a site file",
    "plan": "a plan",
    "field sheet": "a field sheet (written by planner field)",
    "network report": "a network report (network.json written by planner network --out)",
    "coverage problem": "a coverage problem (written by planner export)",
    "control": "a list of control points",
    "observations": "a file of field observations",
    "traverse": "a traverse",
    "station list": "a station list (stations.csv written by planner plan --export csv)",
    "web page": "a web page (report.html or field.html)",
    "pdf": "a PDF document",
    "toml": "a TOML file (an instrument model or a --config profile)",
    "folder": "a folder",
    "unknown": "a file of unknown kind",
}

#: what a command that reads a file of each kind expects there ("planner x expects ...")
EXPECTED = {
    "site": "a site file (" + ", ".join(SITE_SUFFIXES.values()).replace(", IFC", " or IFC") + ")",
    "plan": "a plan.json written by `planner plan --out DIR`",
    "control": "control points (a JSON list of {name, x, y, sigma_x_mm, sigma_y_mm})",
    "observations": "field observations (JSON {angle_unit, length_unit, observations: [...]})",
    "traverse": "a traverse (JSON {points: [{name, x, y}], legs: [[from, to], ...]})",
}

#: the bytes of a JSON file scanned to judge it; one no longer than this is parsed whole
HEAD_BYTES = 1 << 20
#: the bytes of a CSV file read to judge it (its comment lines and header)
CSV_HEAD_BYTES = 1 << 12

_JSON = (".json", ".geojson")

_BY_SUFFIX = {
    ".dxf": "site",
    ".pol": "site",
    ".ifc": "site",
    ".html": "web page",
    ".htm": "web page",
    ".pdf": "pdf",
    ".toml": "toml",
    ".mps": "coverage problem",
}

#: a JSON string or one of the structural characters (numbers and literals are skipped)
_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[{}\[\]:]')


def file_kind(path: str | os.PathLike[str]) -> str:
    """The kind of file ``path`` names: a key of :data:`KINDS` ("unknown" where neither the suffix nor the top of
    the file tells; the reader then judges it).

    Raises
    ------
    InputError
        The file does not exist or cannot be read, or is a JSON file of up to :data:`HEAD_BYTES` that is no valid
        JSON (exit 3), each naming the file.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    try:
        if p.is_dir():
            return "folder"
        whole = p.stat().st_size <= HEAD_BYTES
        with p.open("rb") as f:  # opened in any case: a file that cannot be read is said here
            head = f.read(CSV_HEAD_BYTES if suffix == ".csv" else HEAD_BYTES if suffix in _JSON and not whole else 0)
    except OSError as exc:
        raise InputError(f"cannot read file: {exc.strerror or exc}", file=str(path)) from None
    if suffix in _BY_SUFFIX:
        return _BY_SUFFIX[suffix]
    if suffix == ".csv":
        return _csv_kind(head.decode("utf-8-sig", errors="ignore"))
    if suffix not in _JSON:
        return "unknown"
    top, keys = _json_top(p) if whole else _scan(head.decode("utf-8-sig", errors="ignore"))
    if suffix == ".geojson":  # a field sheet's GeoJSON names its frame; a plan's export reads back as its site
        return "field sheet" if "frame" in keys and "planner" not in keys else "site"
    return _json_kind(top, keys)


def _csv_kind(head: str) -> str:
    """A table CSV (a site), or a station list or a field sheet by their first lines."""
    lines = head.splitlines()
    if lines and lines[0].startswith("# tls-planner station list"):
        return "station list"
    header = next((line for line in lines if line.strip() and not line.startswith("#")), "")
    return "field sheet" if header.replace('"', "").startswith("no.,station") else "site"


def _json_top(path: Path) -> tuple[str, frozenset[str]]:
    """The top-level value's type ("object", "array" or "other") and its keys (for an array, the keys of the
    objects in it), the file parsed whole."""
    data = read_json(path)
    if isinstance(data, dict):
        return "object", frozenset(data)
    if isinstance(data, list):
        return "array", frozenset(k for item in data[:100] if isinstance(item, dict) for k in item)
    return "other", frozenset()


def _scan(text: str) -> tuple[str, frozenset[str]]:
    """:func:`_json_top` of the beginning of a large file: its strings and brackets scanned, the keys at the top
    level (of an array: one level down) kept; what the cut leaves incomplete is not judged."""
    start = text.lstrip()[:1]
    top = {"{": "object", "[": "array"}.get(start, "other")
    depth_of_keys = 1 if top == "object" else 2
    keys: set[str] = set()
    depth, last = 0, None
    for m in _TOKEN.finditer(text):
        token = m.group()
        if token in "{[":
            depth += 1
        elif token in "}]":
            depth -= 1
            if depth <= 0:
                break
        elif token == ":" and last is not None and depth == depth_of_keys:
            keys.add(last)
        last = token[1:-1] if token.startswith('"') else None
    return top, frozenset(keys)


def _json_kind(top: str, keys: frozenset[str]) -> str:
    """The kind of a JSON file by its top-level keys (each writer's own keys first: a network report and a plan
    both list ``stations``, a plan and a site both list ``zones``)."""
    if top == "array":
        return "control" if "name" in keys and keys & {"x", "y"} else "unknown"
    if top != "object":
        return "unknown"
    rules = (
        ("network report", bool(keys & {"nodes", "network_rms_m", "accuracy_check"})),
        ("field sheet", bool(keys & {"route_length_m", "setups"}) or {"mode", "order"} <= keys),
        ("coverage problem", {"candidates", "targets"} <= keys),
        ("observations", "observations" in keys),
        ("traverse", "legs" in keys),
        ("plan", bool(keys & {"stations", "method"})),
        ("site", bool(keys & {"zones", "format"})),
    )
    return next((kind for kind, hit in rules if hit), "unknown")
