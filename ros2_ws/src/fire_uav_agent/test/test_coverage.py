"""Voronoi-Lloyd coverage (FF Eqs. 6-12)."""

import math

import numpy as np
import pytest
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


# --- analytic cells, Lloyd, grid, density, guidance (mutation testing) -----------------------
from fire_uav_agent.coverage import virtual_positions  # noqa: E402
from fire_uav_common.scenario import Vehicle  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


def _x_of(mask: np.ndarray) -> np.ndarray:
    return np.unique(GRID.points[mask, 0])


def test_band_cell_boundary_is_the_shifted_bisector_in_closed_form():
    """Eq. 7, two agents on a horizontal line, delta = 10 m each (Delta = 20 m): the plain cell
    of p_i = (285, 300) ends at the bisector x = 300 (d = 30 m); with the band the virtual p~_j
    sits 2 (Delta - d/2) = 10 m closer, so the bisector moves to d - Delta = 10 m from p_i:
    x = 295. Agents 10 m apart (d < Delta): the boundary passes Delta - d = 10 m *behind* p_i."""
    p_i, p_j = np.array([285.0, 300.0]), np.array([315.0, 300.0])
    assert _x_of(own_cell(GRID.points, p_i, p_j[None])).max() == 297.5  # cells x <= 300
    band = own_cell(GRID.points, p_i, p_j[None], 10.0)
    assert _x_of(band).max() == 292.5 and _x_of(band).min() == 2.5  # x <= 295, full height
    assert np.all(band == (GRID.points[:, 0] <= 295.0))
    close = own_cell(GRID.points, np.array([295.0, 300.0]), np.array([[305.0, 300.0]]), 10.0)
    assert np.all(close == (GRID.points[:, 0] <= 285.0))
    # far apart (d/2 >= Delta) the band changes nothing
    far = own_cell(GRID.points, np.array([200.0, 300.0]), np.array([[300.0, 300.0]]), 10.0)
    assert np.all(far == (GRID.points[:, 0] <= 250.0))
    # a band of 0 is no band
    assert np.array_equal(own_cell(GRID.points, p_i, p_j[None], 0.0), own_cell(GRID.points, p_i, p_j[None]))


def test_virtual_position_in_closed_form():
    """Eq. 7: p~_j = p_j + 2 (Delta_ij - d/2) (p_i - p_j)/d if Delta_ij > d/2, else p_j."""
    p_i = np.array([0.0, 0.0])
    others = np.array([[30.0, 0.0], [0.0, -100.0], [0.0, 0.0]])
    v = virtual_positions(p_i, others, 10.0, np.array([10.0, 10.0, 10.0]))
    assert np.allclose(v[0], [20.0, 0.0])  # 30 - 2 (20 - 15)
    assert np.allclose(v[1], [0.0, -100.0])  # Delta 20 < d/2 = 50: unchanged
    assert np.allclose(v[2], [2 * 20.0, 0.0])  # coincident: moved 2 Delta along the fixed +x
    # per-agent radii add: Delta = 4 + 16
    assert np.allclose(virtual_positions(p_i, others[:1], 4.0, 16.0)[0], [20.0, 0.0])


@settings(max_examples=25, deadline=None)
@given(
    st.floats(100.0, 500.0),
    st.floats(100.0, 500.0),
    st.floats(0.0, 2 * math.pi),
    st.floats(20.0, 39.0),
)
def test_band_cell_equals_the_voronoi_cell_against_the_virtual_position(x, y, angle, d):
    """Where Eq. 7 is sensible (Delta <= d < 2 Delta, Delta = 20 m), own_cell's half-plane form
    must be exactly the plain Voronoi cell of p_i against the printed virtual position p~_j."""
    p_i = np.array([x, y])
    p_j = p_i + d * np.array([math.cos(angle), math.sin(angle)])
    pv = virtual_positions(p_i, p_j[None], 10.0, np.array([10.0]))
    lab = voronoi_labels(GRID.points, np.vstack([p_i, pv]))
    band = own_cell(GRID.points, p_i, p_j[None], 10.0)
    dist_i = np.hypot(*(GRID.points - p_i).T)
    dist_v = np.hypot(*(GRID.points - pv[0]).T)
    clear = np.abs(dist_i - dist_v) > 1e-6  # points on the bisector: ties, either side is right
    assert np.array_equal(band[clear], lab[clear] == 0)


