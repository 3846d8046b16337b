"""The raster front picture, its sharing, and the targeting rules.

Truth used: hand-built cell layouts whose front is known by construction, Rothermel's head rate
(``fire_world_sim.fires.rothermel.head_spread``, itself checked against Behave) for the PM
rate of spread per direction, the analytic Gaussian for Eq. 13', and merge-order invariance
(a join) for the consensus.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.coverage import make_grid
from fire_uav_agent.fire_front import UNKNOWN, FrontCells, FrontConfig, FrontPicture
from fire_uav_agent.front_consensus import FrontSharing
from fire_uav_agent.tactics import (
    TacticConfig,
    aim_on_front,
    burning_within,
    choose_anchor,
    front_density,
    front_weights,
    release_now,
)
from fire_uav_common.constants import CellState
from hypothesis import given, settings
from hypothesis import strategies as st

B, N, U = int(CellState.BURNING), int(CellState.BURNED), int(CellState.UNBURNED)
CS = 5.0


def layout(rows: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cells from text, row 0 = north: '#' burned, '*' burning, '.' unburned, ' ' unseen."""
    xs, ys, st_ = [], [], []
    code = {"#": N, "*": B, ".": U}
    h = len(rows)
    for r, line in enumerate(rows):
        for c, ch in enumerate(line):
            if ch in code:
                xs.append((c + 0.5) * CS)
                ys.append((h - 1 - r + 0.5) * CS)
                st_.append(code[ch])
    return np.array(xs), np.array(ys), np.array(st_)


def picture(w_cells: int = 10, h_cells: int = 10) -> FrontPicture:
    return FrontPicture(FrontConfig((0.0, w_cells * CS, 0.0, h_cells * CS), CS, min_cells_for_centre=1000))


