"""Fire models: Rothermel against published values, raster shape, analytic drops."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.constants import CellState
from fire_uav_common.scenario import AnalyticFire, Ignition, Raster, Wind
from fire_uav_common.terrain import Terrain
from fire_world_sim.fires import AnalyticFireModel, RasterFireModel
from fire_world_sim.fires.fuel_models import fuel_model
from fire_world_sim.fires.rothermel import length_to_breadth, rate_of_spread, spread_params

CHAINS_PER_HOUR = 20.1168 / 3600.0  # [m/s]
MPH = 0.44704  # [m/s]


# Anderson, H.E. 1982. Aids to determining fuel models for estimating fire behavior.
# USDA For. Serv. Gen. Tech. Rep. INT-122, Table 1 ("fire behavior ... at 8 percent dead fuel
# moisture, 100 percent live fuel moisture, 5 mi/h midflame wind", flat ground): rate of
# spread in chains/hour.
@pytest.mark.parametrize(
    ("model", "published_ch_h"),
    [(1, 78.0), (2, 35.0), (3, 104.0), (4, 75.0), (9, 7.5), (10, 7.9), (13, 13.5)],
)
def test_rothermel_matches_anderson_1982(model: int, published_ch_h: float) -> None:
    p = spread_params(fuel_model(model), 0.08, 0.08, 0.08, 1.0, 1.0)
    ros = rate_of_spread(p, 5.0 * MPH) / CHAINS_PER_HOUR
    assert ros == pytest.approx(published_ch_h, rel=0.10)


def test_rothermel_wind_and_slope_increase_spread() -> None:
    p = spread_params(fuel_model(1), 0.06)
    r0 = rate_of_spread(p, 0.0)
    assert r0 == pytest.approx(p.r0_mps)
    assert rate_of_spread(p, 2.0) > r0 * 5
    # slope factor by hand: phi_s = 5.275 beta^-0.3 tan^2 -> R = R0 (1 + phi_s)
    assert rate_of_spread(p, 0.0, 0.3) == pytest.approx(r0 * (1 + p.slope_k * 0.09))
    # above the moisture of extinction nothing spreads
    assert spread_params(fuel_model(1), 0.13).r0_mps == 0.0


def test_length_to_breadth_is_one_without_wind_grows_and_caps() -> None:
    # the values themselves are checked against Behave in test_rothermel_behave.py
    assert length_to_breadth(0.0) == pytest.approx(1.0)
    u = np.linspace(0.0, 30.0, 61)
    lb = length_to_breadth(u)
    assert np.all(np.diff(lb) >= 0) and lb[-1] == pytest.approx(8.0)


def run_raster(wind_mps: float, seconds: float, factor: float = 20.0) -> RasterFireModel:
    spec = Raster(
        nx=80,
        ny=80,
        wind=(Wind(0.0, wind_mps, 90.0),),
        ignitions=(Ignition(200.0, 200.0, 0.0),),
        spread_factor=factor,
    )
    m = RasterFireModel(spec, Terrain())
    t = 0.0
    while t < seconds - 1e-9:
        m.step(t, 0.5)
        t += 0.5
    return m


def extents(m: RasterFireModel) -> tuple[int, int, int, int]:
    ys, xs = np.nonzero(m.state_grid() != CellState.UNBURNED)
    c = 40
    return xs.max() - c, c - xs.min(), ys.max() - c, c - ys.min()


def test_flat_no_wind_grows_as_a_circle() -> None:
    m = run_raster(0.0, 400.0)
    east, west, north, south = extents(m)
    assert min(east, west, north, south) >= 6
    assert max(east, west, north, south) - min(east, west, north, south) <= 1
    g = m.state_grid() != CellState.UNBURNED
    area = g.sum()
    r = (east + west + north + south) / 4 + 0.5
    assert area == pytest.approx(math.pi * r * r, rel=0.15)
    assert (m.state_grid() == CellState.BURNING).any()


def test_wind_elongates_downwind() -> None:
    m = run_raster(2.0, 60.0, factor=1.0)
    east, west, north, south = extents(m)
    assert north >= 3 * max(south, 1)  # wind blows toward +y (90 deg)
    assert north > 2 * max(east, west)
    assert abs(east - west) <= 1


def test_raster_drop_extinguishes_and_wets() -> None:
    m = run_raster(0.0, 200.0)
    assert not m.all_out
    hit = m.apply_drop(202.5, 202.5, 200.0)
    assert hit == [0]
    assert not (m.state_grid() == CellState.BURNING).any() and m.all_out
    assert m.truth()[0].drops_received == 1 and m.truth()[0].status == 1


def test_analytic_drift_and_drop_reduces_area_by_four() -> None:
    m = AnalyticFireModel((AnalyticFire(100.0, 200.0, 40.0, -0.5, 0.2),), extinction_sigma_m=2.0)
    m.step(0.0, 10.0)
    f = m.truth()[0]
    assert (f.x_m, f.y_m) == pytest.approx((95.0, 202.0))
    a0 = f.area_m2
    assert m.apply_drop(95.0 + 30.0, 202.0, None) == [0]  # within sigma
    assert m.truth()[0].area_m2 == pytest.approx(a0 / 4) and m.truth()[0].extent_m == pytest.approx(20.0)
    assert m.apply_drop(95.0 + 30.0, 202.0, None) == []  # now outside sigma 20
    for _ in range(4):
        m.apply_drop(95.0, 202.0, None)
    assert m.all_out and m.truth()[0].status == 1 and m.truth()[0].drops_received == 5
    assert m.detections_near(95.0, 202.0, 70.0) == []


def test_analytic_start_time_and_detection_range() -> None:
    m = AnalyticFireModel((AnalyticFire(0.0, 0.0, 10.0, start_s=5.0),), 2.0)
    assert m.detections_near(0, 0, 70) == []
    assert m.step(0.0, 5.0) == [(0, "ignition")]
    assert [d[0] for d in m.detections_near(69.0, 0, 70)] == [0]
    assert m.detections_near(71.0, 0, 70) == []
