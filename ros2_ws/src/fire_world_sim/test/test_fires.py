"""Fire models: raster shape, analytic drops (Rothermel itself: test_rothermel*.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.constants import CellState
from fire_uav_common.scenario import AnalyticFire, Ignition, Raster, Wind
from fire_uav_common.terrain import Terrain
from fire_world_sim.fires import AnalyticFireModel, RasterFireModel


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
