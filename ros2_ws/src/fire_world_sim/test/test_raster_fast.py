"""Raster fire on small grids (fast: the mutation selection of fire_world_sim.fires.raster).

Truths: Behave's spread ellipse with the ignition at its rear focus, R(theta) = R_h (1 - e) /
(1 - e cos theta) with R_h, e from fire_world_sim.fires.rothermel (checked against Behave in
test_rothermel_behave.py), so the arrival time at distance r is r / R(theta); the cell-space
invariants (burnt area never shrinks, a cell ignites only next to an ignited cell or near its
ignition point, nothing burns on a lake); drops and the truth records by brute-force counts
over state_grid (public interface only)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.constants import CellState, FireStatus
from fire_uav_common.scenario import FuelPatch, Ignition, Raster, Wind
from fire_uav_common.terrain import Lake, Terrain
from fire_world_sim.fires import RasterFireModel
from fire_world_sim.fires.fuel_models import fuel_model
from fire_world_sim.fires.raster import SEED_RADIUS_CELLS
from fire_world_sim.fires.rothermel import ellipse_eccentricity, head_spread, length_to_breadth, spread_params

CS = 5.0  # [m] default cell size
N = 25
FLAT = Terrain()


def model(wind=((0.0, 0.0, 90.0),), ignitions=((62.5, 62.5, 0.0),), factor=20.0, terrain=FLAT, **kw):
    spec = Raster(
        nx=kw.pop("nx", N),
        ny=kw.pop("ny", N),
        wind=tuple(Wind(*w) for w in wind),
        ignitions=tuple(Ignition(*ig) for ig in ignitions),
        spread_factor=factor,
        **{k: v for k, v in kw.items() if k != "lakes"},
    )
    return RasterFireModel(spec, terrain, lakes=kw.get("lakes", ()))


def run(m: RasterFireModel, t0: float, t1: float, dt: float = 0.5):
    """Step from t0 to t1; returns (first time each cell was seen ignited [s], events)."""
    first = np.full((m.ny, m.nx), np.inf)
    first[m.state_grid() != CellState.UNBURNED] = t0
    events = []
    t = t0
    while t < t1 - 1e-9:
        events += [(round(t + dt, 6), *e) for e in m.step(t, dt)]
        t += dt
        g = m.state_grid() != CellState.UNBURNED
        first[g & ~np.isfinite(first)] = t
    return first, events


def centres(m: RasterFireModel):
    yy, xx = np.mgrid[0 : m.ny, 0 : m.nx]
    return xx * m.cs + m.cs / 2, yy * m.cs + m.cs / 2


def analytic_arrival(m, x0, y0, wind_mps, wind_dir_rad, factor, fuel=1, slope_tan=0.0, upslope=0.0):
    p = spread_params(fuel_model(fuel), 0.06)
    rh, d, u = head_spread(p, wind_mps, wind_dir_rad, slope_tan, upslope)
    rh *= factor
    e = ellipse_eccentricity(length_to_breadth(u))
    xx, yy = centres(m)
    r = np.hypot(xx - x0, yy - y0)
    return r * (1 - e * np.cos(np.arctan2(yy - y0, xx - x0) - d)) / (rh * (1 - e))


@pytest.mark.parametrize(("wind_mps", "factor"), [(0.0, 40.0), (2.0, 3.0)])
def test_arrival_times_follow_behaves_ellipse(wind_mps: float, factor: float) -> None:
    x0, y0 = 62.5, 37.5
    m = model(wind=((0.0, wind_mps, 60.0),), ignitions=((x0, y0, 0.0),), factor=factor)
    first, _ = run(m, 0.0, 30.0)
    ta = analytic_arrival(m, x0, y0, wind_mps, math.radians(60.0), factor)
    seen = np.isfinite(first)
    # cells are seen at the first 0.5 s step at or after their arrival
    assert np.all(first[seen] - ta[seen] > -0.35), np.min(first[seen] - ta[seen])
    assert np.all(first[seen] - ta[seen] < 0.6 + 0.05 * ta[seen]), np.max(first[seen] - ta[seen])
    due = ta < 29.0
    assert seen[due].all() and not seen[ta > 31.0].any()
    assert due.sum() > 30


def test_upslope_spread_follows_rothermels_slope_factor() -> None:
    terrain = Terrain(slope_y=0.4)  # rises to the north
    x0, y0 = 62.5, 37.5
    m = model(ignitions=((x0, y0, 0.0),), terrain=terrain)
    first, _ = run(m, 0.0, 25.0)
    ta = analytic_arrival(m, x0, y0, 0.0, 0.0, 20.0, slope_tan=0.4, upslope=math.pi / 2)
    seen = np.isfinite(first)
    assert np.all(np.abs(first[seen] - ta[seen] - 0.35) < 0.8)
    assert seen[ta < 24.0].all() and not seen[ta > 26.0].any()


def test_cell_space_invariants() -> None:
    lake = Lake(90.0, 62.5, 30.0)
    m = model(wind=((0.0, 1.0, 0.0), (10.0, 1.0, 120.0)), lakes=(lake,))
    xx, yy = centres(m)
    wet_lake = (xx - 90.0) ** 2 + (yy - 62.5) ** 2 <= 15.0**2
    prev = m.state_grid()
    t = 0.0
    for _ in range(60):
        m.step(t, 0.5)
        t += 0.5
        g = m.state_grid()
        was, now = prev != CellState.UNBURNED, g != CellState.UNBURNED
        assert np.all(now[was]), "an ignited cell became unburned"
        assert np.all(g[prev == CellState.BURNED] == CellState.BURNED)
        assert not now[wet_lake].any()
        # every new cell is reached from the cells ignited before, in hops of at most two cells
        # (one step may take several hops), or lies within 3 cells of the ignition point
        reached = was | (np.hypot(xx - 62.5, yy - 62.5) <= 3 * CS + 1e-9)
        grow = True
        while grow:
            grow = False
            for i, j in zip(*np.nonzero(now & ~reached), strict=True):
                if reached[max(i - 2, 0) : i + 3, max(j - 2, 0) : j + 3].any():
                    reached[i, j] = grow = True
        assert np.all(reached[now]), (np.argwhere(now & ~reached), t)
        prev = g
    assert (prev == CellState.BURNED).any() and (prev == CellState.BURNING).any()


def test_a_faster_fuel_runs_ahead() -> None:
    # a strip of timber litter (model 8, slow) to the west, grass (1) between, tall grass (3) east
    patches = (FuelPatch(0.0, 40.0, 0.0, 125.0, 8), FuelPatch(85.0, 125.0, 0.0, 125.0, 3))
    m = model(fuel_patches=patches, factor=40.0)
    first, _ = run(m, 0.0, 40.0)
    xx, _ = centres(m)
    row = N // 2
    west = first[row, xx[row] < 40.0]
    east = first[row, xx[row] > 85.0]
    r8 = spread_params(fuel_model(8), 0.06).r0_mps
    r3 = spread_params(fuel_model(3), 0.06).r0_mps
    assert r8 < r3
    assert np.isfinite(east).sum() > np.isfinite(west).sum()


def test_a_lake_blocks_the_fire() -> None:
    m = model(lakes=(Lake(62.5, 62.5, 200.0),))  # the ignition is in the water
    first, events = run(m, 0.0, 5.0)
    assert not np.isfinite(first).any() and (0.5, 0, "ignition") in events
    assert m.truth()[0].area_m2 == 0.0 and m.all_out


def test_truth_records_are_the_counts_of_the_grid() -> None:
    m = model(ignitions=((32.5, 62.5, 0.0), (92.5, 62.5, 5.0), (62.5, 10.0, 100.0)))
    run(m, 0.0, 15.0)
    g = m.state_grid()
    xx, yy = centres(m)
    tr = m.truth()
    ign = g != CellState.UNBURNED
    west, east = ign & (xx < 62.5), ign & (xx > 62.5)
    for rec, cells, (x0, _y0) in ((tr[0], west, (32.5, 62.5)), (tr[1], east, (92.5, 62.5))):
        assert rec.area_m2 == pytest.approx(cells.sum() * CS * CS) and rec.area_m2 > 0
        assert rec.x_m == pytest.approx(xx[cells].mean()) and rec.y_m == pytest.approx(yy[cells].mean())
        assert rec.extent_m == pytest.approx(math.sqrt(rec.area_m2 / math.pi))
        assert rec.started and rec.status == FireStatus.ACTIVE and rec.drops_received == 0
        assert abs(rec.x_m - x0) < 3.0
    assert tr[0].area_m2 > tr[1].area_m2  # started 5 s earlier
    late = tr[2]
    assert not late.started and late.status == FireStatus.ACTIVE and late.area_m2 == 0.0
    assert (late.x_m, late.y_m) == (62.5, 10.0) and not m.all_out


def test_ignition_events_at_their_start_times() -> None:
    m = model(ignitions=((62.5, 62.5, 0.0), (20.0, 20.0, 2.2)))
    _, events = run(m, 0.0, 4.0)
    ign = [(t, n) for t, n, kind in events if kind == "ignition"]
    assert ign == [(0.5, 0), (2.5, 1)]


def test_preburn_equals_a_run_from_the_earlier_start() -> None:
    early = model(ignitions=((62.5, 62.5, -10.0),))
    late = model(ignitions=((62.5, 62.5, 0.0),))
    run(late, 0.0, 10.0)
    assert np.array_equal(early.state_grid(), late.state_grid())
    assert early.truth()[0].area_m2 == late.truth()[0].area_m2 > 0
    assert early.step(0.0, 0.5)[:1] == [(0, "ignition")]  # reported by the first step


def test_a_drop_puts_out_what_it_covers_and_wets_the_rest() -> None:
    m = model(wet_duration_s=5.0)
    run(m, 0.0, 12.0)
    xx, yy = centres(m)
    g = m.state_grid()
    r = 12.0
    inside = (xx - 62.5) ** 2 + (yy - 62.5) ** 2 <= r * r
    burning_in = int(((g == CellState.BURNING) & inside).sum())
    assert burning_in > 0
    assert m.apply_drop(62.5, 62.5, r) == [0]
    assert m.last_drop_cells == (burning_in, int(inside.sum()))
    assert m.truth()[0].drops_received == 1
    wet = m.wet_grid()
    assert np.array_equal(wet, inside & (g == CellState.UNBURNED))
    g2 = m.state_grid()
    assert not (g2[inside] == CellState.BURNING).any()
    first, _ = run(m, 12.0, 16.0)
    assert not np.isfinite(first[wet]).any() or np.all(first[wet] >= 17.0)  # wet for 5 s
    assert m.apply_drop(-500.0, -500.0, 10.0) == [] and m.last_drop_cells == (0, 0)
    assert m.apply_drop(5.0, 120.0, 3.0) == []  # a corner with no fire: nothing hit


def test_wet_cells_ignite_again_after_the_wet_duration() -> None:
    m = model(wet_duration_s=3.0)
    run(m, 0.0, 6.0)
    m.apply_drop(62.5, 62.5, 200.0)  # everything: fire out, rest of the grid wet for 3 s
    assert m.all_out and m.wet_grid().sum() > 0
    assert m.truth()[0].status == FireStatus.EXTINGUISHED


def test_extinguished_event_when_a_fire_burns_out() -> None:
    m = model(nx=5, ny=5, ignitions=((12.5, 12.5, 0.0),), factor=40.0)
    _, events = run(m, 0.0, 60.0)
    assert [(n, k) for _, n, k in events] == [(0, "ignition"), (0, "extinguished")]
    assert m.all_out and m.truth()[0].status == FireStatus.EXTINGUISHED
    assert np.all(m.state_grid() == CellState.BURNED)


def test_extinguished_event_when_the_last_cell_is_put_out() -> None:
    """A drop that puts a fire's last burning cells out between two updates yields its event.

    (Was a bug: the fires active at the previous update were recomputed after the drop.)"""
    m = model(ignitions=((62.5, 62.5, 0.0), (10.0, 10.0, 0.0)))
    run(m, 0.0, 3.0)
    m.apply_drop(62.5, 62.5, 40.0)
    _, events = run(m, 3.0, 5.0)
    assert [(n, k) for _, n, k in events] == [(0, "extinguished")]
    assert m.truth()[0].status == FireStatus.EXTINGUISHED and m.truth()[1].status == FireStatus.ACTIVE
    assert not m.all_out


def test_wind_at_follows_the_segments() -> None:
    m = model(wind=((0.0, 1.0, 0.0), (10.0, 3.0, 90.0)))
    assert m.wind_at(0.0) == (1.0, 0.0)
    assert m.wind_at(10.0 - 1e-12) == (3.0, pytest.approx(math.pi / 2))
    assert m.wind_at(9.9) == (1.0, 0.0) and m.wind_at(50.0)[0] == 3.0


def test_a_wind_shift_turns_the_head() -> None:
    m = model(wind=((0.0, 3.0, 0.0), (8.0, 3.0, 90.0)), factor=2.0)
    first, _ = run(m, 0.0, 16.0)
    xx, yy = centres(m)
    before = np.isfinite(first) & (first <= 8.0)
    after = np.isfinite(first) & (first > 8.0)
    assert xx[before].mean() > 62.5 + 2.0  # east first
    assert yy[after].mean() > yy[before].mean() + 5.0  # then north


def test_sensors_see_burning_cells_within_range() -> None:
    m = model(ignitions=((32.5, 62.5, 0.0), (92.5, 62.5, 0.0)))
    run(m, 0.0, 6.0)
    xx, yy = centres(m)
    g = m.state_grid()
    near = m.detections_near(32.5, 62.5, 15.0)
    assert [d[0] for d in near] == [0]
    tr = m.truth()[0]
    assert near[0][1:] == (tr.x_m, tr.y_m, tr.extent_m)
    assert [d[0] for d in m.detections_near(62.5, 62.5, 40.0)] == [0, 1]
    assert m.detections_near(62.5, 10.0, 5.0) == [] and m.detections_near(-900.0, 0.0, 5.0) == []
    s = m.cells_near(32.5, 62.5, 12.0, 123)
    inside = (xx - 32.5) ** 2 + (yy - 62.5) ** 2 <= 144.0
    assert s.stamp_ns == 123 and len(s.state) == inside.sum()
    order = np.lexsort((xx[inside], yy[inside]))
    got = np.lexsort((s.x_m, s.y_m))
    assert np.array_equal(np.asarray(s.state)[got], g[inside][order])
    assert np.allclose(np.asarray(s.x_m)[got], xx[inside][order])
    assert len(m.cells_near(-900.0, 0.0, 5.0, 1).state) == 0


@pytest.mark.parametrize("r", [1, 2, 3])
def test_ring_is_the_chebyshev_ring_ordered_by_angle(r: int) -> None:
    """Brute-force oracle: every offset at Chebyshev distance r (8 r of them), by angle."""
    from fire_world_sim.fires.ring_update import _ring

    ring = _ring(r)
    expect = {(di, dj) for di in range(-5, 6) for dj in range(-5, 6) if max(abs(di), abs(dj)) == r}
    assert len(ring) == 8 * r and set(ring) == expect
    angles = [math.atan2(di, dj) for di, dj in ring]
    assert angles == sorted(angles)


def test_a_fire_put_out_whole_stays_out() -> None:
    """Once a drop has put out every burning cell of a fire, nothing of it ignites again.

    The exact wavelet times seeded around an ignition point (1) are the fire spreading from
    that point: with the fire out there is no front left to carry them."""
    m = model(wet_duration_s=1.0)
    run(m, 0.0, 6.0)
    burnt_before = m.state_grid() != CellState.UNBURNED
    xx, yy = centres(m)
    burning = m.state_grid() == CellState.BURNING
    r = float(np.sqrt((xx[burning] - 62.5) ** 2 + (yy[burning] - 62.5) ** 2).max()) + 1.0
    assert r < SEED_RADIUS_CELLS * CS  # cells beyond the drop still hold seeded times
    assert m.apply_drop(62.5, 62.5, r) == [0]
    first, events = run(m, 6.0, 120.0)
    assert [(n, k) for _, n, k in events] == [(0, "extinguished")]
    assert not np.isfinite(first[~burnt_before]).any()
    assert m.all_out and m.truth()[0].status == FireStatus.EXTINGUISHED