def test_voronoi_ties_go_to_the_lowest_index_and_no_positions_is_an_error():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    assert list(voronoi_labels(pts, np.array([[1.0, 1.0], [1.0, -1.0]]))) == [0, 0, 0]
    assert list(voronoi_labels(pts, np.array([[-1.0, 0.0], [3.0, 0.0]]))) == [0, 0, 1]
    with pytest.raises(ValueError, match="need at least one position"):
        voronoi_labels(pts, np.zeros((0, 2)))
    assert np.all(own_cell(pts, np.zeros(2), np.zeros((0, 2))))  # alone: the whole area
    # Eq. 6's "<=": a point on the bisector belongs to both cells (each agent's own view)
    p_i, p_j = np.array([0.0, 0.0]), np.array([2.0, 0.0])
    assert list(own_cell(pts, p_i, p_j[None])) == [True, True, False]
    assert list(own_cell(pts, p_j, p_i[None])) == [False, True, True]


def test_lloyd_iteration_converges_to_the_centroidal_voronoi_configuration():
    """Lloyd on a uniform density over a 1200 m x 300 m strip with two agents: the centroidal
    Voronoi tessellation is the two halves, generators at their centres (300, 150), (900, 150)."""
    grid = make_grid(0, 1200, 0, 300, 10.0)
    dens = np.ones(len(grid.points))
    pos = np.array([[100.0, 40.0], [200.0, 260.0]])
    for _ in range(60):
        new = []
        for i in range(2):
            mask = own_cell(grid.points, pos[i], np.delete(pos, i, axis=0))
            m, c = mass_centroid(grid.points, dens, mask, grid.cell_area_m2)
            assert c is not None and m > 0
            new.append(c)
        pos = np.array(new)
    pos = pos[np.argsort(pos[:, 0])]
    assert np.allclose(pos, [[300.0, 150.0], [900.0, 150.0]], atol=1.0)


def test_centroid_of_a_known_density_in_a_half_plane_cell():
    """Uniform density on the cell x <= 300 of the 600 m square: centroid (150, 300), mass the
    area 300 m x 600 m; a linear density rho = x on the whole square: centroid x = 2/3 * 600."""
    mask = GRID.points[:, 0] <= 300.0
    m, c = mass_centroid(GRID.points, np.ones(len(mask)), mask, GRID.cell_area_m2)
    assert np.allclose(c, [150.0, 300.0]) and math.isclose(m, 300.0 * 600.0)
    m, c = mass_centroid(GRID.points, GRID.points[:, 0].copy(), np.ones(len(mask), bool), 25.0)
    assert math.isclose(c[0], 400.0, rel_tol=1e-3) and math.isclose(c[1], 300.0)
    assert mass_centroid(GRID.points, np.zeros(len(mask)), mask, 25.0) == (0.0, None)  # no mass


def test_grid_cells_tile_the_area_and_bad_areas_are_errors():
    g = make_grid(-100.0, 50.0, 10.0, 40.0, 10.0)
    assert g.shape == (3, 15) and g.points.shape == (45, 2) and g.cell_area_m2 == 100.0
    assert g.xs[0] == -95.0 and g.xs[-1] == 45.0 and g.ys[0] == 15.0 and g.ys[-1] == 35.0
    assert np.array_equal(g.points[1], [-85.0, 15.0])  # row-major (y, x): x runs fastest
    assert make_grid(0.0, 25.0, 0.0, 10.0, 10.0).shape == (1, 3)  # a partial cell still counts
    assert make_grid(0.0, 1.0, 0.0, 1.0, 10.0).shape == (1, 1)
    with pytest.raises(ValueError, match="grid resolution must be > 0"):
        make_grid(0, 10, 0, 10, 0.0)
    with pytest.raises(ValueError, match="empty area"):
        make_grid(0, 10, 5, 5, 1.0)
    with pytest.raises(ValueError, match="empty area"):
        make_grid(10, 0, 0, 5, 1.0)


