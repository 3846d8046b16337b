"""Power-diagram balancing (CP Eqs. 2-8) and exclusive assignment (Eq. 9)."""

from __future__ import annotations

import numpy as np
import pytest
from fire_uav_agent.search.errors import PartitionError, SearchConfigError
from fire_uav_agent.search.power_diagram import (
    BalanceConfig,
    BalancerAgent,
    CoverageGrid,
    assign_cells,
    balance_weights,
    equal_targets_m2,
    make_regions_connected,
    power_cell_areas_m2,
    power_cell_centroids_m,
    quadrature,
    worst_area_error,
)
from scipy import ndimage


def _grid(obstacles: bool = False) -> CoverageGrid:
    mask = None
    if obstacles:
        mask = np.zeros((10, 10), dtype=bool)
        mask[3:7, 4:6] = True  # a no-fly block in the middle
    return CoverageGrid.from_area(0.0, 1200.0, 0.0, 1200.0, cell_size_m=120.0, obstacle_mask=mask)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("obstacles", [False, True])
def test_balancing_converges_below_epsilon(seed: int, obstacles: bool) -> None:
    rng = np.random.default_rng(seed)
    grid = _grid(obstacles)
    n = int(rng.integers(2, 7))
    seeds = rng.uniform(0.0, 1200.0, size=(n, 2))
    config = BalanceConfig(epsilon=0.02)
    res = balance_weights(grid, seeds, config)
    assert res.converged
    assert res.e_max < config.epsilon
    np.testing.assert_allclose(res.areas_m2.sum(), grid.free_area_m2)
    np.testing.assert_allclose(res.targets_m2, grid.free_area_m2 / n)  # Eq. 5
    # the reported E_max is Eq. 7 recomputed from scratch
    quad = quadrature(grid, config.subdiv)
    areas = power_cell_areas_m2(quad, seeds, res.weights_m2)
    assert worst_area_error(areas, res.targets_m2) == pytest.approx(res.e_max)


def test_fixed_step_of_the_paper_also_converges_for_well_spread_seeds() -> None:
    grid = _grid()
    seeds = np.array([[200.0, 200.0], [1000.0, 250.0], [600.0, 1000.0]])
    config = BalanceConfig(gamma=0.3, gamma_growth=1.0, gamma_shrink=1.0)
    res = balance_weights(grid, seeds, config)
    assert res.converged and res.e_max < config.epsilon


