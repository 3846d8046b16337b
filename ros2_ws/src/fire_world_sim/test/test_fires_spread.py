"""Raster fire spread against independent truth: Rothermel/Behave rates and ellipse geometry.

Truth used here: the head rate of :func:`head_spread` (itself checked against Behave in
test_rothermel_behave.py), Behave's head and backing rates from data/behave_tables.csv, the
area of a circle, and Huygens' principle (a front grown under a new wind is the Minkowski sum
of the old burnt area and the new ellipse, so its extent in direction n grows by the support
function of the ellipse: R_head in the head direction, sqrt(R_head R_back) across it).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.constants import CellState
from fire_uav_common.scenario import FuelPatch, Ignition, Raster, Wind
from fire_uav_common.terrain import Lake, Terrain
from fire_world_sim.fires import RasterFireModel
from fire_world_sim.fires.fuel_models import fuel_model
from fire_world_sim.fires.rothermel import head_spread, spread_params

FT_MIN = 0.3048 / 60.0  # [m/s]
MPH = 0.44704  # [m/s]
CS = 5.0
# Behave, fuel model 1 at 6 % (data/behave_tables.csv) [ft/min]
FM1_4MPH = (66.7612, 11.0278)  # head, back; 4 mi/h midflame, flat
FM1_SLOPE30 = (21.6592, 6.2913)  # no wind, 30 % slope
FM5_4MPH_HEAD = 18.4413


def run(m: RasterFireModel, t0: float, t1: float, dt: float = 0.5) -> RasterFireModel:
    t = t0
    while t < t1 - 1e-9:
        m.step(t, dt)
        t += dt
    return m


def burnt_xy(m: RasterFireModel) -> tuple[np.ndarray, np.ndarray]:
    ys, xs = np.nonzero(m.state_grid() != CellState.UNBURNED)
    return m.xc[xs], m.yc[ys]


@pytest.mark.parametrize("speed_mps", [2.0, 4.0])
@pytest.mark.parametrize("wind_deg", range(0, 50, 5))
def test_head_follows_the_wind_at_rothermels_rate(speed_mps: float, wind_deg: int) -> None:
    n = 200
    x0 = y0 = 0.25 * n * CS + 3.8  # off the cell centre
    th = math.radians(wind_deg)
    rh = head_spread(spread_params(fuel_model(1), 0.06), speed_mps, th, 0.0, 0.0)[0]
    seconds = round(250.0 / rh / 0.5) * 0.5  # the head runs ~50 cells
    spec = Raster(
        cell_size_m=CS, nx=n, ny=n, wind=(Wind(0.0, speed_mps, wind_deg),), ignitions=(Ignition(x0, y0),)
    )
    m = run(RasterFireModel(spec, Terrain()), 0.0, seconds)
    x, y = burnt_xy(m)
    px, py = x - x0, y - y0
    along = px * math.cos(th) + py * math.sin(th)
    assert along.max() == pytest.approx(rh * seconds, rel=0.05)
    far = np.argmax(np.hypot(px, py))
    err = (math.degrees(math.atan2(py[far], px[far])) - wind_deg + 180.0) % 360.0 - 180.0
    assert abs(err) <= 5.0


def test_no_wind_burnt_area_is_the_circle() -> None:
    n, factor, seconds = 100, 10.0, 400.0
    x0 = y0 = n * CS / 2 + 1.1
    spec = Raster(
        cell_size_m=CS,
        nx=n,
        ny=n,
        wind=(Wind(0.0, 0.0, 0.0),),
        ignitions=(Ignition(x0, y0),),
        spread_factor=factor,
    )
    m = run(RasterFireModel(spec, Terrain()), 0.0, seconds)
    r = spread_params(fuel_model(1), 0.06).r0_mps * factor * seconds  # ~19 cells
    area = (m.state_grid() != CellState.UNBURNED).sum() * CS * CS
    assert area == pytest.approx(math.pi * r * r, rel=0.03)


def test_wind_turning_mid_burn_grows_the_new_ellipse() -> None:
    u = 4.0 * MPH
    rh, rb = FM1_4MPH[0] * FT_MIN, FM1_4MPH[1] * FT_MIN
    x0, y0 = 202.0, 203.0
    spec = Raster(
        cell_size_m=CS,
        nx=120,
        ny=120,
        wind=(Wind(0.0, u, 0.0), Wind(300.0, u, 90.0)),  # east, then north from t = 300 s
        ignitions=(Ignition(x0, y0),),
    )
    m = run(RasterFireModel(spec, Terrain()), 0.0, 300.0)
    x, y = burnt_xy(m)
    assert x.max() - x0 == pytest.approx(rh * 300.0, rel=0.05)  # head east before the turn
    north0, east0, south0 = y.max(), x.max(), y.min()
    run(m, 300.0, 700.0)
    x, y = burnt_xy(m)
    dt = 400.0
    assert y.max() - north0 == pytest.approx(rh * dt, rel=0.05)  # the new head
    assert x.max() - east0 == pytest.approx(math.sqrt(rh * rb) * dt, abs=1.5 * CS)  # now a flank
    assert south0 - y.min() == pytest.approx(rb * dt, abs=1.5 * CS)  # now the back


@pytest.mark.parametrize("upslope_deg", [0, 30, 45, 90, 135, 210, 270, 315])
def test_slope_drives_the_head_upslope_in_every_direction(upslope_deg: int) -> None:
    factor, seconds = 5.0, 400.0
    rh, rb = (v * FT_MIN * factor for v in FM1_SLOPE30)
    th = math.radians(upslope_deg)
    terrain = Terrain(slope_x=0.3 * math.cos(th), slope_y=0.3 * math.sin(th))  # 30 %
    c = 350.0
    x0, y0 = c - 100.0 * math.cos(th) + 1.3, c - 100.0 * math.sin(th) + 0.7
    spec = Raster(
        cell_size_m=CS,
        nx=140,
        ny=140,
        wind=(Wind(0.0, 0.0, 0.0),),
        ignitions=(Ignition(x0, y0),),
        spread_factor=factor,
    )
    m = run(RasterFireModel(spec, terrain), 0.0, seconds)
    x, y = burnt_xy(m)
    px, py = x - x0, y - y0
    along = px * math.cos(th) + py * math.sin(th)
    assert along.max() == pytest.approx(rh * seconds, rel=0.05)
    assert -along.min() == pytest.approx(rb * seconds, abs=1.5 * CS)
    # L/W is only 1.2 here, so the farthest cell is ill-defined; the centroid of an ellipse
    # with the ignition at its focus lies on its major axis
    err = (math.degrees(math.atan2(py.mean(), px.mean())) - upslope_deg + 180.0) % 360.0 - 180.0
    assert abs(err) <= 5.0


def test_head_slows_to_the_brush_rate_across_a_fuel_boundary() -> None:
    factor = 3.0
    spec = Raster(
        cell_size_m=CS,
        nx=160,
        ny=60,
        fuel_model=1,
        fuel_patches=(FuelPatch(300.0, 800.0, 0.0, 300.0, 5),),
        wind=(Wind(0.0, 4.0 * MPH, 0.0),),
        ignitions=(Ignition(150.0, 150.0),),
        spread_factor=factor,
    )
    m = run(RasterFireModel(spec, Terrain()), 0.0, 100.0)
    x, _ = burnt_xy(m)
    assert x.max() - 150.0 == pytest.approx(FM1_4MPH[0] * FT_MIN * factor * 100.0, rel=0.05)  # grass
    run(m, 100.0, 250.0)
    x_a = burnt_xy(m)[0].max()
    assert x_a > 300.0 + 3 * CS  # in the brush
    run(m, 250.0, 650.0)
    x_b = burnt_xy(m)[0].max()
    assert x_b - x_a == pytest.approx(FM5_4MPH_HEAD * FT_MIN * factor * 400.0, rel=0.05)


def test_fire_goes_around_a_lake_not_through_it() -> None:
    lake = Lake(300.0, 150.0, 60.0)
    spec = Raster(
        cell_size_m=CS, nx=100, ny=60, wind=(Wind(0.0, 4.0, 0.0),), ignitions=(Ignition(150.0, 150.0),)
    )
    m = run(RasterFireModel(spec, Terrain(), lakes=(lake,)), 0.0, 600.0)
    xx, yy = np.meshgrid(m.xc, m.yc)
    water = (xx - lake.x_m) ** 2 + (yy - lake.y_m) ** 2 <= lake.diameter_m**2 / 4
    g = m.state_grid()
    assert (g[water] == CellState.UNBURNED).all()
    assert (g[~water & (xx > 360.0)] != CellState.UNBURNED).any()  # the head passed it


def test_fire_burning_before_t0_is_handed_over_grown() -> None:
    u = 4.0 * MPH
    spec = Raster(
        cell_size_m=CS,
        nx=120,
        ny=80,
        wind=(Wind(-300.0, u, 0.0),),
        ignitions=(Ignition(101.0, 201.0, -300.0), Ignition(500.0, 100.0, 50.0)),
    )
    m = RasterFireModel(spec, Terrain())
    assert m.truth()[0].started and not m.truth()[1].started
    x, _ = burnt_xy(m)
    assert x.max() - 101.0 == pytest.approx(FM1_4MPH[0] * FT_MIN * 300.0, rel=0.05)
    assert m.truth()[0].area_m2 > 0.3e4
    assert m.step(0.0, 0.5) == [(0, "ignition")]  # reported once, by the first step
    assert m.step(0.5, 0.5) == []


def test_burns_out_and_reports_extinguished() -> None:
    spec = Raster(
        cell_size_m=CS, nx=12, ny=12, wind=(Wind(0.0, 4.0, 0.0),), ignitions=(Ignition(30.0, 30.0),)
    )
    m = RasterFireModel(spec, Terrain())
    events: list[tuple[int, str]] = []
    t = 0.0
    while not m.all_out and t < 4000.0:
        events += m.step(t, 0.5)
        t += 0.5
    assert m.all_out and events[0] == (0, "ignition") and events[-1] == (0, "extinguished")
    g = m.state_grid()
    assert (g == CellState.BURNED).all() and not (g == CellState.BURNING).any()


def test_drop_on_the_head_stops_it_there() -> None:
    spec = Raster(
        cell_size_m=CS, nx=100, ny=40, wind=(Wind(0.0, 4.0, 0.0),), ignitions=(Ignition(50.0, 100.0),)
    )
    m = run(RasterFireModel(spec, Terrain()), 0.0, 100.0)
    x, y = burnt_xy(m)
    head_x = x.max()
    # drench the whole front (burning cells) and a band ahead of it
    while (m.state_grid() == CellState.BURNING).any():
        ys, xs = np.nonzero(m.state_grid() == CellState.BURNING)
        m.apply_drop(float(m.xc[xs[0]]), float(m.yc[ys[0]]), 30.0)
    assert m.all_out
    run(m, 100.0, 300.0)
    assert burnt_xy(m)[0].max() == head_x
