"""Terrain.elevation: the scalar shortcut on a plane gives the array form's numbers bit for bit
(the EKF, the control law and the world ask for single points every step; a last-bit change
there moves missions)."""

import numpy as np
from fire_uav_common.terrain import Hill, Terrain


def test_a_point_on_a_plane_is_the_array_forms_number_bit_for_bit():
    rng = np.random.default_rng(3)
    for _ in range(300):
        t = Terrain(
            base_m=float(rng.uniform(-500, 2000)),
            slope_x=float(rng.normal(0, 0.3)),
            slope_y=float(rng.normal(0, 0.3)),
        )
        for x, y in rng.uniform(-5000, 5000, (20, 2)):
            fast = t.elevation(float(x), float(y))  # the scalar shortcut
            ref = t.elevation(np.array([x]), np.array([y]))[0]  # the array form
            assert isinstance(fast, float)
            assert np.float64(fast).tobytes() == np.float64(ref).tobytes(), (t, x, y)
            assert t.elevation(np.float64(x), np.float64(y)) == fast


def test_hills_and_arrays_keep_the_array_form():
    t = Terrain(base_m=10.0, slope_x=0.01, hills=(Hill(x_m=0.0, y_m=0.0, height_m=50.0, sigma_m=100.0),))
    assert t.elevation(0.0, 0.0) == 60.0
    e = t.elevation(np.array([0.0, 100.0]), np.array([0.0, 0.0]))
    assert e.shape == (2,) and e[0] == 60.0 and 10.0 + 1.0 < e[1] < 60.0
