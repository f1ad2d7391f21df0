"""Art-gallery benchmark polygons (AGPLIB ``.pol``): one line, ``n x1 y1 ... xn yn [h n1 ... ]``.

The outline (counter-clockwise, then h holes) becomes one inside zone scaled to a larger extent of ``extent_m``, every
wall ``height_m`` (docs/exchange.md). Numbers are ASCII rationals ``p/q`` or decimals, read with
:class:`fractions.Fraction`; nothing is evaluated, and a number beyond the range of a float is refused.
"""

from __future__ import annotations

import math
import re
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np

from planner.core.errors import InputError
from planner.core.fileio import read_text
from planner.site.geometry import signed_area
from planner.site.model import ScanSide, Site, Zone
from planner.site.params import Parameters

#: a coordinate: an ASCII rational p/q or a decimal number (no digit grouping, no inf/nan, no other digits)
_RATIONAL = r"[+-]?[0-9]+/[0-9]+"
_DECIMAL = r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?"
#: a count has at most this many digits (the file size limit allows far fewer vertices)
MAX_COUNT_DIGITS = 12


def _shown(tok: str) -> str:
    """The token as an error message quotes it (a 400-digit number cut short)."""
    return tok if len(tok) <= 40 else f"{tok[:37]}..."


def _number(tok: str, file: str, k: int) -> float:
    where = dict(file=file, row=f"token {k}", field="number", value=_shown(tok))
    try:
        if re.fullmatch(_RATIONAL, tok):
            p, q = tok.split("/")
            value = float(Fraction(int(p), int(q)))
        elif re.fullmatch(_DECIMAL, tok):
            value = float(tok)  # a decimal exponent (1e400) gives inf here, in no time
        else:
            raise ValueError(tok)
    except (ValueError, ZeroDivisionError):  # int() refuses numbers of more than 4300 digits
        raise InputError("not a number p/q", **where) from None
    except OverflowError:
        value = math.inf
    if not math.isfinite(value):
        raise InputError(f"number out of range (beyond +-{sys.float_info.max:.3g})", **where)
    return value


def _count(tok: str, file: str, k: int, what: str) -> int:
    where = dict(file=file, row=f"token {k}", field="count", value=_shown(tok))
    if not (tok.isascii() and tok.isdigit()):  # str.isdigit() alone takes a superscript 2, which int() does not
        raise InputError(f"expected the number of {what}", **where)
    if len(tok) > MAX_COUNT_DIGITS:
        raise InputError(f"more {what} than a file within the size limit can hold", **where)
    return int(tok)


def read_pol(
    path: Path | str, extent_m: float = 100.0, height_m: float = 3.0, parameters: Parameters | None = None
) -> Site:
    """Read a ``.pol`` file as a one-zone site (see the module docstring)."""
    file = str(path)
    toks = read_text(Path(path)).split()
    pos = 0

    def ring(what: str) -> np.ndarray:
        nonlocal pos
        if pos >= len(toks):
            raise InputError(f"file ends before the {what}", file=file, row=f"token {pos + 1}")
        n = _count(toks[pos], file, pos + 1, f"vertices of the {what}")
        if n < 3:
            raise InputError(f"the {what} needs at least 3 vertices", file=file, row=f"token {pos + 1}", value=n)
        if pos + 1 + 2 * n > len(toks):
            raise InputError(
                f"{what} promises {n} vertices; the file ends first", file=file, row=f"token {pos + 1}", value=n
            )
        vals = [_number(toks[pos + 1 + i], file, pos + 2 + i) for i in range(2 * n)]
        pos += 1 + 2 * n
        return np.array(vals, dtype=float).reshape(n, 2)

    outer = ring("outline")
    holes = []
    if pos < len(toks):
        h = _count(toks[pos], file, pos + 1, "holes")
        pos += 1
        holes = [ring(f"hole {k}") for k in range(1, h + 1)]
    if pos != len(toks):
        where = dict(file=file, row=f"token {pos + 1}", field="token", value=_shown(toks[pos]))
        raise InputError("unexpected tokens after the last ring", **where)
    lo = outer.min(axis=0)
    scale = extent_m / float(np.ptp(outer, axis=0).max() or 1.0)
    outer = (outer - lo) * scale
    holes = [(r - lo) * scale for r in holes]
    if signed_area(outer) < 0:
        outer = outer[::-1]
    holes = [r if signed_area(r) < 0 else r[::-1] for r in holes]
    try:
        zone = Zone(
            id="P",
            scan_side=ScanSide.INSIDE,
            vertices=tuple(map(tuple, outer.tolist())),
            vertex_heights_m=(height_m,) * len(outer),
            holes=tuple(tuple(map(tuple, r.tolist())) for r in holes),
            hole_heights_m=tuple((height_m,) * len(r) for r in holes),
            notes=(
                f"AGPLIB coordinates scaled by {scale:.6g} (larger extent {extent_m:g} m), origin moved to the bounding box",
            ),
        )
    except InputError as exc:
        raise exc.located(file) from None
    return Site(name=Path(path).stem, zones=(zone,), parameters=parameters or Parameters(), source=file)