def test_gaussian_density_is_the_sum_of_unit_peak_gaussians():
    """Eqs. 13-15: peak 1 at each centre, exp(-1/2) at one sigma along x or y, exp(-1) at
    sqrt(2) sigma on the diagonal; masses 2 pi sigma^2 add; a sigma <= 0 contributes nothing."""
    g = make_grid(0, 1000, 0, 1000, 10.0)
    d = gaussian_density(g, [(205.0, 305.0), (705.0, 605.0)], [40.0, 20.0]).reshape(g.shape)
    at = lambda x, y: d[np.searchsorted(g.ys, y), np.searchsorted(g.xs, x)]  # noqa: E731
    assert math.isclose(at(205.0, 305.0), 1.0, rel_tol=1e-9)
    assert math.isclose(at(245.0, 305.0), math.exp(-0.5), rel_tol=1e-9)
    assert math.isclose(at(205.0, 265.0), math.exp(-0.5), rel_tol=1e-9)
    assert math.isclose(at(725.0, 625.0), math.exp(-1.0), rel_tol=1e-9)
    assert math.isclose(d.sum() * 100.0, 2 * math.pi * (40.0**2 + 20.0**2), rel_tol=1e-3)
    d0 = gaussian_density(g, [(205.0, 305.0), (705.0, 605.0)], [40.0, 0.0])
    assert math.isclose(d0.sum() * 100.0, 2 * math.pi * 40.0**2, rel_tol=1e-3)


def test_gaussian_density_is_the_accumulated_sum_bit_for_bit():
    """The density is the same bits as summing every term into a grid of zeros in order (the
    missions' Eq. 8 masses and Eq. 9 centroids depend on them): one centre, several (a sigma <= 0
    skipped, first or later), none; and the zero grid when no sigma is positive."""
    g = make_grid(-50, 930, 10, 770, 5.0)
    rng = np.random.default_rng(7)
    cases = [
        ([(205.3, 305.1)], [40.0]),
        ([(205.3, 305.1), (705.0, 605.9), (-80.0, 900.0)], [40.0, 3.7, 120.0]),
        ([(1.0, 2.0), (300.0, 300.0), (500.5, 20.0)], [0.0, 12.5, 60.0]),
        ([(300.0, 300.0), (500.5, 20.0)], [12.5, -1.0]),
        (list(map(tuple, rng.uniform(0, 900, (9, 2)))), list(rng.uniform(0.5, 200, 9))),
        ([(1.0, 2.0)], [0.0]),
        ([], []),
    ]
    for centres, sigmas in cases:
        ref = np.zeros(g.shape)
        for (cx, cy), s in zip(centres, sigmas, strict=True):
            if s > 0:
                ref += np.outer(
                    np.exp(-((g.ys - cy) ** 2) / (2 * s * s)), np.exp(-((g.xs - cx) ** 2) / (2 * s * s))
                )
        got = gaussian_density(g, centres, sigmas)
        assert got.shape == (g.points.shape[0],)
        assert got.tobytes() == ref.ravel().tobytes()


def test_vehicle_limits_of_a_scenario_vehicle():
    lim = VehicleLimits.of(Vehicle(v_stall_mps=30.0, v_max_mps=80.0, vz_max_mps=7.0, omega_max_radps=0.5))
    assert lim == VehicleLimits(30.0, 80.0, 7.0, 0.5)


