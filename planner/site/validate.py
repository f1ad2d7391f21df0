"""What ``planner validate`` reports: the site as read, its closures, corrections and limits."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from planner.core.checks import argument
from planner.core.errors import InputError, located_in
from planner.instrument.models import Scanner, load_instrument
from planner.site.model import Site
from planner.site.params import RangeLimit, ThetaLimit, resolve_range_limit, resolve_theta_limit

#: the fields of a :class:`~planner.site.features.Correction` the report lists after its zone and target
_CORRECTION_KEYS = ("field", "printed", "corrected", "reason")


def site_scanner(site: Site) -> Scanner:
    """The site's instrument, which must be a scanner for planning."""
    inst = load_instrument(site.instrument)
    if not isinstance(inst, Scanner):
        raise InputError(
            "is a total station; planning needs a scanner",
            file=site.source or None,
            field="instrument",
            value=site.instrument,
        )
    return inst


@dataclass(frozen=True)
class ValidationReport:
    """A site checked end to end: zones closed, corrections listed, S_max resolved."""

    site: Site
    scanner: Scanner
    range_limit: RangeLimit
    theta_limit: ThetaLimit | None = None

    @property
    def theta_max_deg(self) -> float:
        """The incidence limit of the coverage test (the model's limit when theta_max is derived)."""
        return self.site.parameters.theta_max_deg if self.theta_limit is None else self.theta_limit.theta_max_deg

    def to_dict(self) -> dict[str, Any]:
        p = self.site.parameters
        return {
            "instance": self.site.name,
            "source": self.site.source,
            "instrument": self.scanner.name,
            "parameters": {
                "theta_max_deg": p.theta_max_deg,
                "overlap": p.overlap,
                "sigma_req_m": p.sigma_req_m,
                "drawing_scale": p.drawing_scale,
                "sigma_0_m": p.budget.sigma_0_m,
                "centring_m": p.budget.centring_m,
                "graphical_m": p.budget.graphical_m,
                "instrument_height_m": p.instrument_height_m,
                "max_slant_range_m": self.range_limit.max_slant_range_m,
                "max_slant_range_source": self.range_limit.source,
                "sigma_instr_m": self.range_limit.sigma_instr_m,
                "incidence_model": p.incidence_model,
                "min_standoff_m": p.min_standoff_m,
                "theta_max_derived": None
                if self.theta_limit is None or not self.theta_limit.by_range
                else [{"slant_m": s, "theta_max_deg": t} for s, t in self.theta_limit.by_range],
            },
            "zones": [_zone_dict(z) for z in self.site.zones],
            "obstacles": [
                {"name": o.name, "polygon": [list(v) for v in o.vertices], "height_m": o.height_m}
                for o in self.site.obstacles
            ],
            "no_go": [{"name": a.name, "polygon": [list(v) for v in a.vertices]} for a in self.site.no_go_areas],
            "boundary": None if self.site.boundary is None else [list(v) for v in self.site.boundary],
            "control_points": [
                {"name": c.name, "x": c.x, "y": c.y, "z": c.z, "sigma_x_m": c.sigma_x_m, "sigma_y_m": c.sigma_y_m}
                for c in self.site.control_points
            ],
            "corrections": [
                {"zone": c.zone, "target": c.target} | {k: getattr(c, k) for k in _CORRECTION_KEYS}
                for c in self.site.corrections
            ],
            "accepted_misclosures": [asdict(a) for a in self.site.accepted_misclosures],
        }

    def _repr_html_(self) -> str:
        from planner.core.text import summary_html

        return summary_html(self, "Validation")

    def summary(self) -> str:
        """A plain-text report for the terminal."""
        s, p, lim = self.site, self.site.parameters, self.range_limit
        scale = f" (drawing scale 1:{p.drawing_scale})" if p.drawing_scale else ""
        out = [
            f"instance   {s.name}  ({s.source})",
            f"instrument {self.scanner.name}: {self.scanner.description}",
            f"limits     S_max {lim.max_slant_range_m:.3f} m [{lim.source}], theta_max {'derived' if p.derive_theta_max else f'{p.theta_max_deg:g} deg'}, "
            f"overlap {p.overlap:.0%}, sigma_req {p.sigma_req_m * 1000:g} mm{scale}, sigma_instr {lim.sigma_instr_m * 1000:.4f} mm, "
            f"IH {p.instrument_height_m:g} m",
            f"accuracy   incidence model {p.incidence_model}, stand-off {p.min_standoff_m:g} m from walls and obstacles"
            + ("" if self.theta_limit is None or not self.theta_limit.by_range else f"; {self.theta_limit.summary()}"),
            "",
            f"{'zone':<9}{'side':<9}{'walls':>6}{'perimeter m':>13}{'area m2':>12}  closure",
        ]
        for z in s.zones:
            closure = z.closure.summary() if z.closure else "given by coordinates"
            out.append(
                f"{z.id:<9}{z.scan_side.value:<9}{len(z.walls):>6}{z.perimeter_m:>13.3f}{z.area_m2:>12.1f}  {closure}"
            )
        out.append(f"{'total':<18}{len(s.walls):>6}{sum(z.perimeter_m for z in s.zones):>13.3f}")
        out.append(
            f"obstacles {len(s.obstacles)}, no-go areas {len(s.no_go_areas)}, "
            f"boundary {'yes' if s.boundary else 'none'}, control points {len(s.control_points)}"
        )
        out += ["", "walls (index: length m, top height start..end m, printed height)"]
        for z in s.zones:
            cells = [
                f"{w.index}: {w.length_m:.3f}, {w.h_start_m:g}..{w.h_end_m:g}"
                + ("" if w.printed_height_m is None else f", {w.printed_height_m:g}")
                for w in z.walls
            ]
            out.append(f"  {z.id}: " + "; ".join(cells))
        bad = [(z.id, w) for z in s.zones for w in z.height_check_failures()]
        ok = "wall heights: every printed wall height is the max of its two vertex heights"
        out += ["", "wall heights that are not the max of their vertex heights:" if bad else ok]
        out += [
            f"  {zid} wall {w.index}: printed {w.printed_height_m:g}, vertices {w.h_start_m:g} / {w.h_end_m:g}"
            for zid, w in bad
        ]
        out += ["", f"corrections applied: {len(s.corrections)}"]
        out += [
            f"  {c.zone} {c.target} {c.field}: printed {c.printed:g} -> {c.corrected:g}. {c.reason}"
            for c in s.corrections
        ]
        out.append(f"misclosures accepted: {len(s.accepted_misclosures)}")
        for a in s.accepted_misclosures:
            out.append(
                f"  {a.zone}: {a.angular_misclosure_deg:+.3f} deg, {a.linear_misclosure_m:.3f} m (compass rule). {a.reason}"
            )
        notes = [f"  {z.id}: {n}" for z in s.zones for n in z.notes]
        if notes:
            out += ["notes:"] + notes
        return "\n".join(out)


