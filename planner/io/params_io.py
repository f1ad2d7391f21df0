"""A site's instrument and parameters as a record that travels inside the exports (DXF, GeoJSON).

A plan exported to DXF or GeoJSON and read back as a site must plan the same: the drawing carries the geometry, and this
record carries what the geometry does not say (the instrument, theta_max, overlap, sigma_req, the error budget, ...). It
is the :class:`~planner.site.params.Parameters` field by field, so reading it back is exact; unknown keys or values of
the wrong kind are refused, naming the file.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

from planner.core.errors import InputError, located_in
from planner.core.fileio import known_keys, to_float
from planner.instrument.accuracy import ErrorBudget
from planner.instrument.models import load_instrument
from planner.site.model import Site
from planner.site.params import Parameters

#: the record's key in GeoJSON's ``planner`` member and the DXF header's custom property
RECORD_KEY = "tls_planner_site"
#: parameters that are no number: their kind, and what the error says
_KINDS: dict[str, tuple[type, str]] = {
    "incidence_model": (str, "must be a text"),
    "derive_theta_max": (bool, "must be true or false"),
}
_OPTIONAL = {"drawing_scale", "max_slant_range_m"}


@dataclass(frozen=True)
class SiteRecord:
    """What an export says about the site beyond its geometry."""

    name: str
    instrument: str
    parameters: Parameters


def with_record(site: Site, record: SiteRecord | None, parameters: Parameters | None = None) -> Site:
    """``site`` (as its drawing gave it) with the record's name, instrument and parameters; ``parameters``, when the
    caller gives them, win over the record's. No record: ``site`` unchanged."""
    if record is None:
        return site
    return replace(site, name=record.name, instrument=record.instrument, parameters=parameters or record.parameters)


def site_record(name: str, instrument: str, p: Parameters) -> dict[str, Any]:
    """The plain-data record of a site's name, instrument and parameters."""
    return {"name": name, "instrument": instrument, "parameters": asdict(p)}


#: a DXF header property holds text of at most this many characters (the record is cut into numbered parts)
DXF_PART_CHARS = 200


def dxf_properties(record: dict[str, Any]) -> list[tuple[str, str]]:
    """The record as DXF header custom properties ``tls_planner_site.1``, ``.2``, ... of JSON text."""
    text = json.dumps(record, sort_keys=True, separators=(",", ":"))
    parts = [text[k : k + DXF_PART_CHARS] for k in range(0, len(text), DXF_PART_CHARS)]
    return [(f"{RECORD_KEY}.{k}", part) for k, part in enumerate(parts, 1)]


def record_from_dxf(properties: list[tuple[str, str]], file: str) -> SiteRecord | None:
    """The record of :func:`dxf_properties` read back (None: the drawing has none)."""
    parts = sorted(
        (int(tag.rsplit(".", 1)[1]), value)
        for tag, value in properties
        if tag.startswith(RECORD_KEY + ".") and tag.rsplit(".", 1)[1].isdigit()
    )
    if not parts:
        return None
    try:
        raw = json.loads("".join(value for _, value in parts))
    except json.JSONDecodeError as exc:
        raise InputError(f"header property is not JSON ({exc.msg})", file=file, row=RECORD_KEY) from None
    return read_site_record(raw, file)


def read_site_record(raw: Any, file: str) -> SiteRecord:
    """The record written by :func:`site_record`, checked: InputError naming ``file`` and the field."""
    where: dict[str, Any] = {"file": file, "row": RECORD_KEY}
    if not isinstance(raw, dict):
        raise InputError("must be an object", **where, value=type(raw).__name__)
    known_keys(raw, {"name", "instrument", "parameters"}, **where)
    name, instrument, params = raw.get("name"), raw.get("instrument"), raw.get("parameters")
    for key, value in (("name", name), ("instrument", instrument)):
        if not isinstance(value, str) or not value:
            raise InputError("must be a text", **where, field=key, value=value)
    if not isinstance(params, dict):
        raise InputError("must be an object", **where, field="parameters", value=type(params).__name__)
    with located_in(file):
        load_instrument(str(instrument))  # a name this installation knows, else a one-line error
        return SiteRecord(str(name), str(instrument), _parameters(params, where))


def _parameters(raw: dict[str, Any], where: dict[str, Any]) -> Parameters:
    names = {f.name for f in fields(Parameters)}
    known_keys(raw, names, file=where["file"], row=f"{RECORD_KEY}.parameters")
    values: dict[str, Any] = {}
    for key, value in raw.items():
        at = f"parameters.{key}"
        if key == "budget":
            if not isinstance(value, dict):
                raise InputError("must be an object", **where, field=at, value=type(value).__name__)
            known_keys(value, {f.name for f in fields(ErrorBudget)}, file=where["file"], row=f"{RECORD_KEY}.{at}")
            values[key] = ErrorBudget(**{k: to_float(v, field=f"{at}.{k}", **where) for k, v in value.items()})
        elif key in _KINDS:
            kind, message = _KINDS[key]
            if not isinstance(value, kind):
                raise InputError(message, **where, field=at, value=value)
            values[key] = value
        elif value is None and key in _OPTIONAL:
            values[key] = None
        elif key == "drawing_scale":  # the N of 1:N
            n = to_float(value, field=at, **where)
            if not n.is_integer():
                raise InputError("must be a whole number (the N of 1:N)", **where, field=at, value=value)
            values[key] = int(n)
        else:
            values[key] = to_float(value, field=at, **where)
    return Parameters(**values)