def test_speed_cap_and_terrain_following_rate():
    """A far target: v = min(cap, v_max) but never below stall. At the commanded height over a
    plane of slope 0.1 the climb command is the terrain's own rate dE/dt = v grad E . heading
    (up, across, down the slope), so the height does not lag."""
    lim, g = VehicleLimits(), ControlGains()
    s = np.array([0.0, 0.0, 30.0, 0.0])
    far = np.array([1000.0, 0.0])
    assert control_law(s, far, 30.0, Terrain(), lim, g, v_cap_mps=60.0)[0] == 60.0
    assert control_law(s, far, 30.0, Terrain(), lim, g, v_cap_mps=10.0)[0] == lim.v_stall_mps
    assert control_law(s, far, 30.0, Terrain(), lim, g, v_cap_mps=500.0)[0] == lim.v_max_mps
    slope = Terrain(slope_x=0.1)
    for th, rate in ((0.0, 0.1), (math.pi / 2, 0.0), (math.pi, -0.1)):
        tgt = 1000.0 * np.array([math.cos(th), math.sin(th)])
        v, vz, om = control_law(np.array([0.0, 0.0, 30.0, th]), tgt, 30.0, slope, lim, g, v_cap_mps=60.0)
        assert v == 60.0 and math.isclose(vz, 60.0 * rate, abs_tol=1e-9) and abs(om) < 1e-9
    # 2 m below the commanded height: the gains' docstring chooses "half dead-beat" at the 0.1 s
    # control period, so one step's climb (v_z T) closes half the error: v_z = 10 m/s
    _, vz, _ = control_law(np.array([0.0, 0.0, 28.0, 0.0]), far, 30.0, Terrain(), lim, g)
    assert math.isclose(vz * 0.1, 1.0)
    _, vz, _ = control_law(np.array([0.0, 0.0, 90.0, 0.0]), far, 30.0, Terrain(), lim, g)
    assert vz == -20.0  # the documented 20 m/s cap on the commanded climb / sink rate
    # FF Eq. 10's K_p = 50 1/s: 1 m from the centroid the speed is 50 m/s (between stall and max)
    assert control_law(s, np.array([0.0, 1.0]), 30.0, Terrain(), lim, g)[0] == pytest.approx(50.0)
    low = VehicleLimits(vz_max_mps=3.0)
    _, vz, _ = control_law(np.array([0.0, 0.0, 0.0, 0.0]), far, 30.0, Terrain(), low, g)
    assert vz == 3.0
    # on the target itself: no turn
    assert control_law(s, np.array([0.0, 0.0]), 30.0, Terrain(), lim, g)[2] == 0.0
    # heading -3.0 rad, target at bearing pi - 0.01: 8.7 deg to the right across the +-pi cut;
    # wrapped (Eq. 11) that is a gentle right turn K_a * -0.15, not a 351 deg left turn
    _, _, om = control_law(np.array([0, 0, 30.0, -3.0]), np.array([-100.0, 1.0]), 30.0, Terrain(), lim, g)
    assert -1.0 < om < -0.5


def _cell_cases(seed: int):
    """Fleets on three grids: random, clustered, coincident, and grid-aligned (exact ties and
    axis-parallel bisectors), with 0 to 24 others."""
    from fire_uav_agent.coverage import make_grid

    rs = np.random.default_rng(seed)
    for res, side in ((5.0, 600.0), (7.3, 1000.0), (10.0, 600.0)):
        g = make_grid(0.0, side, 0.0, side, res)
        for t in range(150):
            n = int(rs.integers(0, 25))
            others = rs.uniform(-50, side + 50, (n, 2))
            p = rs.uniform(0, side, 2)
            if t % 5 == 0 and n > 2:
                others[:3] = p + rs.normal(0, 15, (3, 2))  # inside the safety band
            if t % 7 == 0 and n > 0:
                others[0] = p  # coincident
            if t % 3 == 0:
                p = g.points[rs.integers(len(g.points))].copy()
                if n > 0:
                    others = g.points[rs.integers(len(g.points), size=n)].copy()
                if n > 1:
                    others[1] = p + (2 * res, 0.0)  # bisector through a grid column
            yield g, p, others