@pytest.mark.parametrize("seed", range(10))
def test_every_free_cell_assigned_exactly_once_and_regions_connected(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    grid = _grid(obstacles=seed % 2 == 1)
    n = int(rng.integers(2, 8))
    seeds = rng.uniform(0.0, 1200.0, size=(n, 2))
    res = balance_weights(grid, seeds)
    labels = make_regions_connected(assign_cells(grid, seeds, res.weights_m2))
    # Eq. 9: each free cell has exactly one owner in 0..n-1, obstacles none
    assert np.all((labels >= 0) == grid.free)
    assert labels.max() < n
    masks = [labels == i for i in range(n)]
    assert np.array_equal(np.sum(masks, axis=0), grid.free.astype(int))
    for m in masks:
        if m.any():
            _, k = ndimage.label(m, structure=[[0, 1, 0], [1, 1, 1], [0, 1, 0]])
            assert k == 1


def test_decentralised_agents_match_lockstep_loop() -> None:
    grid = _grid()
    seeds = np.array([[100.0, 100.0], [150.0, 900.0], [1100.0, 600.0], [600.0, 600.0]])
    quad = quadrature(grid, 4)
    targets = equal_targets_m2(grid, 4)
    agents = [BalancerAgent(i, seeds[i], targets[i], quad) for i in range(4)]
    for _ in range(500):
        inbox = {a.uav_id: a.report() for a in agents}  # what each agent receives
        if all([a.step(inbox) for a in agents]):
            break
    res = balance_weights(grid, seeds, quad=quad)
    np.testing.assert_allclose([a.weight_m2 for a in agents], res.weights_m2)
    assert all(a.converged for a in agents)
    assert agents[0].report().iteration == res.iterations


def test_agent_refuses_reports_of_another_iteration() -> None:
    grid = _grid()
    quad = quadrature(grid, 2)
    a = BalancerAgent(0, (100.0, 100.0), 1e5, quad)
    b = BalancerAgent(1, (900.0, 900.0), 1e5, quad)
    stale = b.report()._replace(iteration=3)
    with pytest.raises(PartitionError, match="iteration 3, expected 0"):
        a.step({0: a.report(), 1: stale})
    with pytest.raises(PartitionError, match="own report missing"):
        a.step({1: b.report()})
    c = BalancerAgent(0, (100.0, 100.0), 1e5, quad, fleet_ids=[0, 1, 2])
    with pytest.raises(PartitionError, match=r"missing from uavs \[2\]"):
        c.step({0: c.report(), 1: b.report()})


def test_centroids_of_two_halves() -> None:
    grid = CoverageGrid.from_area(0.0, 200.0, 0.0, 100.0, cell_size_m=10.0)
    quad = quadrature(grid, 2)
    c = power_cell_centroids_m(quad, np.array([[50.0, 50.0], [150.0, 50.0]]), np.zeros(2))
    np.testing.assert_allclose(c, [[50.0, 50.0], [150.0, 50.0]])


def test_grid_errors() -> None:
    mask = np.zeros((3, 3), dtype=bool)
    mask[:, 1] = True  # splits the free space in two
    with pytest.raises(PartitionError, match="4-connected"):
        CoverageGrid.from_area(0, 30, 0, 30, cell_size_m=10, obstacle_mask=mask)
    with pytest.raises(SearchConfigError, match="cell_size_m"):
        CoverageGrid.from_area(0, 30, 0, 30, cell_size_m=0.0)
    with pytest.raises(SearchConfigError, match="shape"):
        CoverageGrid.from_area(0, 30, 0, 30, cell_size_m=10, obstacle_mask=np.zeros((2, 2)))
    with pytest.raises(SearchConfigError, match="epsilon"):
        BalanceConfig(epsilon=0.0)
    with pytest.raises(PartitionError, match="shape"):
        balance_weights(_grid(), np.zeros((3,)))


def test_grid_overhang_rounds_up() -> None:
    g = CoverageGrid.from_area(0.0, 250.0, 0.0, 100.0, cell_size_m=100.0)
    assert (g.nx, g.ny) == (3, 1)
    assert g.free_area_m2 == pytest.approx(30000.0)


def test_zero_weights_give_the_voronoi_diagram() -> None:
    """Eq. 2 with w = 0 is the nearest-seed (Voronoi) rule: compare with a k-d tree."""
    from fire_uav_agent.search.power_diagram import power_labels
    from scipy.spatial import cKDTree

    rng = np.random.default_rng(11)
    seeds = rng.uniform(0.0, 1200.0, size=(6, 2))
    pts = quadrature(_grid(), 3).points_m
    _, nearest = cKDTree(seeds).query(pts)
    np.testing.assert_array_equal(power_labels(pts, seeds, np.zeros(6)), nearest)


@pytest.mark.parametrize("w0,w1", [(0.0, 0.0), (120000.0, 0.0), (0.0, 240000.0), (-60000.0, 60000.0)])
def test_two_seed_power_bisector_areas_and_centroids(w0: float, w1: float) -> None:
    """Seeds (0, y) and (d, y): the power bisector is the line x* = (d^2 + w0 - w1) / (2 d) (Eq. 2),
    so on the rectangle [0, L] x [0, H] cell 0 has area x* H and centroid (x*/2, H/2) (Eq. 3)."""
    grid = CoverageGrid.from_area(0.0, 1200.0, 0.0, 600.0, cell_size_m=100.0)
    quad = quadrature(grid, 4)  # sub-cells of 25 m: every x* below lies on a sub-cell edge
    d = 600.0
    seeds = np.array([[0.0, 300.0], [d, 300.0]])
    x_star = (d * d + w0 - w1) / (2 * d)
    areas = power_cell_areas_m2(quad, seeds, np.array([w0, w1]))
    np.testing.assert_allclose(areas, [x_star * 600.0, (1200.0 - x_star) * 600.0])
    c = power_cell_centroids_m(quad, seeds, np.array([w0, w1]))
    np.testing.assert_allclose(c, [[x_star / 2, 300.0], [(1200.0 + x_star) / 2, 300.0]])
    e = worst_area_error(areas, np.array([360000.0, 360000.0]))
    assert e == pytest.approx(abs(x_star * 600.0 - 360000.0) / 360000.0)


def test_an_empty_power_cell_keeps_its_seed_as_centroid() -> None:
    grid = CoverageGrid.from_area(0.0, 100.0, 0.0, 100.0, cell_size_m=50.0)
    quad = quadrature(grid, 2)
    seeds = np.array([[50.0, 50.0], [500.0, 500.0]])  # the far seed owns nothing
    c = power_cell_centroids_m(quad, seeds, np.zeros(2))
    np.testing.assert_allclose(c, [[50.0, 50.0], [500.0, 500.0]])
    np.testing.assert_allclose(power_cell_areas_m2(quad, seeds, np.zeros(2)), [10000.0, 0.0])


@pytest.mark.parametrize("subdiv", [1, 2, 5])
def test_quadrature_tiles_the_free_cells(subdiv: int) -> None:
    grid = _grid(obstacles=True)
    q = quadrature(grid, subdiv)
    assert len(q.points_m) == grid.free.sum() * subdiv**2
    assert q.area_m2.sum() == pytest.approx(grid.free_area_m2)
    ix = np.floor(q.points_m[:, 0] / grid.cell_size_m).astype(int)
    iy = np.floor(q.points_m[:, 1] / grid.cell_size_m).astype(int)
    np.testing.assert_array_equal(ix, q.coarse_ix)
    np.testing.assert_array_equal(iy, q.coarse_iy)
    assert grid.free[iy, ix].all()
    assert len(np.unique(q.points_m.round(6), axis=0)) == len(q.points_m)
    with pytest.raises(SearchConfigError, match="subdiv"):
        quadrature(grid, 0)


def test_assignment_follows_the_bisector_and_ties_go_to_the_lower_index() -> None:
    """Bisector through the middle of a coarse column: half the votes each, the lower index wins."""
    grid = CoverageGrid.from_area(0.0, 500.0, 0.0, 200.0, cell_size_m=100.0)
    seeds = np.array([[0.0, 100.0], [500.0, 100.0]])  # x* = 250: the middle of column 2
    labels = assign_cells(grid, seeds, np.zeros(2), subdiv=2)
    np.testing.assert_array_equal(labels, [[0, 0, 0, 1, 1], [0, 0, 0, 1, 1]])
    labels = assign_cells(grid, seeds[::-1], np.zeros(2), subdiv=2)
    np.testing.assert_array_equal(labels, [[1, 1, 0, 0, 0], [1, 1, 0, 0, 0]])


def test_a_stray_piece_goes_to_the_neighbour_with_the_longest_border() -> None:
    labels = np.array([[0, 0, 1, 1], [2, 2, 0, 1], [2, 2, 1, 1]])  # the stray 0 borders 1 thrice, 2 once
    out = make_regions_connected(labels)
    fixed = labels.copy()
    fixed[1, 2] = 1
    np.testing.assert_array_equal(out, fixed)
    stray = np.array([[0, 0, 1, 1], [1, 1, 1, 0]])  # agent 0 in two pieces: the smaller one moves
    out = make_regions_connected(stray)
    np.testing.assert_array_equal(out, [[0, 0, 1, 1], [1, 1, 1, 1]])
    with_obstacle = np.array([[0, -1, 0], [0, -1, 0], [0, 0, 0]])
    np.testing.assert_array_equal(make_regions_connected(with_obstacle), with_obstacle)


def test_config_and_target_errors() -> None:
    with pytest.raises(SearchConfigError, match="n_agents"):
        equal_targets_m2(_grid(), 0)
    with pytest.raises(SearchConfigError, match="gamma_min"):
        BalanceConfig(gamma=30.0)
    with pytest.raises(SearchConfigError, match="gamma_growth"):
        BalanceConfig(gamma_shrink=0.0)
    with pytest.raises(SearchConfigError, match="max_iterations"):
        BalanceConfig(max_iterations=0)
    with pytest.raises(SearchConfigError, match="targets_m2"):
        balance_weights(_grid(), np.array([[100.0, 100.0], [900.0, 900.0]]), targets_m2=np.array([1.0, -1.0]))
    with pytest.raises(PartitionError, match="finite"):
        balance_weights(_grid(), np.array([[100.0, np.nan]]))
    with pytest.raises(SearchConfigError, match="target_area_m2"):
        BalancerAgent(0, (0.0, 0.0), 0.0, quadrature(_grid(), 1))
    with pytest.raises(PartitionError, match="no free cell"):
        CoverageGrid.from_area(0, 20, 0, 20, cell_size_m=10, obstacle_mask=np.ones((2, 2), dtype=bool))
    with pytest.raises(SearchConfigError, match="x_max_m > x_min_m"):
        CoverageGrid.from_area(10, 10, 0, 20, cell_size_m=10)