def cell_set(c: FrontCells) -> set[tuple[int, int]]:
    return {(int(x // CS), int(y // CS)) for x, y in zip(c.x_m, c.y_m, strict=True)}


def test_front_is_the_burning_edge_not_the_burnt_interior_nor_an_enclosed_burning_cell() -> None:
    rows = [
        ".......",
        ".*****.",
        ".*###*.",
        ".*#*#*.",  # the middle '*' is enclosed by burnt cells: not front
        ".*###*.",
        ".*****.",
        ".......",
    ]
    p = picture(7, 7)
    p.observe(*layout(rows), t_s=10.0)
    got = cell_set(p.front())
    ring = {(c, 6 - r) for r in range(7) for c in range(7) if rows[r][c] == "*" and (r, c) != (3, 3)}
    assert got == ring and len(ring) == 16


def test_unseen_neighbours_count_as_open_and_stale_cells_leave_the_front() -> None:
    p = picture(4, 3)
    p.observe(*layout(["##*", "##*", "##*"]), t_s=0.0)  # column 3 never seen
    assert len(p.front(0.0)) == 3
    assert len(p.front(p.cfg.max_age_s + 1.0)) == 0
    assert p.state[0, 3] == UNKNOWN


def test_an_extinguished_cell_seen_burnt_leaves_the_front() -> None:
    p = picture(3, 1)
    p.observe(*layout(["#*."]), t_s=1.0)
    assert len(p.front()) == 1
    p.observe(*layout(["##."]), t_s=2.0)
    assert len(p.front()) == 0


def _msgs() -> list[FrontCells]:
    x, y, s = layout(["#**.", "#*..", "##*."])
    return [
        FrontCells(x, y, s, np.full(x.size, 5.0), np.full(x.size, np.nan)),
        FrontCells(x[:4], y[:4], np.full(4, N), np.full(4, 9.0), np.full(4, np.nan)),  # newer: burnt
        FrontCells(
            x[4:], y[4:], np.full(x.size - 4, U), np.full(x.size - 4, 1.0), np.full(x.size - 4, np.nan)
        ),
    ]


@settings(max_examples=30, deadline=None)
@given(st.permutations(list(range(6))))
def test_merging_is_order_independent(order: list[int]) -> None:
    msgs = _msgs() + _msgs()  # duplicates too
    ref = picture(4, 3)
    for m in msgs:
        ref.merge(m)
    p = picture(4, 3)
    for k in order:
        p.merge(msgs[k])
    assert np.array_equal(p.state, ref.state) and np.array_equal(p.t_obs, ref.t_obs)
    assert cell_set(p.front(9.0)) == cell_set(ref.front(9.0))


def test_two_agents_that_share_fronts_agree_and_retractions_propagate() -> None:
    a, b = picture(8, 3), picture(8, 3)
    left = ["#*..", "#*..", "#*.."]
    right = ["..*#", "..*#", "..*#"]
    xa, ya, sa = layout(left)
    xb, yb, sb = layout(right)
    a.observe(xa, ya, sa, 1.0)
    b.observe(xb + 4 * CS, yb, sb, 1.0)
    sha, shb = FrontSharing(), FrontSharing()
    b.merge(sha.message(a, 1.0))
    a.merge(shb.message(b, 1.0))
    assert cell_set(a.front()) == cell_set(b.front()) and len(a.front()) == 6
    # a sees its burning column put out (burnt); its next message retracts them at b
    a.observe(xa, ya, np.where(sa == B, N, sa), 3.0)
    b.merge(sha.message(a, 3.0))
    assert cell_set(b.front(3.0)) == cell_set(a.front(3.0)) and len(b.front(3.0)) == 3


def test_merge_rejects_unequal_arrays_with_a_clear_error() -> None:
    with pytest.raises(ValueError, match="must have the same length"):
        FrontCells(np.zeros(2), np.zeros(3), np.zeros(2), np.zeros(2), np.zeros(2))
    with pytest.raises(ValueError, match="front cell_size_m must be > 0"):
        FrontConfig((0.0, 1.0, 0.0, 1.0), 0.0)


def test_pm_rate_of_spread_toward_the_head_matches_rothermel() -> None:
    """A raster fire (fire_world_sim) seen whole at two times 60 s apart: the PM Eq. 1 ROS of the
    front toward the wind is Rothermel's head rate (within 20 %), and the head has the largest ROS."""
    from fire_uav_common.scenario import Ignition, Raster, Wind
    from fire_uav_common.terrain import Terrain
    from fire_world_sim.fires import RasterFireModel
    from fire_world_sim.fires.fuel_models import fuel_model
    from fire_world_sim.fires.rothermel import head_spread, spread_params

    spec = Raster(
        cell_size_m=CS, nx=120, ny=80, wind=(Wind(0.0, 3.0, 0.0),), ignitions=(Ignition(150.0, 200.0),)
    )
    m = RasterFireModel(spec, Terrain())
    rh = float(head_spread(spread_params(fuel_model(1), 0.06), 3.0, 0.0, 0.0, 0.0)[0])
    p = FrontPicture(FrontConfig((0.0, 600.0, 0.0, 400.0), CS, revisit_gap_s=30.0))
    t = 0.0
    xs, ys = np.meshgrid(m.xc, m.yc)
    for t_obs in (120.0, 180.0):
        while t < t_obs - 1e-9:
            m.step(t, 0.5)
            t += 0.5
        p.observe(xs.ravel(), ys.ravel(), m.state_grid().ravel(), t_obs)
    f = p.front()
    k = int(np.nanargmax(f.ros_mps))
    head = int(np.argmax(f.x_m))
    assert f.ros_mps[head] == pytest.approx(rh, rel=0.2)
    assert f.x_m[k] >= f.x_m.max() - 3 * CS  # the fastest front cell is at the head


def test_head_weights_follow_ros_and_the_flank_anchor_is_the_slowest_cell() -> None:
    x = np.array([0.0, 50.0, 100.0, 150.0])
    f = FrontCells(x, np.zeros(4), np.full(4, B), np.zeros(4), np.array([0.1, 0.4, 1.0, np.nan]))
    w = front_weights(f, TacticConfig("head"))
    assert int(np.argmax(w)) == 2 and w[0] < w[1] < w[2]
    assert choose_anchor(f) == (0.0, 0.0)
    wf = front_weights(f, TacticConfig("flank", flank_scale_m=50.0), choose_anchor(f))
    assert wf[0] > wf[1] > wf[2] > wf[3]
    assert wf[1] - 0.02 == pytest.approx(math.exp(-1.0))
    with pytest.raises(ValueError, match="tactic must be one of"):
        TacticConfig("tail")


def test_density_is_the_sum_of_gaussians_of_eq13() -> None:
    g = make_grid(0.0, 200.0, 0.0, 200.0, 5.0)
    f = FrontCells(np.array([102.5]), np.array([102.5]), np.array([B]), np.zeros(1), np.zeros(1))
    d = front_density(g, f, np.array([1.0]), 10.0).reshape(g.shape)
    i = j = 20  # grid point (102.5, 102.5)
    assert d[i, j] == pytest.approx(1.0, rel=0.03)
    assert d[i, j + 2] == pytest.approx(math.exp(-0.5), rel=0.05)  # 10 m = one sigma east


def test_aim_is_a_front_cell_of_the_own_cell_nearest_the_centroid() -> None:
    f = FrontCells(np.array([0.0, 10.0, 20.0]), np.zeros(3), np.full(3, B), np.zeros(3), np.zeros(3))
    w = np.array([1.0, 2.0, 3.0])
    assert aim_on_front((11.0, 5.0), f, w, np.array([True, True, False])) == (10.0, 0.0)
    assert aim_on_front((0.0, 0.0), f, w, np.zeros(3, dtype=bool)) == (20.0, 0.0)  # none in cell: heaviest


def test_release_only_over_burning_cells_at_the_peak_of_the_pass() -> None:
    cfg = TacticConfig(min_burning_cells=3, release_radius_m=10.0)
    x, y, s = layout(["..***..", "..***..", "..***.."])  # burning cells at x 12.5..22.5
    cells = (x, y, s)
    assert burning_within(cells, (17.5, 7.5), 10.0) == 9
    assert not release_now(cells, (-30.0, 7.5), 0.0, 4.5, cfg)  # nothing burning under it
    assert not release_now(cells, (8.0, 7.5), 0.0, 4.5, cfg)  # burning ahead: more to come
    assert release_now(cells, (17.5, 7.5), 0.0, 4.5, cfg)  # over the middle
    assert not release_now(None, (17.5, 7.5), 0.0, 4.5, cfg)


def test_density_of_many_scattered_cells_is_the_exact_sum_of_gaussians_everywhere() -> None:
    """Eq. 13' evaluated directly on every grid point, for cells spread over the grid and at its
    edges (the density is computed on a window around the cells: nothing may be lost outside it)."""
    g = make_grid(0.0, 400.0, 0.0, 300.0, 5.0)
    rng = np.random.default_rng(3)
    n = 40
    # cell centres on the 5 m lattice (the splat is exact there), a few on the grid's border
    x = (rng.integers(0, 80, n) + 0.5) * 5.0
    y = (rng.integers(0, 60, n) + 0.5) * 5.0
    x[:3], y[:3] = 2.5, 297.5
    w = rng.uniform(0.1, 1.0, n)
    f = FrontCells(x, y, np.full(n, B), np.zeros(n), np.zeros(n))
    sigma = 10.0
    d = front_density(g, f, w, sigma)
    q = g.points
    exact = (w[None, :] * np.exp(-((q[:, :1] - x) ** 2 + (q[:, 1:] - y) ** 2) / (2 * sigma**2))).sum(axis=1)
    # gaussian_filter's sampled, truncated (3 sigma), renormalised kernel: a few % of the peak
    assert np.max(np.abs(d - exact)) <= 0.03 * exact.max()
    # beyond the 3 sigma kernel (separable: a square support) it is zero
    far = np.min(np.maximum(np.abs(q[:, :1] - x), np.abs(q[:, 1:] - y)), axis=1) > 3.5 * sigma
    assert far.any() and np.all(d[far] == 0.0)


def test_front_follows_every_new_observation_and_merge() -> None:
    """front() is cached per step: a later sighting or a peer's cells must show in it at once."""
    p = picture()
    p.observe(*layout(["....", ".**.", "...."]), 1.0)
    assert cell_set(p.front()) == {(1, 1), (2, 1)}
    p.observe(np.array([7.5]), np.array([7.5]), np.array([N]), 2.0)  # (1, 1) seen burnt out
    assert cell_set(p.front()) == {(2, 1)}
    peer = FrontCells(np.array([12.5]), np.array([7.5]), np.array([N]), np.array([3.0]), np.array([np.nan]))
    p.merge(peer)
    assert len(p.front()) == 0


def test_direct_run_points_of_a_fleet_are_apart_around_the_track_centre() -> None:
    """Stalled UAVs over a contained raster fire fly at distinct points, not at one centre:
    six points on a 25 m circle are a regular hexagon, neighbours one radius (25 m) apart."""
    from fire_uav_agent.tactics import direct_run_point

    cfg = TacticConfig()
    pts = np.array([direct_run_point((300.0, 400.0), k, cfg) for k in range(6)])
    assert np.allclose(np.hypot(pts[:, 0] - 300.0, pts[:, 1] - 400.0), 25.0)
    d = np.hypot(pts[:, None, 0] - pts[None, :, 0], pts[:, None, 1] - pts[None, :, 1])
    assert d[~np.eye(6, dtype=bool)].min() == pytest.approx(25.0)