@pytest.mark.parametrize("band", [None, 0.0, 20.0])
def test_own_cell_on_grid_is_own_cell_point_for_point(band):
    """The row-interval form decides every grid point as the half-plane form does (Eqs. 6-7)."""
    from fire_uav_agent.coverage import own_cell, own_cell_on_grid

    cases = 0
    for g, p, others in _cell_cases(5):
        want = own_cell(g.points, p, others, band)
        got = own_cell_on_grid(g, p, others, band)
        assert got.dtype == bool and got.shape == want.shape
        assert np.array_equal(got, want), (p, others, band, np.flatnonzero(got != want)[:5])
        cases += 1
    assert cases == 450


@pytest.mark.parametrize("gap", [-5e-7, -2e-9, 2e-9, 5e-7, 3e-6])
@pytest.mark.parametrize("band", [None, 20.0])
def test_points_a_hair_from_the_bisector_are_decided_exactly(gap, band):
    """A grid column ``gap`` m inside (> 0) or outside (< 0) the bound of one half-plane, in
    x, in y and on a diagonal: inside the 1e-6 m margin only own_cell's expression decides."""
    from fire_uav_agent.coverage import make_grid, own_cell, own_cell_on_grid

    g = make_grid(0.0, 100.0, 0.0, 100.0, 5.0)  # centres at 2.5, 7.5, ...
    p = np.array([22.5, 47.5])
    edge = 42.5 + gap - 1e-9  # own_cell keeps a point up to 1e-9 m past the bound
    shift = 2 * (edge - p[0]) if band is None else edge - p[0] + 2 * band
    for u in (np.array([1.0, 0.0]), np.array([0.0, 1.0]), np.array([-0.6, 0.8])):
        q = p + shift * u
        others = np.vstack([q, [[95.0, 95.0], [5.0, 95.0]]])
        want = own_cell(g.points, p, others, band)
        assert np.array_equal(own_cell_on_grid(g, p, others, band), want), (u, gap)
    assert want.any() and not want.all()


@pytest.mark.parametrize("on_grid", [False, True])
def test_half_planes_in_closed_form_coincident_close_and_banded(on_grid):
    """One other UAV: the cell is the half-plane behind a line whose place Eqs. 6-7 fix.

    Coincident (d = 0): the fixed direction +x, so x <= p_x (ties to i) or, with the band,
    x <= p_x - 2 delta. At d = 0.5 m along +y: the bisector y <= p_y + 0.25, and with a 20 m
    band y <= p_y + 0.5 - 40. At d = 100 m > 2 Delta with a 20 m band (Delta = 40 < d/2): the
    plain bisector y <= p_y + 50. At d = 60 m (Delta > d/2): y <= p_y + 60 - 40. With a band of
    0.6 m, between 0 and 1: y <= p_y + 0.5 - 1.2 at d = 0.5.
    """
    from fire_uav_agent.coverage import make_grid, own_cell, own_cell_on_grid

    g = make_grid(0.0, 200.0, 0.0, 200.0, 1.0)
    p = np.array([100.3, 100.3])  # off the grid's half-metres: no point on any line below
    rx, ry = g.points[:, 0] - p[0], g.points[:, 1] - p[1]
    cases = [
        ((0.0, 0.0), None, rx <= 0.0),
        ((0.0, 0.0), 20.0, rx <= -40.0),
        ((0.0, 0.5), None, ry <= 0.25),
        ((0.0, 0.5), 20.0, ry <= 0.5 - 40.0),
        ((0.0, 100.0), 20.0, ry <= 50.0),
        ((0.0, 60.0), 20.0, ry <= 20.0),
        ((0.0, 0.5), 0.6, ry <= 0.5 - 1.2),
    ]
    for (dx, dy), band, want in cases:
        other = p + (dx, dy)
        got = own_cell_on_grid(g, p, other[None, :], band) if on_grid else own_cell(g.points, p, other, band)
        assert np.array_equal(got, want), ((dx, dy), band, int((got != want).sum()))


