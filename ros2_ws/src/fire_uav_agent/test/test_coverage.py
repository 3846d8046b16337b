"""Voronoi-Lloyd coverage (FF Eqs. 6-12)."""

import math

import numpy as np
from fire_uav_agent.coverage import (
    ControlGains,
    VehicleLimits,
    control_law,
    gaussian_density,
    make_grid,
    mass_centroid,
    own_cell,
    voronoi_labels,
)
from fire_uav_common.terrain import Terrain

GRID = make_grid(0, 600, 0, 600, 5.0)


def test_cells_partition_the_grid_exactly():
    rng = np.random.default_rng(1)
    pos = rng.uniform(0, 600, (9, 2))
    labels = voronoi_labels(GRID.points, pos)
    masks = np.array([labels == i for i in range(9)])
    assert np.all(masks.sum(axis=0) == 1)  # every grid cell assigned exactly once
    for i in range(9):  # own_cell (Eq. 6, no band) agrees with the global tessellation
        own = own_cell(GRID.points, pos[i], np.delete(pos, i, axis=0))
        assert np.array_equal(own, masks[i])  # no ties with random positions


def test_safety_band_keeps_centroids_apart():
    fire = gaussian_density(GRID, [(300.0, 300.0)], [50.0])
    p1, p2 = np.array([296.0, 300.0]), np.array([304.0, 300.0])  # 8 m apart, Delta = 20 m
    sep = {}
    for band in (None, 10.0):
        c1 = mass_centroid(GRID.points, fire, own_cell(GRID.points, p1, p2[None], band), 25.0)[1]
        c2 = mass_centroid(GRID.points, fire, own_cell(GRID.points, p2, p1[None], band), 25.0)[1]
        sep[band] = float(np.linalg.norm(c1 - c2))
        assert c1[0] < 300 < c2[0]  # each stays on its side
    assert sep[10.0] > sep[None] and sep[10.0] > 8.0
    # the band leaves a no-man's land between the two cells
    m1 = own_cell(GRID.points, p1, p2[None], 10.0)
    m2 = own_cell(GRID.points, p2, p1[None], 10.0)
    assert not np.any(m1 & m2) and np.any(~(m1 | m2))


def test_centroid_of_single_gaussian_in_full_cell():
    d = gaussian_density(GRID, [(200.0, 350.0)], [30.0])
    m, c = mass_centroid(GRID.points, d, np.ones(len(d), bool), GRID.cell_area_m2)
    assert np.allclose(c, [200, 350], atol=0.5)
    assert math.isclose(m, 2 * math.pi * 30**2, rel_tol=1e-3)  # Eq. 8: integral of the Gaussian


def test_control_law_points_toward_centroid_and_respects_limits():
    lim, g = VehicleLimits(), ControlGains()
    v, vz, om = control_law(np.array([0.0, 0.0, 30.0, 0.0]), np.array([0.0, 100.0]), 30.0, Terrain(), lim, g)
    assert v == lim.v_max_mps and om == 5.0 * math.pi / 2 and vz == 0.0
    v, _, om = control_law(np.array([0.0, 0.0, 30.0, 0.0]), np.array([0.1, 0.0]), 30.0, Terrain(), lim, g)
    assert v == lim.v_stall_mps and om == 0.0
    _, vz, om = control_law(np.array([0, 0, 0.0, 0]), np.array([-10.0, -0.001]), 30.0, Terrain(), lim, g)
    assert vz == g.vz_cmd_max_mps and om == -lim.omega_max_radps
    # Eq. 12 with terrain: climb on a slope while flying up it
    _, vz, _ = control_law(
        np.array([0, 0, 30.0, 0]), np.array([100.0, 0]), 30.0, Terrain(slope_x=0.1), lim, g
    )
    assert vz > 5.0
