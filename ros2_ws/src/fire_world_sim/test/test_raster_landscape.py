"""The raster fire on a landscape (worcester_vt): per-cell fuels, wind adjustment, crown fire."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.scenario import load_scenario
from fire_world_sim.fires.crown import FireType
from fire_world_sim.fires.raster import PAD, RasterFireModel

from .conftest import SCENARIOS


def model(**overrides: object) -> RasterFireModel:
    s = load_scenario(SCENARIOS / "worcester_vt.yaml", overrides=overrides)
    return RasterFireModel(s.fires.raster, s.terrain, lakes=s.lakes, drop_radius_m=s.fires.drop_radius_m)


@pytest.fixture(scope="module")
def running() -> RasterFireModel:
    return model()  # pre-burnt 600 s to t = 0


def test_only_burnable_cells_ever_ignite(running: RasterFireModel) -> None:
    inner = running._inner
    ignited = np.isfinite(running.t_ign[inner])
    assert ignited.sum() > 20
    assert not (ignited & ~running.burnable[inner]).any()
    # water (98), the other non-burnable codes and the cells outside the data never burn
    assert not (ignited & ((running.fuel == 0) | (running.fuel >= 91) & (running.fuel <= 99))).any()


def test_the_head_runs_at_the_cells_rate_of_spread(running: RasterFireModel) -> None:
    """Along the grass (GR2) row east of the ignition, with the wind blowing east and the
    ground nearly flat, the arrival times grow by cell / head rate (the cells' own head rate)."""
    ig = running.spec.ignitions[0]
    i = PAD + math.floor(ig.y_m / running.cs)
    j = PAD + math.floor(ig.x_m / running.cs)
    cols = [c for c in range(j + 2, j + 7) if running.fuel[i - PAD, c - PAD] == 102]
    assert len(cols) >= 4
    t = running.t_ign[i, cols]
    assert np.all(np.isfinite(t))
    head = running._head[i, cols]
    along = np.cos(running._head_dir[i, cols])  # the head's east component
    expected = running.cs / (head * along)
    assert np.diff(t) == pytest.approx(expected[1:], rel=0.2)


def test_the_fire_goes_where_the_wind_blows() -> None:
    east = model().truth()[0]
    west = model(
        **{"fires.raster.wind": [{"start_s": -600.0, "speed_mps": 8.0, "direction_deg": 180.0}]}
    ).truth()[0]
    x0 = 285.0  # the ignition
    assert east.x_m > x0 + 50.0 and west.x_m < x0 - 10.0


def test_fire_type_per_cell_includes_crown_fire_under_the_scenarios_weather(running: RasterFireModel) -> None:
    ft = running.fire_type
    assert ft.shape == (running.ny, running.nx)
    counts = np.bincount(ft.ravel(), minlength=4)
    assert counts[FireType.SURFACE] > 1000 and counts[FireType.PASSIVE] + counts[FireType.ACTIVE] > 0
    assert np.all(ft[~running.burnable[running._inner]] == FireType.UNBURNABLE)
    no_crown = model(**{"fires.raster.landscape.crown": "none"}).fire_type
    assert not np.isin(no_crown, [FireType.PASSIVE, FireType.ACTIVE]).any()


def test_fire_type_grid_holds_the_type_each_ignited_cell_burned_with() -> None:
    """Under one wind a cell burns with its own fire type; cells not reached carry 0. The
    scenario's 15 minutes reach a few crowning cells."""
    m = model()
    for k in range(900):
        m.step(float(k), 1.0)
    grid = m.fire_type_grid()
    assert grid is not None and grid.shape == (m.ny, m.nx)
    ignited = m.state_grid() != 0
    assert np.array_equal(grid[ignited], m.fire_type[ignited])
    assert not grid[~ignited].any()
    counts = np.bincount(grid[ignited], minlength=4)
    assert counts[FireType.UNBURNABLE] == 0
    # (about 70 surface cells: the grass patch the fire starts in, held by the one-cell roads and
    # streams around it, which it crossed before the spread stopped at non-burnable cells)
    assert counts[FireType.SURFACE] > 50 and counts[FireType.PASSIVE] + counts[FireType.ACTIVE] > 0


def test_a_cell_keeps_the_highest_type_of_the_winds_it_burned_in() -> None:
    """A wind change while a cell burns re-derives its fire; its recorded type is the higher one."""
    calm = {"start_s": -600.0, "speed_mps": 0.0, "direction_deg": 0.0}
    gale = {"start_s": 30.0, "speed_mps": 20.0, "direction_deg": 0.0}
    m = model(**{"fires.raster.wind": [calm, gale]})
    before = m.fire_type.copy()
    for k in range(31):
        m.step(float(k), 1.0)
    burning = m.state_grid() == 1
    grid = m.fire_type_grid()
    assert grid is not None and burning.any()
    assert np.all(grid[burning] == np.maximum(before[burning], m.fire_type[burning]))
    assert (m.fire_type[burning] > before[burning]).any()  # the gale raised some


def test_no_fire_type_grid_without_a_landscape() -> None:
    from fire_world_sim.fires import make_fire_model

    for name in ("grass_running", "ff_two_fires"):
        s = load_scenario(SCENARIOS / f"{name}.yaml")
        assert make_fire_model(s.fires, s.terrain, s.lakes).fire_type_grid() is None
