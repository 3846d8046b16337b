"""Suppression measures: containment on constructed cases, drop accounting,
the no-fleet baseline world."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from fire_uav_common.constants import CellState, EventType
from fire_uav_common.scenario import Ignition, Raster, Wind, load_scenario
from fire_uav_common.terrain import Terrain
from fire_world_sim.errors import ConfigError
from fire_world_sim.fires import RasterFireModel
from fire_world_sim.measures import Containment, SuppressionMeasures
from fire_world_sim.world import Command, World

SCEN = Path(__file__).resolve().parents[1] / "scenarios"


def test_containment_needs_a_full_quiet_window_and_resets_on_a_breach() -> None:
    c = Containment(window_s=60.0)
    assert c.update(0.0, last_ignition_s=-5.0, burning=True) is None
    assert c.update(30.0, last_ignition_s=10.0, burning=True) is None
    assert c.update(69.9, last_ignition_s=10.0, burning=True) is None  # 59.9 s quiet
    assert c.update(70.0, last_ignition_s=10.0, burning=True) == 70.0  # 60 s quiet
    assert c.update(100.0, last_ignition_s=10.0, burning=True) == 70.0  # stays
    assert c.update(101.0, last_ignition_s=100.5, burning=True) is None  # line breached
    assert c.update(161.0, last_ignition_s=100.5, burning=True) == 161.0
    assert Containment().update(5.0, last_ignition_s=4.9, burning=False) == 5.0  # all out


def test_containment_error_paths() -> None:
    with pytest.raises(ValueError, match="window_s must be > 0"):
        Containment(window_s=0.0)
    c = Containment()
    c.update(10.0, 0.0, True)
    with pytest.raises(ValueError, match="must not go back in time"):
        c.update(9.0, 0.0, True)


def test_a_fire_that_reaches_the_grid_edges_is_contained_a_window_after_its_last_new_cell() -> None:
    """Constructed case: a 20 x 20 grass plot burns to its edges. Truth: the last time the count of
    ignited cells (from the state grid) changed, plus 60 s, to within one 0.5 s update."""
    spec = Raster(
        cell_size_m=5.0, nx=20, ny=20, wind=(Wind(0.0, 3.0, 0.0),), ignitions=(Ignition(12.0, 50.0),)
    )
    m = RasterFireModel(spec, Terrain())
    c = Containment(60.0)
    t, dt = 0.0, 0.5
    last_change, count = 0.0, 0
    contained = []
    while t < 600.0:
        m.step(t, dt)
        t += dt
        n = int((m.state_grid() != CellState.UNBURNED).sum())
        if n != count:
            count, last_change = n, t
        contained.append((t, c.update(t, m.last_ignition_s, not m.all_out)))
    assert count == 400  # the whole plot burnt
    before = [v for tt, v in contained if tt < last_change + 60.0 - dt]
    assert all(v is None for v in before)
    assert c.contained_at_s == pytest.approx(last_change + 60.0, abs=dt + 1e-9)


def test_a_free_running_fire_is_never_contained() -> None:
    spec = Raster(
        cell_size_m=5.0, nx=200, ny=60, wind=(Wind(0.0, 3.0, 0.0),), ignitions=(Ignition(40.0, 150.0),)
    )
    m = RasterFireModel(spec, Terrain())
    c = Containment(60.0)
    t = 0.0
    while t < 200.0:
        m.step(t, 0.5)
        t += 0.5
        c.update(t, m.last_ignition_s, not m.all_out)
    assert c.contained_at_s is None


def test_drop_cell_counts_match_the_footprint_geometry() -> None:
    spec = Raster(
        cell_size_m=5.0, nx=60, ny=60, wind=(Wind(0.0, 0.0, 0.0),), ignitions=(Ignition(150.0, 150.0),)
    )
    m = RasterFireModel(spec, Terrain())
    r = 20.0
    xs, ys = np.meshgrid(m.xc, m.yc)
    in_disc = int((((xs - 40.0) ** 2 + (ys - 40.0) ** 2) <= r * r).sum())  # away from the fire
    assert m.apply_drop(40.0, 40.0, r) == []
    assert m.last_drop_cells == (0, in_disc)
    t = 0.0
    while t < 120.0:
        m.step(t, 0.5)
        t += 0.5
    burning = m.state_grid() == CellState.BURNING
    near = ((xs - 150.0) ** 2 + (ys - 150.0) ** 2) <= 10.0**2
    expect = int((burning & near).sum())
    assert expect > 0
    assert m.apply_drop(150.0, 150.0, 10.0) == [0]
    assert m.last_drop_cells == (expect, int(near.sum()))


def test_measures_water_on_burning_cells_and_hit_rate() -> None:
    s = SuppressionMeasures()
    assert s.hit_rate is None
    assert s.add_drop(2000.0, 10, 40, hit=True) == pytest.approx(500.0)
    assert s.add_drop(2000.0, 0, 40, hit=False) == 0.0
    assert s.add_drop(0.0, 5, 40, hit=True) == 0.0  # empty tank: no drop
    assert (s.drops, s.hits, s.hit_rate) == (2, 1, 0.5)
    assert s.water_on_burning_kg == pytest.approx(500.0)


def test_no_fleet_world_burns_the_fire_alone() -> None:
    sc = load_scenario(SCEN / "grass_running.yaml")
    w = World(sc, no_fleet=True)
    assert w.uav_count == 0 and w.vehicles == []
    a0 = None
    for _ in range(20):
        r = w.step({})
        assert r.bundles == {}
        a0 = a0 if a0 is not None else w.measures.burned_area_m2
    assert w.measures.burned_area_m2 > a0 > 4e4  # ~5.5 ha at t = 0, growing
    assert w.measures.containment.contained_at_s is None
    with pytest.raises(ConfigError, match="no_fleet needs uav_count 0"):
        World(sc, uav_count=3, no_fleet=True)


def test_world_drop_event_carries_the_burning_cell_count() -> None:
    sc = load_scenario(SCEN / "grass_running.yaml")
    w = World(sc, uav_count=1)
    w.vehicles[0].status = w.vehicles[0].status.__class__.AIRBORNE  # put it in the air over the fire
    # the fire's burning cells at t = 0: drop on one of them
    g = w.fires.state_grid()
    iy, ix = np.argwhere(g == CellState.BURNING)[0]
    w.vehicles[0].x_m, w.vehicles[0].y_m = float(w.fires.xc[ix]), float(w.fires.yc[iy])
    w.vehicles[0].z_m = 50.0
    r = w.step({0: Command(15.0, 0.0, 0.0)}, {0: [1]})
    drops = [e for e in r.events if e.type == EventType.DROP]
    assert len(drops) == 1 and drops[0].fire_id == 0
    assert "cells burning" in drops[0].detail
    assert w.measures.hits == 1 and w.measures.water_on_burning_kg > 0
    assert not math.isnan(w.measures.burned_area_m2)