def test_points_near_two_bounds_with_opposite_answers_are_each_decided():
    """Two half-planes pass within 1e-6 m of grid columns, one just keeping its column and one
    just cutting its own: each near point gets its own answer."""
    from fire_uav_agent.coverage import make_grid, own_cell, own_cell_on_grid

    g = make_grid(0.0, 100.0, 0.0, 100.0, 5.0)
    p = np.array([47.5, 47.5])
    keep = 2 * (72.5 + 5e-7 - p[0])  # bisector 5e-7 m beyond column x = 72.5: kept
    cut = 2 * (p[0] - (22.5 + 5e-7))  # bisector 5e-7 m inside column x = 22.5: cut
    others = np.array([[p[0] + keep, p[1]], [p[0] - cut, p[1]]])
    want = own_cell(g.points, p, others)
    xs = g.points[:, 0]
    assert want[np.isclose(xs, 72.5)].all() and not want[np.isclose(xs, 22.5)].any()
    assert np.array_equal(own_cell_on_grid(g, p, others), want)


@pytest.mark.parametrize("band", [None, 20.0])
def test_own_cell_on_grid_on_a_grid_wider_than_2_16_columns_and_with_a_nan_peer(band):
    """A 70,000-column grid (the row ranges' wide integer type) and a peer at NaN (the bounds are
    NaN: the comparisons over the whole grid decide): the same mask as :func:`own_cell`."""
    from fire_uav_agent.coverage import make_grid, own_cell, own_cell_on_grid

    wide = make_grid(0.0, 70_000.0, 0.0, 3.0, 1.0)
    assert wide.shape == (3, 70_000)
    p = np.array([35_000.2, 1.5])
    for others in (np.array([[35_100.0, 1.0], [1_000.0, 2.0]]), np.array([[35_000.2, 1.5]])):
        want = own_cell(wide.points, p, others, band)
        assert want.any() and not want.all()
        assert np.array_equal(own_cell_on_grid(wide, p, others, band), want)
    g = make_grid(0.0, 300.0, 0.0, 300.0, 5.0)
    others = np.array([[np.nan, 100.0], [200.0, 150.0]])
    p = np.array([120.0, 140.0])
    assert np.array_equal(own_cell_on_grid(g, p, others, band), own_cell(g.points, p, others, band))


# --- session 21's mutation survivors -----------------------------------------------------------
def test_an_area_of_zero_width_or_height_is_refused():
    from fire_uav_agent.errors import ConfigError

    for args in ((5.0, 5.0, 0.0, 10.0), (0.0, 10.0, 5.0, 5.0)):
        with pytest.raises(ConfigError, match="empty area"):
            make_grid(*args, 1.0)


def test_density_of_a_narrow_gaussian_is_the_two_dimensional_formula():
    """sigma under 1 m (e.g. 0.5 m) is a valid spread: the brute-force exp(-|q - c|^2 / 2 s^2) of
    Eqs. 13-15 over the grid's points, both terms summed."""
    g = make_grid(0.0, 4.0, 0.0, 3.0, 0.5)
    centres, sigmas = np.array([[1.2, 1.1], [3.0, 2.0]]), np.array([0.5, 0.9])
    want = sum(
        np.exp(-((g.points - c) ** 2).sum(axis=1) / (2 * s * s)) for c, s in zip(centres, sigmas, strict=True)
    )
    np.testing.assert_allclose(gaussian_density(g, centres, sigmas), want, rtol=1e-12, atol=0)


def test_a_small_positive_mass_has_its_centroid():
    """Eqs. 8-9 for a cell of little mass (density 1e-3): M = sum w * area, C = sum w q / sum w."""
    pts = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 4.0], [9.0, 9.0]])
    w = np.array([1e-3, 1e-3, 2e-3, 5.0])
    mask = np.array([True, True, True, False])
    m, c = mass_centroid(pts, w, mask, 4.0)
    assert m == pytest.approx(4e-3 * 4.0)
    np.testing.assert_allclose(c, [0.5, 2.0])


