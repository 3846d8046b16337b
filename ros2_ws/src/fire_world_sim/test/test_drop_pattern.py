"""Drops as ground patterns (fire_world_sim.drop_pattern, RasterFireModel.apply_pattern).

The pattern is measured on a fine grid, against numbers that do not come from the module:
the load released, the line a tank empties over (v V / Q), free-fall time (h = g/2 -> 1 s), the
unit conversion of a coverage level, and the drop guides' levels by fuel model.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.constants import CellState
from fire_uav_common.scenario import FUEL_MODELS, Ignition, Raster, Wind
from fire_uav_common.terrain import Terrain
from fire_world_sim.drop_pattern import (
    L_PER_M2_PER_CL,
    PatternModel,
    Release,
    coverage_level,
    coverage_lpm2,
    pattern_of,
    required_coverage_lpm2,
)
from fire_world_sim.fires import RasterFireModel

G = 9.80665


def release(**kw) -> Release:
    base = dict(
        x_m=0.0,
        y_m=0.0,
        heading_rad=0.3,
        ground_speed_mps=50.0,
        height_m=20.0,
        volume_l=3000.0,
        flow_lps=750.0,
        wind_mps=(0.0, 0.0),
    )
    base.update(kw)
    return Release(**base)


def field(p, step=0.5):
    """Coverage [L/m^2] on a grid of ``step`` [m] over the pattern and 6 sigma around it."""
    x0, x1, y0, y1 = p.bounds_m(6.0)
    xs = np.arange(x0, x1, step) + step / 2
    ys = np.arange(y0, y1, step) + step / 2
    xx, yy = np.meshgrid(xs, ys)
    return xx, yy, coverage_lpm2(p, xx, yy)


def centre_line(p, step=0.05):
    """(s [m] along the heading from the release point, coverage) on the line through the pattern's
    centre along the heading."""
    h = p.release.heading_rad
    s = np.arange(-4 * p.sigma_m - 50, p.length_m + 4 * p.sigma_m + 50, step)
    cx, cy = p.x0_m, p.y0_m
    return s, coverage_lpm2(p, cx + s * math.cos(h), cy + s * math.sin(h))


def half_max_span(s, c):
    above = s[c >= 0.5 * c.max()]
    return above[-1] - above[0]


@pytest.mark.parametrize(
    "kw",
    [
        {},
        {"ground_speed_mps": 0.0},
        {"height_m": 60.0, "wind_mps": (5.0, -3.0)},
        {"volume_l": 10.0, "flow_lps": 5.0},
    ],
)
def test_volume_on_the_ground_is_the_load(kw):
    p = pattern_of(release(**kw))
    _, _, c = field(p)
    assert float(c.sum()) * 0.25 == pytest.approx(release(**kw).volume_l, rel=1e-3)


def test_a_loss_fraction_takes_its_share():
    p = pattern_of(release(), PatternModel(loss_fraction=0.2))
    _, _, c = field(p)
    assert float(c.sum()) * 0.25 == pytest.approx(0.8 * 3000.0, rel=1e-3)


@pytest.mark.parametrize(
    ("v", "vol", "q"),
    [(50.0, 3000.0, 750.0), (100.0, 3000.0, 750.0), (50.0, 6000.0, 750.0), (50.0, 3000.0, 1500.0)],
)
def test_line_length_is_speed_times_release_time(v, vol, q):
    """Measured on the ground: the span of the centre line wetted at >= half the peak is the line
    the aircraft flies while the tank empties, v V / Q (1 % or one grid step)."""
    p = pattern_of(release(ground_speed_mps=v, volume_l=vol, flow_lps=q, height_m=10.0))
    s, c = centre_line(p)
    assert half_max_span(s, c) == pytest.approx(v * vol / q, rel=0.01)


def test_width_grows_with_height_and_the_peak_falls():
    widths, peaks = [], []
    for h in (5.0, 15.0, 30.0, 60.0):
        p = pattern_of(release(height_m=h))
        hd = p.release.heading_rad
        mid = np.array([p.x0_m + 0.5 * p.length_m * math.cos(hd), p.y0_m + 0.5 * p.length_m * math.sin(hd)])
        n = np.arange(-200.0, 200.0, 0.05)
        c = coverage_lpm2(p, mid[0] - n * math.sin(hd), mid[1] + n * math.cos(hd))
        widths.append(half_max_span(n, c))
        peaks.append(float(c.max()))
    assert all(b > a for a, b in zip(widths, widths[1:], strict=False))
    assert all(b < a for a, b in zip(peaks, peaks[1:], strict=False))
    # a constant-flow tank: the line holds Q / v litres per metre (the peak times the Gaussian's
    # effective width sqrt(2 pi) sigma, sigma = FWHM / 2.3548)
    for w, pk in zip(widths, peaks, strict=True):
        assert pk * math.sqrt(2 * math.pi) * w / (2 * math.sqrt(2 * math.log(2))) == pytest.approx(
            750 / 50, rel=0.01
        )


def test_wind_drifts_the_pattern_over_the_fall_time():
    """h = g / 2 falls in exactly 1 s: the centroid moves by the wind [m/s] in metres."""
    calm = pattern_of(release(height_m=G / 2))
    windy = pattern_of(release(height_m=G / 2, wind_mps=(4.0, -2.5)))
    xx, yy, c0 = field(calm)
    cx0, cy0 = (xx * c0).sum() / c0.sum(), (yy * c0).sum() / c0.sum()
    xx, yy, c1 = field(windy)
    cx1, cy1 = (xx * c1).sum() / c1.sum(), (yy * c1).sum() / c1.sum()
    assert cx1 - cx0 == pytest.approx(4.0, abs=0.01)
    assert cy1 - cy0 == pytest.approx(-2.5, abs=0.01)
    # and from 4 times as high, twice as far (t = sqrt(2 h / g))
    high = pattern_of(release(height_m=2 * G, wind_mps=(4.0, 0.0)))
    assert high.x0_m - pattern_of(release(height_m=2 * G)).x0_m == pytest.approx(8.0, abs=1e-9)


def test_coverage_levels_by_fuel_model():
    assert L_PER_M2_PER_CL == pytest.approx(0.4074, abs=1e-4)  # 1 US gal / 100 ft^2 in L/m^2
    # the drop guides' Table 1 by fire behavior fuel model
    guide = {1: 1, 2: 2, 3: 3, 5: 3, 8: 2, 9: 2, 10: 4, 11: 3, 6: 6, 4: 6}
    for fm, cl in guide.items():
        assert coverage_level(fm) == cl
    assert coverage_level(12) > 6 and coverage_level(13) > 6
    assert all(math.isfinite(coverage_level(m)) for m in FUEL_MODELS)
    assert coverage_level(91) == math.inf  # urban / non-burnable


def _grass_fire(wet_s=600.0):
    spec = Raster(
        nx=40,
        ny=40,
        wind=(Wind(0.0, 0.0, 0.0),),
        ignitions=(Ignition(100.0, 100.0, 0.0),),
        spread_factor=20.0,
        wet_duration_s=wet_s,
    )
    m = RasterFireModel(spec, Terrain())
    t = 0.0
    while (m.state_grid() == CellState.BURNING).sum() < 40:
        m.step(t, 0.5)
        t += 0.5
    return m


def test_burning_cells_go_out_only_above_their_coverage_level():
    m = _grass_fire()
    burning0 = m.state_grid() == CellState.BURNING
    # Q / v = 10 L/m spread by sigma = 7 m: ~0.57 L/m^2 on the centre line, above grass's level 1
    # (0.41 L/m^2) within ~6 m of it, below it further out
    p = pattern_of(
        release(
            x_m=20.0,
            y_m=100.0,
            heading_rad=0.0,
            ground_speed_mps=20.0,
            height_m=10.0,
            volume_l=1600.0,
            flow_lps=200.0,
        )
    )
    xs, ys = np.meshgrid(m.xc, m.yc)
    cov = coverage_lpm2(p, xs, ys)
    hit = m.apply_pattern(p)
    assert hit == [0]
    burning1 = m.state_grid() == CellState.BURNING
    strong = burning0 & (cov >= 1.0 * 0.40746)
    weak = burning0 & (cov < 1.0 * 0.40746)
    assert strong.any() and weak.any()
    assert not (burning1 & strong).any()  # every cell at level 1 out
    assert (burning1[weak]).all()  # every cell below it still burning
    assert m.last_drop_out_cells == int(strong.sum())


def test_brush_needs_more_water_than_grass():
    """The same load on the same burning cells: grass (level 1) goes out, chaparral (level 6) not."""
    out = {}
    for fuel in (1, 4):
        spec = Raster(
            nx=40, ny=40, fuel_model=fuel, ignitions=(Ignition(100.0, 100.0, 0.0),), spread_factor=20.0
        )
        m = RasterFireModel(spec, Terrain())
        t = 0.0
        while (m.state_grid() == CellState.BURNING).sum() < 20:
            m.step(t, 0.5)
            t += 0.5
        before = int((m.state_grid() == CellState.BURNING).sum())
        p = pattern_of(
            release(
                x_m=20.0,
                y_m=100.0,
                heading_rad=0.0,
                ground_speed_mps=20.0,
                height_m=10.0,
                volume_l=1600.0,
                flow_lps=200.0,
            )
        )
        m.apply_pattern(p)
        out[fuel] = before - int((m.state_grid() == CellState.BURNING).sum())
    assert out[1] > 0
    assert out[4] < out[1]


def test_wetted_unburned_cells_stay_wet_in_proportion_to_their_coverage():
    m = _grass_fire(wet_s=600.0)
    p = pattern_of(
        release(
            x_m=150.0,
            y_m=20.0,
            heading_rad=math.pi / 2,
            ground_speed_mps=20.0,
            height_m=10.0,
            volume_l=1600.0,
            flow_lps=200.0,
        )
    )
    m.apply_pattern(p)
    xs, ys = np.meshgrid(m.xc, m.yc)
    cov = coverage_lpm2(p, xs, ys)
    wet_until = m.wet_until[2:-2, 2:-2]
    unburned = m.state_grid() == CellState.UNBURNED
    sel = unburned & (cov >= 0.5 * 0.40746)
    assert sel.sum() > 10
    # the level grass needs (1) keeps a cell wet for wet_duration_s; twice that, twice as long
    np.testing.assert_allclose(wet_until[sel] - m.t_s, 600.0 * cov[sel] / 0.40746, rtol=1e-3)
    assert not np.isfinite(wet_until[unburned & (cov < 0.5 * 0.40746)]).any()


def test_bad_release_is_refused():
    with pytest.raises(ValueError, match="flow_lps"):
        pattern_of(release(flow_lps=0.0))


def test_the_drop_event_names_the_line_the_report_draws():
    from fire_report.figures import drop_line
    from fire_world_sim.world import _pattern_text

    p = pattern_of(release(x_m=-12.5, y_m=300.0, heading_rad=2.0))
    line = drop_line("hit fires [0], 3 of 40 cells burning" + _pattern_text(p, 2))
    assert line == pytest.approx((p.x0_m, p.y0_m, p.x1_m, p.y1_m), abs=0.05)
    assert drop_line("hit fires [0], 3 of 40 cells burning") is None


def test_ff_analytic_fires_keep_the_paper_rule_with_a_pattern():
    """FF V-B: a drop within the fire's sigma halves it, whatever the pattern's coverage."""
    from fire_uav_common.scenario import AnalyticFire
    from fire_world_sim.fires import AnalyticFireModel

    m = AnalyticFireModel((AnalyticFire(x_m=100.0, y_m=100.0, sigma_m=40.0),), extinction_sigma_m=2.0)
    m.step(0.0, 0.1)
    far = pattern_of(release(x_m=-300.0, y_m=100.0, heading_rad=0.0, ground_speed_mps=100.0))
    assert far.length_m >= 400  # the line reaches the fire, but the release point is far from it
    assert m.apply_pattern(far) == []
    near = pattern_of(release(x_m=110.0, y_m=100.0, volume_l=1.0))
    assert m.apply_pattern(near) == [0]
    assert m.truth()[0].extent_m == pytest.approx(20.0)


# --- edges named by the mutation run (docs/testing.md) ----------------------------------------------
def _line_convolved(p, xs, ys, n=20001):
    """(P2) by brute force: the V / L litres per metre of the line from (x0, y0) to (x1, y1), each
    metre smeared by a round Gaussian of sigma, summed by the trapezoid rule along the line."""
    t = np.linspace(0.0, 1.0, n)
    lx, ly = p.x0_m + t * (p.x1_m - p.x0_m), p.y0_m + t * (p.y1_m - p.y0_m)
    out = []
    for x, y in zip(xs, ys, strict=True):
        d2 = (x - lx) ** 2 + (y - ly) ** 2
        g = np.exp(-0.5 * d2 / p.sigma_m**2) / (2 * math.pi * p.sigma_m**2)
        out.append(p.volume_l * float(np.sum((g[1:] + g[:-1]) * 0.5) / (n - 1)))
    return np.array(out)


@pytest.mark.parametrize("speed", [50.0, 2.0])  # a 200 m line, and one of 8 m: shorter than sigma
def test_coverage_is_the_line_smeared_by_the_gaussian(speed):
    p = pattern_of(release(ground_speed_mps=speed, height_m=18.0, heading_rad=0.7))
    assert p.sigma_m == pytest.approx(11.0)
    hd = p.release.heading_rad
    pts = [(s, n) for s in (-15.0, 0.0, 6.0, 0.5 * p.length_m, p.length_m + 4.0) for n in (0.0, 9.0, -20.0)]
    xs = [p.x0_m + s * math.cos(hd) - n * math.sin(hd) for s, n in pts]
    ys = [p.y0_m + s * math.sin(hd) + n * math.cos(hd) for s, n in pts]
    got = coverage_lpm2(p, np.array(xs), np.array(ys))
    assert got == pytest.approx(_line_convolved(p, xs, ys), rel=1e-6, abs=1e-12)


def test_release_bounds_each_refused_alone_and_zero_allowed():
    for kw in ({"ground_speed_mps": -1.0}, {"height_m": -1.0}, {"volume_l": -1.0}):
        with pytest.raises(ValueError, match=r"^ground_speed_mps, height_m and volume_l must be >= 0$"):
            pattern_of(release(**kw))
    for kw in ({"ground_speed_mps": 0.0}, {"height_m": 0.0}, {"volume_l": 0.0}, {"flow_lps": 0.5}):
        pattern_of(release(**kw))
    with pytest.raises(ValueError, match=r"^spread sigma must be > 0, got 0.0$"):
        pattern_of(release(height_m=0.0), PatternModel(sigma0_m=0.0))
    assert pattern_of(release(height_m=0.0), PatternModel(sigma0_m=0.5)).sigma_m == 0.5


def test_a_northward_wind_drifts_it_north_by_wind_times_fall_time():
    """From h = 2 g the fall takes 2 s (P4)."""
    calm, windy = (
        pattern_of(release(height_m=2 * G)),
        pattern_of(release(height_m=2 * G, wind_mps=(0.0, 3.0))),
    )
    assert (windy.x0_m - calm.x0_m, windy.y0_m - calm.y0_m) == pytest.approx((0.0, 6.0), abs=1e-9)


def test_the_required_coverage_is_a_float_grid():
    need = required_coverage_lpm2(np.array([[1, 4], [99, 102]]))
    assert need.dtype == np.float64
    assert need.tolist() == [
        [1.0 * L_PER_M2_PER_CL, 6.0 * L_PER_M2_PER_CL],
        [math.inf, 1.0 * L_PER_M2_PER_CL],
    ]


def test_the_line_is_flown_while_the_tank_empties():
    """(P1): 3000 L at 750 L/s empty in 4 s, 200 m at 50 m/s (the ground-measured test above
    samples the line, which a wrong length of 1e8 m would exhaust memory on)."""
    p = pattern_of(release(ground_speed_mps=50.0, volume_l=3000.0, flow_lps=750.0, heading_rad=0.0))
    assert (p.x1_m - p.x0_m, p.y1_m - p.y0_m) == pytest.approx((200.0, 0.0))


@pytest.mark.parametrize(
    "volume_l, flow_lps, v_mps, h_m, peak_cl",
    [  # docs/suppression.md, "What one load gives on flat ground" (peak [CL], 2 decimals)
        (2000.0, 1000.0, 44.7, 12.0, 2.74),
        (2000.0, 1000.0, 100.0, 36.0, 0.49),
        (3000.0, 757.0, 46.8, 20.0, 1.32),
        (3000.0, 757.0, 60.0, 20.0, 1.03),
        (10.0, 5.0, 15.6, 12.0, 0.04),
        (10.0, 5.0, 0.0, 12.0, None),  # no ground speed: a round heap, V / (2 pi sigma^2)
    ],
)
def test_the_shared_peak_is_the_patterns_highest_coverage(volume_l, flow_lps, v_mps, h_m, peak_cl):
    """fire_uav_common.drop_coverage (P5), which the agents decide their drop runs by, against the
    world's pattern (P2) measured on a 0.25 m grid around the line and the docs' pattern table."""
    from fire_uav_common.drop_coverage import peak_coverage_lpm2

    r = release(heading_rad=0.0, ground_speed_mps=v_mps, height_m=h_m, volume_l=volume_l, flow_lps=flow_lps)
    p = pattern_of(r)
    xs = np.arange(-4.0 * p.sigma_m, p.length_m + 4.0 * p.sigma_m, 0.25)
    ys = np.arange(-1.0, 1.01, 0.25)
    xx, yy = np.meshgrid(xs, ys)
    measured = float(coverage_lpm2(p, xx, yy).max())
    shared = peak_coverage_lpm2(volume_l, flow_lps, v_mps, h_m)
    assert shared == pytest.approx(measured, rel=1e-3)
    assert shared == pytest.approx(p.peak_lpm2, rel=1e-9)
    if peak_cl is not None:
        assert round(shared / L_PER_M2_PER_CL, 2) == peak_cl
    else:
        assert shared == pytest.approx(volume_l / (2.0 * math.pi * p.sigma_m**2), rel=1e-9)
    assert peak_coverage_lpm2(0.0, flow_lps, v_mps, h_m) == 0.0


@pytest.mark.parametrize("v_mps", [0.5, 1.0, 3.0, 10.0])
def test_the_shared_peak_of_a_line_shorter_than_its_spread(v_mps):
    """A slow release lays a line shorter than sigma (2-20 m against 8 m): still the line's peak
    (P5), not the round heap's, as the world's pattern (P2) measured on a 0.1 m grid has it."""
    from fire_uav_common.drop_coverage import peak_coverage_lpm2

    p = pattern_of(
        release(heading_rad=0.0, ground_speed_mps=v_mps, height_m=12.0, volume_l=10.0, flow_lps=5.0)
    )
    assert p.length_m < 3.0 * p.sigma_m
    xs = np.arange(-4.0 * p.sigma_m, p.length_m + 4.0 * p.sigma_m, 0.1)
    xx, yy = np.meshgrid(xs, np.array([0.0]))
    measured = float(coverage_lpm2(p, xx, yy).max())
    assert peak_coverage_lpm2(10.0, 5.0, v_mps, 12.0) == pytest.approx(measured, rel=1e-4)
