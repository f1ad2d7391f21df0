"""Point spacing of a view on a wall piece (issue 47, planner.coverage.spacing).

A setting "6.3 mm @ 10 m" steps 6.3e-4 rad. Hand check: a wall along the x axis from (-1, 0) to (1, 0), height
0, the instrument on the floor (ih = 0) at (0, 10). At the piece's middle the beam meets the wall square at 10 m:
10 x 6.3e-4 = 6.3 mm, the datasheet's figure. At its ends hd = sqrt(101): horizontal hd^2 / d = 101 / 10 = 10.1 m
per radian; vertical (no height: dz = 0) f(hd) = hd = 10.05. So the piece gets 10.1 x 6.3e-4 = 6.363 mm.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planner.core.errors import InputError
from planner.coverage.spacing import point_spacing_m, view_factors
from planner.instrument.field_table import FieldProperties
from planner.instrument.models import load_instrument


def test_a_square_view_at_10_m_gets_the_setting_s_own_spacing():
    f = view_factors(np.array([[0.0, 10.0]]), np.array([[-1.0, 0.0]]), np.array([[1.0, 0.0]]), np.array([0.0]), 0.0)
    assert f[0] == 10.1  # 101 / 10: the ends, horizontally
    mid = point_spacing_m(
        np.array([[0.0, 10.0]]), np.array([[0.0, 0.0]]), np.array([[0.0, -1.0]]), np.array([0.0]), 0.0, 6.3e-4
    )
    assert math.isclose(mid[0], 6.3e-3)  # square at 10 m: 6.3 mm


def test_a_tall_wall_is_spaced_vertically_twice_its_height_at_best():
    """The top of a wall H above the instrument: f(hd) = hd + H^2 / hd >= 2H, reached at hd = H. A 26.5 m wall
    (Baalbek's tallest, instrument on the floor) at the P30's finest 1.6 mm @ 10 m: 53 x 1.6e-4 = 8.48 mm."""
    h = 26.5
    hd = np.linspace(5, 60, 1101)
    f = view_factors(
        np.stack([np.zeros_like(hd), hd], axis=1),
        np.tile([[-0.01, 0.0]], (len(hd), 1)),
        np.tile([[0.01, 0.0]], (len(hd), 1)),
        np.full(len(hd), h),
        0.0,
    )
    assert math.isclose(f.min(), 2 * h, rel_tol=1e-4)
    assert math.isclose(f.min() * 1.6e-4, 8.48e-3, rel_tol=1e-3)


def _brute_force(station, a, b, top, ih, n=41):
    """The largest spacing per radian over the piece, by finite differences of the beam's hits: points along
    a-b (ends and the perpendicular foot included), at the foot and the top of the wall."""
    step = 1e-7
    ab = b - a
    length = np.hypot(*ab)
    u = ab / length
    normal = np.array([-u[1], u[0]])
    pa = station - a
    along = np.clip(pa @ u, 0, length)
    worst = 0.0
    for t in np.unique(np.r_[np.linspace(0, length, n), along]):
        p = a + u * t
        v = p - station
        hd = np.hypot(*v)
        d = abs(v @ normal)
        # horizontal: turn the beam by step, meet the wall line again
        phi = math.atan2(v[1], v[0]) + step
        r = np.array([math.cos(phi), math.sin(phi)])
        denom = r @ normal
        if abs(denom) > 1e-12:
            k = ((p - station) @ normal) / denom
            worst = max(worst, np.hypot(*(station + k * r - p)) / step)
        for z in (0.0, top):  # foot and top, relative heights
            eps = math.atan2(z - ih, hd)
            worst = max(worst, abs(hd * math.tan(eps + step) - hd * math.tan(eps)) / step)
            worst = max(worst, abs(hd * math.tan(eps - step) - hd * math.tan(eps)) / step)
        assert d > 0
    return worst


@settings(max_examples=80, deadline=None)
@given(
    sx=st.floats(-8, 8),
    sy=st.floats(0.3, 12),
    ax=st.floats(-6, 6),
    length=st.floats(0.05, 4),
    top=st.floats(0.0, 12),
    ih=st.floats(0.0, 2.0),
)
def test_the_piece_factor_is_the_largest_spacing_over_the_piece(sx, sy, ax, length, top, ih):
    """Against a brute-force oracle on random views: the factor bounds every point's spacing (foot to top, end to
    end), and is reached (within the oracle's sampling)."""
    station = np.array([sx, sy])
    a, b = np.array([ax, 0.0]), np.array([ax + length, 0.0])
    f = view_factors(station[None], a[None], b[None], np.array([top]), ih)[0]
    brute = _brute_force(station, a, b, top, ih)
    assert brute <= f * (1 + 1e-4) + 1e-9
    assert f <= brute * (1 + 1e-3) + 1e-6


def test_settings_are_read_from_their_names_coarsest_first():
    p30 = load_instrument("leica-p30").field_properties
    assert p30 is not None
    steps = [(name, round(step, 9)) for name, step, _ in p30.by_step()]
    assert steps == [
        ("12.5 mm @ 10 m", 0.00125),
        ("6.3 mm @ 10 m", 0.00063),
        ("3.1 mm @ 10 m", 0.00031),
        ("1.6 mm @ 10 m", 0.00016),
    ]


def test_a_setting_named_without_a_spacing_is_refused_with_its_name():
    props = FieldProperties(scan_times_s=(("high", 300.0),), default_setting="high")
    with pytest.raises(InputError, match=r"field\.scan_time_s\.high = 'high': names no point spacing") as err:
        props.step_rad("high")
    assert "\n" not in str(err.value)


def test_every_bundled_scanner_names_its_settings_by_spacing():
    """Each model's [field] settings give an angular step (--max-point-spacing works with every bundled scanner)."""
    from planner.instrument.models import Scanner, list_instruments

    models = [load_instrument(name) for name in list_instruments()]
    scanners = [m for m in models if isinstance(m, Scanner)]
    assert len(scanners) >= 3
    for m in scanners:
        props = m.field_properties
        assert props is not None, m.name
        steps = [step for _, step, _ in props.by_step()]
        assert steps == sorted(steps, reverse=True) and all(s > 0 for s in steps), m.name
