"""Tactics against independent truth (mutation testing of tactics).

Truths: the module doc's definitions (head weights ordered by ROS with the fastest at 1 + w_min,
unknown ROS worth the mean of the known; flank weights decaying by e per ``flank_scale_m`` from
the anchor), Eq. 13' summed directly on every grid point, geometry (regular polygons, distances
measured by hand), and the layer stack's bounds (top, floor, step) as invariants.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.coverage import make_grid
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.tactics import (
    MAX_LAYERS,
    TRACKING_ERROR_M,
    TacticConfig,
    aim_on_front,
    burning_within,
    choose_anchor,
    direct_run_point,
    front_density,
    front_weights,
    layer_height,
    raster_layers,
    release_now,
)
from fire_uav_common.constants import CellState
from hypothesis import given, settings
from hypothesis import strategies as st

B, N, U = int(CellState.BURNING), int(CellState.BURNED), int(CellState.UNBURNED)


def front(x, y=None, ros=None) -> FrontCells:
    x = np.asarray(x, dtype=float)
    y = np.zeros(x.size) if y is None else np.asarray(y, dtype=float)
    r = np.full(x.size, np.nan) if ros is None else np.asarray(ros, dtype=float)
    return FrontCells(x, y, np.full(x.size, B), np.zeros(x.size), r)


# --- config ---------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kw", "msg"),
    [
        ({"sigma_m": 0.0}, "tactic sigma_m must be > 0, got 0.0"),
        ({"flank_scale_m": 0.0}, "tactic flank_scale_m must be > 0, got 0.0"),
        ({"min_burning_cells": 0}, "tactic min_burning_cells must be >= 1, got 0"),
        ({"release_radius_m": 0.0}, "tactic release_radius_m must be > 0, got 0.0"),
        ({"direct_points": 0}, "tactic direct_points must be >= 1, got 0"),
        ({"layers": 0}, "tactic layers must be >= 1, got 0"),
        ({"layer_step_m": -0.5}, r"tactic layer_step_m must be >= 0, got -0.5"),
        ({"layers": 4, "layer_step_m": 12.0, "layer_top_m": 36.0}, "put the lowest at 0 m"),
        ({"tactic": "tail"}, r"tactic must be one of \['head', 'flank', 'auto'\], got 'tail'"),
    ],
)
def test_each_bad_tactic_field_is_named(kw, msg) -> None:
    with pytest.raises(ValueError, match=msg):
        TacticConfig(**kw)


def test_the_smallest_valid_values_are_accepted() -> None:
    c = TacticConfig(min_burning_cells=1, direct_points=1, layers=1, layer_step_m=0.0, layer_top_m=0.5)
    assert c.layer_height_m(7) == 0.5
    TacticConfig(layers=4, layer_step_m=11.9, layer_top_m=36.0)  # lowest at 0.3 m: above ground


@settings(max_examples=25, deadline=None)
@given(layers=st.integers(1, 6), step=st.floats(0.0, 9.0), top=st.floats(50.0, 80.0), ids=st.integers(0, 40))
def test_layer_heights_are_the_stack_top_down_by_id_modulo_layers(layers, step, top, ids) -> None:
    """``layer_top_m`` down in steps of ``layer_step_m``: the heights of ids 0..layers-1 are exactly
    the stack {top - k step}; an id and id + layers share a layer."""
    c = TacticConfig(layers=layers, layer_step_m=step, layer_top_m=top)
    hs = sorted(c.layer_height_m(k) for k in range(layers))
    expect = sorted(top - k * step for k in range(layers))
    assert hs == pytest.approx(expect)
    assert c.layer_height_m(ids) == c.layer_height_m(ids + layers)


def test_raster_layers_properties() -> None:
    """Step max(R, separation) + 2 e; top 2 e below the range; as many layers as fit above the floor
    (capped)."""
    for r, rng, floor, e, sep in [
        (3.0, 40.0, 7.5, 2.0, 0.0),
        (3.0, 40.0, 7.5, 2.0, 10.0),
        (1.0, 60.0, 5.0, 1.0, 4.0),
        (2.0, 30.0, 10.0, 0.5, 1.0),
        (4.0, 50.0, 13.0, 2.0, 0.0),
    ]:
        n, step, top = raster_layers(r, rng, floor, e, sep)
        assert step == pytest.approx(max(r, sep) + 2 * e) and top == pytest.approx(rng - 2 * e)
        assert 1 <= n <= MAX_LAYERS
        assert top - (n - 1) * step >= floor - 1e-9
        assert n == MAX_LAYERS or top - n * step < floor
    # exactly fitting: (36 - 8) / 14 = 2 steps -> 3 layers, the lowest on the floor
    assert raster_layers(3.0, 40.0, 8.0, 2.0, 10.0)[0] == 3
    assert raster_layers(3.0, 40.0, 7.5) == raster_layers(3.0, 40.0, 7.5, TRACKING_ERROR_M)
    assert raster_layers(-2.0, 40.0, 7.5, 0.0)[0] == MAX_LAYERS  # no step: the cap
    with pytest.raises(ValueError, match=r"\(36 m\) is not above the floor \(36 m\)"):
        raster_layers(3.0, 40.0, 36.0, 2.0)


def test_ff_layer_heights_are_centred_on_the_flight_height() -> None:
    """``layers`` heights ``step_m`` apart whose mean is the flight height; the 6 x 3.5 m default."""
    for layers, step in ((6, 3.5), (4, 2.0), (3, 5.0)):
        hs = np.array([layer_height(k, 20.0, layers, step) for k in range(layers)])
        assert np.mean(hs) == pytest.approx(20.0)
        assert np.allclose(np.diff(np.sort(hs)), step) and len(set(hs.round(9))) == layers
        assert layer_height(layers + 1, 20.0, layers, step) == layer_height(1, 20.0, layers, step)
    d = np.array([layer_height(k, 30.0) for k in range(6)])
    assert np.mean(d) == pytest.approx(30.0) and np.ptp(d) == pytest.approx(5 * 3.5)
    assert layer_height(6, 30.0) == layer_height(0, 30.0)


@pytest.mark.parametrize("n", [1, 3, 5, 8])
def test_direct_run_points_are_a_regular_polygon_on_the_spread_circle(n) -> None:
    cfg = TacticConfig(direct_points=n, direct_spread_m=40.0)
    pts = np.array([direct_run_point((-100.0, 50.0), k, cfg) for k in range(n)])
    assert np.allclose(np.hypot(pts[:, 0] + 100.0, pts[:, 1] - 50.0), 40.0)
    if n > 1:
        d = np.hypot(*(pts[:, None, :] - pts[None, :, :]).transpose(2, 0, 1))
        side = 2 * 40.0 * math.sin(math.pi / n)
        assert d[~np.eye(n, dtype=bool)].min() == pytest.approx(side)
        assert np.allclose(np.sort(d, axis=1)[:, 1], side)  # every point has its neighbour one side away
    assert direct_run_point((-100.0, 50.0), n + 2, cfg) == pytest.approx(
        direct_run_point((-100.0, 50.0), 2, cfg)
    )


# --- anchor and weights ---------------------------------------------------------------------
def test_the_anchor_is_the_slowest_known_cell_first_among_ties() -> None:
    assert choose_anchor(FrontCells.empty()) is None
    assert choose_anchor(front([0.0, 10.0, 20.0], [1.0, 2.0, 3.0], [np.nan, 0.3, 0.2])) == (20.0, 3.0)
    assert choose_anchor(front([0.0, 10.0, 20.0], ros=[0.5, 0.2, 0.2])) == (10.0, 0.0)
    assert choose_anchor(front([7.0, 10.0], [8.0, 9.0])) == (7.0, 8.0)  # no ROS known: the first


@settings(max_examples=25, deadline=None)
@given(
    ros=st.lists(st.one_of(st.floats(0.01, 3.0), st.just(float("nan"))), min_size=2, max_size=12),
    p=st.sampled_from([1.0, 2.0, 3.0]),
    wmin=st.sampled_from([0.0, 0.02, 0.1]),
)
def test_head_weights_rank_by_ros_and_unknown_counts_as_the_mean(ros, p, wmin) -> None:
    r = np.array(ros)
    w = front_weights(
        front(np.arange(r.size) * 5.0, ros=r), TacticConfig("head", head_power=p, min_weight=wmin)
    )
    known = np.isfinite(r)
    if not known.any():
        assert np.array_equal(w, np.ones(r.size))
        return
    filled = np.where(known, r, r[known].mean())
    assert w.max() == pytest.approx(1.0 + wmin)
    assert w[int(np.argmax(filled))] == pytest.approx(1.0 + wmin)
    for a in range(r.size):
        for b in range(r.size):
            if filled[a] > filled[b] * (1 + 1e-9):
                assert w[a] > w[b]
            # the power law: (w_a - wmin) / (w_b - wmin) = (R_a / R_b)^p
            assert (w[a] - wmin) * filled[b] ** p == pytest.approx((w[b] - wmin) * filled[a] ** p, rel=1e-6)


def test_head_weights_without_a_positive_rate_are_uniform_and_a_negative_rate_counts_as_zero() -> None:
    cfg = TacticConfig("head", min_weight=0.05)
    assert np.array_equal(front_weights(front([0.0, 1.0], ros=[0.0, 0.0]), cfg), np.ones(2))
    assert np.array_equal(front_weights(front([0.0, 1.0], ros=[np.nan, np.nan]), cfg), np.ones(2))
    assert front_weights(FrontCells.empty(), cfg).shape == (0,)
    assert front_weights(FrontCells.empty(), TacticConfig("flank")).shape == (0,)
    w = front_weights(front([0.0, 1.0], ros=[-0.4, 0.8]), cfg)
    assert w == pytest.approx([0.05, 1.05])


def test_flank_weights_decay_by_e_per_scale_length_from_the_nearest_cell_to_the_anchor() -> None:
    """w = exp(-(d - d_min) / L) + w_min: the cell nearest the anchor 1 + w_min, one L farther
    1/e + w_min; an anchor off the front (30 m before the first cell) changes nothing of that."""
    cfg = TacticConfig("flank", flank_scale_m=40.0, min_weight=0.03)
    f = front([0.0, 40.0, 80.0, 20.0], ros=[0.9, 0.1, 0.5, 0.7])
    w = front_weights(f, cfg, (-30.0, 0.0))
    assert w == pytest.approx([1.03, math.exp(-1) + 0.03, math.exp(-2) + 0.03, math.exp(-0.5) + 0.03])
    wa = front_weights(f, cfg)  # default anchor: the slowest cell, x = 40
    assert wa == pytest.approx([math.exp(-1) + 0.03, 1.03, math.exp(-1) + 0.03, math.exp(-0.5) + 0.03])


# --- density, aim, release ------------------------------------------------------------------
def test_density_on_an_offset_grid_is_the_direct_sum_and_empty_is_zero() -> None:
    g = make_grid(-300.0, -100.0, 1000.0, 1150.0, 5.0)
    assert np.array_equal(front_density(g, FrontCells.empty(), np.zeros(0), 10.0), np.zeros(len(g.points)))
    x = np.array([-297.5, -197.5, -102.5, -152.5])
    y = np.array([1002.5, 1072.5, 1147.5, 1147.5])
    w = np.array([1.0, 0.5, 2.0, 0.25])
    for sigma in (7.0, 12.0):
        d = front_density(g, front(x, y), w, sigma)
        q = g.points
        exact = (w * np.exp(-((q[:, :1] - x) ** 2 + (q[:, 1:] - y) ** 2) / (2 * sigma**2))).sum(axis=1)
        assert np.max(np.abs(d - exact)) <= 0.04 * exact.max()


def test_aim_point_rules() -> None:
    f = front([0.0, 10.0, 20.0, 30.0], [0.0, 0.0, 0.0, 50.0])
    w = np.array([1.0, 3.0, 3.0, 2.0])
    cell = np.array([True, False, False, True])
    assert aim_on_front((0.0, 0.0), FrontCells.empty(), np.zeros(0), np.zeros(0, dtype=bool)) is None
    assert aim_on_front((29.0, 40.0), f, w, cell) == (30.0, 50.0)  # own cell, nearest the centroid
    assert aim_on_front(None, f, w, cell) == (30.0, 50.0)  # own cell, no centroid: the heaviest there
    none = np.zeros(4, dtype=bool)
    assert aim_on_front((19.0, 0.0), f, w, none) == (20.0, 0.0)  # heaviest, ties: nearest centroid
    assert aim_on_front((11.0, 0.0), f, w, none) == (10.0, 0.0)
    assert aim_on_front(None, f, w, none) == (10.0, 0.0)  # heaviest, first


def test_burning_cells_are_counted_out_to_the_radius_inclusive() -> None:
    x = np.array([0.0, 3.0, 0.0, -5.0, 6.0, 0.0])
    y = np.array([0.0, 4.0, -5.0, 0.0, 0.0, 1.0])
    s = np.array([B, B, B, N, B, U])
    assert burning_within((x, y, s), (0.0, 0.0), 5.0) == 3  # (3, 4) and (0, -5) exactly at 5 m
    assert burning_within((x, y, s), (3.0, 0.0), 3.0) == 2  # (0, 0) and (6, 0)
    assert burning_within((np.zeros(0), np.zeros(0), np.zeros(0)), (0.0, 0.0), 5.0) == 0
    assert burning_within(None, (0.0, 0.0), 5.0) == 0


def test_release_at_the_threshold_and_on_a_level_pass_along_the_heading() -> None:
    """A row of burning cells along y: flying north along it, as many ahead as here is the peak
    (release); exactly ``min_burning_cells`` under the footprint is enough; heading matters."""
    ys = np.arange(0.0, 101.0, 5.0)
    cells = (np.zeros(ys.size), ys, np.full(ys.size, B))
    cfg = TacticConfig(min_burning_cells=3, release_radius_m=5.0)
    assert burning_within(cells, (0.0, 50.0), 5.0) == 3
    assert release_now(cells, (0.0, 50.0), math.pi / 2, 5.0, cfg)  # 3 here, 3 ahead: level
    four = TacticConfig(min_burning_cells=4, release_radius_m=5.0)
    assert not release_now(cells, (0.0, 50.0), math.pi / 2, 5.0, four)  # 3 < 4 under the footprint
    # 2 m short of the row's south end flying north: 1 cell here, 2 one step ahead: wait
    one = TacticConfig(min_burning_cells=1, release_radius_m=5.0)
    assert not release_now(cells, (0.0, -2.0), math.pi / 2, 5.0, one)
    # the same position flying south (away from the row): this is the peak
    assert release_now(cells, (0.0, -2.0), -math.pi / 2, 5.0, one)
    # flying east across the row at its middle: ahead is empty, release
    assert release_now(cells, (0.0, 50.0), 0.0, 10.0, cfg)


def test_small_positive_sizes_are_accepted() -> None:
    c = TacticConfig(sigma_m=0.5, flank_scale_m=0.5, release_radius_m=0.5)
    assert (c.sigma_m, c.flank_scale_m, c.release_radius_m) == (0.5, 0.5, 0.5)


def test_raster_layers_with_small_and_zero_steps() -> None:
    """Step 1 m (R 0, e 0.5): top 11 m, floor 7.5 m -> layers at 11, 10, 9, 8 m; no step at all (R 0,
    e 0): every layer fits, the cap."""
    assert raster_layers(0.0, 12.0, 7.5, 0.5) == (4, 1.0, 11.0)
    assert raster_layers(0.0, 40.0, 7.5, 0.0)[0] == MAX_LAYERS


def test_flank_weights_use_the_anchor_distance_in_2d() -> None:
    """Cells on a vertical line x = 0 at y = 100, 140, 180, anchor at (0, 60): d = 40, 80, 120."""
    cfg = TacticConfig("flank", flank_scale_m=40.0, min_weight=0.0)
    f = front([0.0, 0.0, 0.0], [100.0, 140.0, 180.0])
    assert front_weights(f, cfg, (0.0, 60.0)) == pytest.approx([1.0, math.exp(-1), math.exp(-2)])
    g = front([100.0, 130.0], [50.0, 90.0])  # anchor (100, 50): d = 0, 50
    assert front_weights(g, cfg, (100.0, 50.0)) == pytest.approx([1.0, math.exp(-50.0 / 40.0)])


def test_density_reaches_out_to_the_three_sigma_cut_off_in_every_direction() -> None:
    """Eq. 13' truncated at 3 sigma (the module's kernel cut-off): at 3 sigma from a lone cell the
    density is exp(-4.5) of its weight, east, west, north and south alike; beyond, zero."""
    g = make_grid(0.0, 300.0, 0.0, 300.0, 5.0)
    f = front([152.5], [152.5])
    d = front_density(g, f, np.array([1.0]), 10.0).reshape(g.shape)
    i = j = 30  # the cell's grid point
    for di, dj in ((0, 6), (0, -6), (6, 0), (-6, 0)):  # 30 m = 3 sigma
        assert d[i + di, j + dj] == pytest.approx(math.exp(-4.5), rel=0.3)
    for di, dj in ((0, 7), (0, -7), (7, 0), (-7, 0)):
        assert d[i + di, j + dj] == 0.0


def test_a_single_burning_cell_counts_and_release_looks_ahead_along_the_heading() -> None:
    one = (np.array([40.0]), np.array([-20.0]), np.array([B]))
    assert burning_within(one, (40.0, -20.0), 1.0) == 1
    # a row along x at y = 0 (x = 0, 5, ..., 100): 2 m short of its east end flying east, ahead
    # (103, 0) has 1 cell against 2 here: the peak, release
    xs = np.arange(0.0, 101.0, 5.0)
    row = (xs, np.zeros(xs.size), np.full(xs.size, B))
    cfg = TacticConfig(min_burning_cells=1, release_radius_m=5.0)
    assert burning_within(row, (98.0, 0.0), 5.0) == 2
    assert release_now(row, (98.0, 0.0), 0.0, 5.0, cfg)
    assert not release_now(row, (98.0, 0.0), math.pi, 3.0, cfg)  # flying west: 3 at (95, 0)