def test_density_at_masked_points_is_the_full_grids_bit_for_bit():
    """gaussian_density_at / density_centroid (the density computed in the own cell only) against
    gaussian_density on the whole grid then masked, and mass_centroid of it: the same bytes, on
    non-square grids, 1-3 centres inside and outside the area, zero / negative / NaN sigmas,
    and empty, full, random and Voronoi-cell masks."""
    import numpy as np
    from fire_uav_agent.coverage import (
        density_centroid,
        gaussian_density,
        gaussian_density_at,
        make_grid,
        mass_centroid,
        own_cell_on_grid,
    )

    rng = np.random.default_rng(20261207)
    for trial in range(300):
        grid = make_grid(
            0.0,
            float(rng.integers(20, 400)),
            -50.0,
            float(rng.integers(20, 300)),
            rng.choice([2.5, 5.0, 7.0]),
        )
        k = int(rng.integers(1, 4))
        centres = rng.uniform(-100.0, 450.0, size=(k, 2))
        sigmas = (
            rng.choice([0.0, -1.0, np.nan, 3.0, 20.0, 80.0], size=k)
            if trial % 5 == 0
            else rng.uniform(1.0, 90.0, k)
        )
        kind = trial % 4
        if kind == 0:
            mask = rng.random(grid.points.shape[0]) < 0.3
        elif kind == 1:
            mask = (
                np.ones(grid.points.shape[0], bool)
                if trial % 8 == 1
                else np.zeros(grid.points.shape[0], bool)
            )
        else:
            pts = rng.uniform(0.0, 300.0, size=(int(rng.integers(2, 7)), 2))
            mask = own_cell_on_grid(grid, pts[0], pts[1:], 10.0 if kind == 3 else None)
        full = gaussian_density(grid, centres, sigmas)
        idx = np.flatnonzero(mask)
        at = gaussian_density_at(grid, centres, sigmas, idx)
        assert at.tobytes() == full[mask].tobytes(), trial
        assert float(at.sum()).hex() == float(full[mask].sum()).hex()
        m_new, c_new = density_centroid(grid, centres, sigmas, mask)
        m_old, c_old = mass_centroid(grid.points, full, mask, grid.cell_area_m2)
        assert m_new.hex() == m_old.hex(), trial
        assert (c_new is None and c_old is None) or c_new.tobytes() == c_old.tobytes(), trial


def test_density_at_points_is_numpys_sum_of_the_gaussians_there():
    """gaussian_density_at against Eqs. 13-15 written out in numpy over the whole grid, then indexed:
    sum over the fires with sigma > 0 of exp(-|q - c|^2 / (2 sigma^2)). A sigma-0 fire centred on a
    grid point adds nothing (not a 0 / 0 there), a narrow one (sigma 0.5 m, less than a cell) its
    1.0 at its centre; an empty list of indices gives no values, as numpy's indexing does."""
    from fire_uav_agent.coverage import gaussian_density_at, make_grid

    grid = make_grid(0.0, 100.0, 0.0, 60.0, 2.5)
    centres = np.array([[51.25, 31.25], [26.25, 11.25], [70.0, 40.0]])  # the first two on grid points
    sigmas = np.array([0.0, 0.5, 20.0])
    d2 = ((grid.points[:, None, :] - centres[None, :, :]) ** 2).sum(axis=2)
    keep = sigmas > 0
    truth = np.exp(-d2[:, keep] / (2.0 * sigmas[keep] ** 2)).sum(axis=1)
    rng = np.random.default_rng(7)
    for idx in (np.arange(truth.size), rng.choice(truth.size, 200, replace=False)):
        np.testing.assert_allclose(
            gaussian_density_at(grid, centres, sigmas, idx), truth[idx], rtol=1e-12, atol=0
        )
    on_narrow = 4 * grid.xs.size + 10  # (26.25, 11.25): row 4, column 10
    wide = math.exp(-((26.25 - 70.0) ** 2 + (11.25 - 40.0) ** 2) / (2.0 * 20.0**2))
    assert gaussian_density_at(grid, centres, sigmas, [on_narrow])[0] == pytest.approx(1.0 + wide, rel=1e-12)
    assert gaussian_density_at(grid, centres, sigmas, []).shape == (0,)
