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


def test_analytic_fire_does_not_drift_before_it_starts_and_drifts_from_then() -> None:
    m = AnalyticFireModel((AnalyticFire(100.0, 50.0, 10.0, 1.0, -2.0, start_s=5.0),), 2.0)
    assert m.step(0.0, 2.0) == []
    f = m.truth()[0]
    assert (f.x_m, f.y_m, f.started) == (100.0, 50.0, False)
    assert m.step(2.0, 3.0) == [(0, "ignition")]  # starts exactly at 5 s
    assert m.truth()[0].started and (m.truth()[0].x_m, m.truth()[0].y_m) == (100.0, 50.0)
    m.step(5.0, 10.0)  # 10 s after its start: c(start) + v * 10 s (FF IV-A)
    assert (m.truth()[0].x_m, m.truth()[0].y_m) == pytest.approx((110.0, 30.0))
    assert m.step(15.0, 1.0) == []  # ignition is reported once


def test_analytic_fire_started_at_zero_is_burning_from_the_start_without_an_event() -> None:
    m = AnalyticFireModel((AnalyticFire(0.0, 0.0, 10.0),), 2.0)
    assert m.truth()[0].started and m.step(0.0, 1.0) == []
    assert m.cells_near(0.0, 0.0, 70.0, 0) is None


def test_analytic_drops_radius_rules_and_who_is_hit() -> None:
    fires = (
        AnalyticFire(0.0, 0.0, 10.0),
        AnalyticFire(500.0, 0.0, 10.0),
        AnalyticFire(0, 0, 10.0, start_s=99.0),
    )
    m = AnalyticFireModel(fires, extinction_sigma_m=2.0, drop_radius_m=25.0)
    assert m.apply_drop(25.0, 0.0) == [0]  # default footprint 25 m > sigma 10 m, edge inclusive
    assert m.apply_drop(25.1, 0.0) == []  # sigma now 5 m: the 25 m footprint decides
    assert m.apply_drop(24.9, 0.0) == [0]
    assert m.apply_drop(500.0, 3.0, radius_m=3.0) == [1]  # an explicit radius
    assert m.apply_drop(500.0, 3.1, radius_m=3.0) == []
    assert m.truth()[2].drops_received == 0  # not started: not hit, though under the drop
    t = m.truth()
    assert [r.drops_received for r in t] == [2, 1, 0]
    assert t[0].area_m2 == pytest.approx(math.pi * 2.5**2) and t[0].extent_m == 2.5
    assert t[1].area_m2 == pytest.approx(math.pi * 5.0**2)


def test_analytic_extinction_is_strictly_below_the_threshold_and_all_out_counts_unstarted() -> None:
    m = AnalyticFireModel((AnalyticFire(0.0, 0.0, 8.0), AnalyticFire(900.0, 0.0, 4.0, start_s=50.0)), 2.0)
    m.apply_drop(0.0, 0.0)
    m.apply_drop(0.0, 0.0)  # sigma 2.0 = the threshold: still burning
    t = m.truth()[0]
    assert t.status == 0 and t.extent_m == 2.0 and [d[0] for d in m.detections_near(0, 0, 70)] == [0]
    assert m.apply_drop(0.0, 0.0) == [0]  # 1.0 < 2.0: out
    t = m.truth()[0]
    assert (t.status, t.extent_m, t.area_m2) == (1, 0.0, 0.0)
    assert m.apply_drop(0.0, 0.0) == []  # an extinguished fire is not hit again
    assert not m.all_out  # the second fire has not started yet
    m.step(0.0, 50.0)
    assert not m.all_out and m.detections_near(900.0, 70.0, 70.0) == [(1, 900.0, 0.0, 4.0)]
    m.apply_drop(900.0, 0.0)
    assert m.apply_drop(900.0, 0.0) == [1] and m.all_out


# --- the protocol: what the world and its node ask of any fire model -----------------------------
def _protocol_members() -> set[str]:
    from fire_world_sim.fires.base import FireModel

    return {n for n in vars(FireModel) if not n.startswith("_")}


@pytest.mark.parametrize(
    "make", [lambda: AnalyticFireModel((AnalyticFire(0.0, 0.0, 10.0),), 2.0), lambda: run_raster(0.0, 1.0)]
)
def test_both_models_have_every_member_of_the_protocol(make) -> None:
    m = make()
    missing = sorted(n for n in _protocol_members() if not hasattr(m, n))
    assert _protocol_members() >= {"last_ignition_s", "last_drop_cells", "drop_extinctions", "cell_grid"}
    assert missing == [], f"{type(m).__name__} lacks {missing}"


def test_analytic_protocol_answers_a_drop_and_has_no_cells() -> None:
    m = AnalyticFireModel((AnalyticFire(0.0, 0.0, 3.0), AnalyticFire(500.0, 0.0, 40.0)), 2.0)
    assert m.last_ignition_s == math.inf and not m.has_cells and m.cell_grid() is None
    hit = m.apply_drop(0.0, 0.0, 600.0)  # both hit: sigma 3 -> 1.5 (out), 40 -> 20
    assert hit == [0, 1] and m.drop_extinctions(hit) == [0] and m.last_drop_cells is None


def test_raster_protocol_reports_extinctions_from_step_and_shows_its_grid() -> None:
    m = run_raster(0.0, 20.0)
    g = m.cell_grid()
    assert m.has_cells and g is not None and (g.nx, g.ny) == (m.nx, m.ny) and g.cell_size_m == m.cs
    assert np.array_equal(g.state, m.state_grid()) and np.array_equal(g.wet, m.wet_grid())
    assert (g.origin_x_m, g.origin_y_m) == (m.spec.origin.x_m, m.spec.origin.y_m)
    assert 0.0 <= m.last_ignition_s <= 20.0
    hit = m.apply_drop(202.5, 202.5, 200.0)
    assert hit == [0] and m.all_out and m.drop_extinctions(hit) == []  # step() reports it
    assert m.last_drop_cells is not None and m.last_drop_cells[0] > 0
