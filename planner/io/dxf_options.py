"""Which DXF layers hold what, the layer default heights and the arc flattening of the DXF reader.

:class:`DxfOptions` is checked when it is made: a bad value is a :class:`~planner.core.errors.UsageError` naming the
field, before any file is read.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from planner.core.checks import real
from planner.core.errors import UsageError
from planner.site.model import ScanSide

ZONE_LAYERS: dict[str, ScanSide | None] = {
    "WALLS": None,
    "ZONES": None,
    "ZONES-INSIDE": ScanSide.INSIDE,
    "ZONES-OUTSIDE": ScanSide.OUTSIDE,
    "ZONES-BOTH": ScanSide.BOTH,
}


@dataclass(frozen=True, kw_only=True)
class DxfOptions:
    """Which layers hold what (names compared case-insensitively) and the defaults.

    ``zone_layers``: zone layer names and the scan side each gives (None: from XDATA, else ``default_side``);
    ``obstacle_layers``, ``hole_layers``, ``nogo_layers``: the layers of obstacles, free-standing blocks (holes) and
    no-go areas; ``layer_heights_m``: the wall height (m, finite, > 0) of polylines on a layer that carry none;
    ``default_side``: the scan side of zones whose layer and XDATA do not say; ``flatten_m``: the largest deviation
    (m, finite, > 0) of the flattened arcs and circles from the true curve.
    """

    zone_layers: dict[str, ScanSide | None] = field(default_factory=lambda: dict(ZONE_LAYERS))
    obstacle_layers: tuple[str, ...] = ("OBSTACLES",)
    hole_layers: tuple[str, ...] = ("HOLES",)
    nogo_layers: tuple[str, ...] = ("NOGO", "NO-GO")
    layer_heights_m: dict[str, float] = field(default_factory=dict)
    default_side: ScanSide = ScanSide.INSIDE
    flatten_m: float = 0.01

    def __post_init__(self) -> None:
        real(self.flatten_m, "flatten_m", above=0.0)
        if not isinstance(self.default_side, ScanSide):  # "inside" from a script: read it as the enum, or refuse
            try:
                object.__setattr__(self, "default_side", ScanSide(self.default_side))
            except ValueError:
                raise UsageError(
                    f"must be one of {', '.join(s.value for s in ScanSide)}",
                    field="default_side",
                    value=self.default_side,
                ) from None
        _one_per_layer(self.layer_heights_m, "layer_heights_m")
        _one_per_layer(self.zone_layers, "zone_layers")
        for layer, height in self.layer_heights_m.items():
            real(height, f"layer_heights_m[{layer!r}]", above=0.0)

    def role(self, layer: str) -> str | None:
        """``zone``, ``obstacle``, ``no_go``, ``hole``, or None for a layer that is not read."""
        u = layer.upper()
        if u in {k.upper() for k in self.zone_layers}:
            return "zone"
        if u in {k.upper() for k in self.obstacle_layers}:
            return "obstacle"
        if u in {k.upper() for k in self.nogo_layers}:
            return "no_go"
        if u in {k.upper() for k in self.hole_layers}:
            return "hole"
        return None

    def layer_side(self, layer: str) -> ScanSide | None:
        """The scan side a zone layer gives its zones (None: XDATA or the default decides)."""
        return {k.upper(): v for k, v in self.zone_layers.items()}.get(layer.upper())

    def layer_height(self, layer: str) -> float | None:
        """The default wall height of ``layer`` (None: none given)."""
        return {k.upper(): v for k, v in self.layer_heights_m.items()}.get(layer.upper())


def _one_per_layer(by_layer: object, name: str) -> None:
    """Refuse a layer named twice (layer names are compared case-insensitively: one value would be lost)."""
    if not isinstance(by_layer, Mapping):
        raise UsageError("must be a dict of layer names", field=name, value=type(by_layer).__name__)
    seen: dict[str, str] = {}
    for layer in by_layer:
        if not isinstance(layer, str) or not layer:
            raise UsageError(
                "layer names must be non-empty text",
                field=name,
                value=layer if isinstance(layer, str) else type(layer).__name__,
            )
        if layer.upper() in seen:
            raise UsageError(
                f"layer given twice ({seen[layer.upper()]!r} and {layer!r}; names are case-insensitive)",
                field=name,
                value=layer,
            )
        seen[layer.upper()] = layer