def _zone_dict(z: Any) -> dict[str, Any]:
    c = z.closure
    closure = (
        None
        if c is None
        else {
            "angle_sum_deg": c.angle_sum_deg,
            "angular_misclosure_deg": c.angular_misclosure_deg,
            "linear_misclosure_m": c.linear_misclosure_m,
            "dx_m": c.misclosure_dx_m,
            "dy_m": c.misclosure_dy_m,
            "relative_precision": None if math.isinf(c.relative_precision) else c.relative_precision,
            "max_vertex_shift_m": c.max_vertex_shift_m,
            "accepted_reason": c.accepted_reason,
        }
    )
    return {
        "id": z.id,
        "side": z.scan_side.value,
        "frame": z.frame,
        "perimeter_m": z.perimeter_m,
        "area_m2": z.area_m2,
        "polygon": [list(v) for v in z.vertices],
        "vertex_heights_m": list(z.vertex_heights_m),
        # the floor and ceiling of docs/instance-format.md, only where not the defaults (floor 0, no ceiling)
        **({"floor_level_m": z.floor_level_m} if z.floor_level_m != 0.0 else {}),
        **({"ceiling_height_m": z.ceiling_height_m} if z.ceiling_height_m is not None else {}),
        "closure": closure,
        "notes": list(z.notes),
    }


def validate_site(site: Site) -> ValidationReport:
    """Check that a loaded site can be planned: its instrument exists and S_max is defined."""
    argument(site, Site, "site")
    with located_in(site.source or None):
        scanner = site_scanner(site)
        limit = resolve_range_limit(site.parameters, scanner)
        theta = resolve_theta_limit(site.parameters, scanner, limit.max_slant_range_m)
    return ValidationReport(site=site, scanner=scanner, range_limit=limit, theta_limit=theta)
