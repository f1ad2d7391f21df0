"""The reader behind the JSON instance format: a file name that every error names, and the few ways a value is taken
from a JSON object (an object with known keys, a list, a number, a whole number, a length in m or mm, a text, a
polygon)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, overload

from planner.core.errors import InputError
from planner.core.fileio import to_float, to_int
from planner.site.geometry import as_vertices, signed_area


class InstanceReader:
    """Holds the file name so every error can name it."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.file = str(path)

    def fail(self, message: str, **where: Any) -> InputError:
        return InputError(message, file=self.file, **where)

    def obj(self, value: Any, what: str, allowed: set[str], **where: Any) -> dict[str, Any]:
        if not isinstance(value, dict):
            raise self.fail("must be an object", field=what, value=type(value).__name__, **where)
        unknown = sorted(set(value) - allowed)
        if unknown:
            raise self.fail(f"unknown key in {what} (allowed: {', '.join(sorted(allowed))})", field=unknown[0], **where)
        return value

    def items(self, data: dict[str, Any], key: str) -> list[Any]:
        value = data.get(key, [])
        if not isinstance(value, list):
            raise self.fail("must be a list", field=key, value=type(value).__name__)
        return value

    def num(self, data: dict[str, Any], key: str, **where: Any) -> float:
        return to_float(self._given(data, key, where), field=key, file=self.file, **where)

    def whole(self, data: dict[str, Any], key: str, **where: Any) -> int:
        return to_int(self._given(data, key, where), field=key, file=self.file, **where)

    def _given(self, data: dict[str, Any], key: str, where: dict[str, Any]) -> Any:
        if key not in data:
            raise self.fail("missing", field=key, **where)
        return data[key]

    @overload
    def length(self, data: dict[str, Any], base: str, default: float, **where: Any) -> float: ...

    @overload
    def length(self, data: dict[str, Any], base: str, default: None = None, **where: Any) -> float | None: ...

    def length(self, data: dict[str, Any], base: str, default: float | None = None, **where: Any) -> float | None:
        """A length given as ``base_m`` or ``base_mm`` (in metres), or the default."""
        keys = [k for k in (f"{base}_m", f"{base}_mm") if k in data]
        if len(keys) == 2:
            raise self.fail("given twice (in m and mm)", field=base, **where)
        if not keys or data[keys[0]] is None:
            return default
        value = to_float(data[keys[0]], field=keys[0], file=self.file, **where)
        return value / 1000.0 if keys[0].endswith("_mm") else value

    def text(self, data: dict[str, Any], key: str, default: str | None = None, **where: Any) -> str:
        value = data.get(key, default)
        if not isinstance(value, str) or not value.strip():
            raise self.fail("must be a non-empty text", field=key, value=value, **where)
        return value

    def polygon(self, value: Any, what: str, name: str) -> tuple[tuple[float, float], ...]:
        try:
            xy = as_vertices(value, what=what, zone=name)
        except InputError as exc:
            raise exc.located(self.file) from None
        if len(xy) >= 3 and signed_area(xy) < 0:
            xy = xy[::-1]
        return tuple((float(x), float(y)) for x, y in xy)
