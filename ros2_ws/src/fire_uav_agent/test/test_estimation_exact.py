"""EKF (FF III-B) on cases with a closed-form answer: each stage of the filter against the exact
Kalman/Bayes result of a linear-Gaussian model, and the sample timing of ``process``.

Fast (well under a second); the mutation run of ``estimation`` uses this file. The long NEES run
(tests in test_estimation.py) checks the whole filter's consistency on the nonlinear model.
"""

import math

import numpy as np
import pytest
from fire_uav_agent.estimation import EkfConfig, Samples, StateEkf, wrap_angle
from fire_uav_common.terrain import Hill, Terrain

DT = 0.01


def ekf(sigma_nu=(0.0, 0.0, 0.0), initial=(0.0, 0.0, 0.0, 0.0), s0=(0.0, 0.0, 30.0, 0.0), **kw) -> StateEkf:
    return StateEkf(EkfConfig(sigma_nu=sigma_nu, initial_sigma=initial, **kw), np.array(s0, dtype=float))


def test_input_noise_spreads_along_the_heading_and_in_height():
    """Eq. 17 with only v_lin / v_z noise (no yaw uncertainty): after n substeps the position
    covariance is n (sigma_v dt)^2 u u^T along the heading u, the height's n (sigma_vz dt)^2, and
    the mean moves n dt (v cos, v sin, v_z) (Eq. 16)."""
    th, n = 0.7, 50
    f = ekf(sigma_nu=(2.0, 3.0, 0.0), s0=(10.0, -5.0, 30.0, th))
    for _ in range(n):
        f.predict(np.array([40.0, 1.5, 0.0]), DT)
    u = np.array([math.cos(th), math.sin(th)])
    assert np.allclose(
        f.s, [10.0 + n * DT * 40.0 * u[0], -5.0 + n * DT * 40.0 * u[1], 30.0 + n * DT * 1.5, th]
    )
    assert np.allclose(f.P[:2, :2], n * (2.0 * DT) ** 2 * np.outer(u, u), rtol=1e-12, atol=1e-15)
    assert math.isclose(f.P[2, 2], n * (3.0 * DT) ** 2, rel_tol=1e-12)
    assert np.allclose(f.P[3], 0.0) and np.allclose(f.P[:2, 2], 0.0)


def test_heading_uncertainty_maps_to_cross_track_position_error():
    """Eq. 17's A with an uncertain, constant heading (sigma_theta, no input noise): flying a
    distance L = v t, a heading error delta moves the vehicle by L (-sin, cos) delta to first
    order, so P_xy = sigma_theta^2 L^2 (-sin, cos)(-sin, cos)^T and P_x,theta = -L sin sigma^2."""
    th, sig, v, n = 0.4, 0.05, 60.0, 80
    f = ekf(initial=(0.0, 0.0, 0.0, sig), s0=(0.0, 0.0, 30.0, th))
    for _ in range(n):
        f.predict(np.array([v, 0.0, 0.0]), DT)
    length = v * n * DT
    w = length * np.array([-math.sin(th), math.cos(th)])
    assert np.allclose(f.P[:2, :2], sig**2 * np.outer(w, w), rtol=1e-9)
    assert np.allclose(f.P[:2, 3], sig**2 * w, rtol=1e-9)
    assert math.isclose(f.P[3, 3], sig**2, rel_tol=1e-12)


def test_yaw_rate_noise_is_a_random_walk_and_the_gyro_is_a_conjugate_update():
    """Without a gyro the yaw variance grows by (sigma_omega dt)^2 per substep. With a gyro sample m
    (variance sigma_g^2) of the substep's true rate, whose prior is N(omega_cmd, sigma_omega^2),
    the rate's posterior is the precision-weighted mean with variance 1/(1/sigma_omega^2 +
    1/sigma_g^2): the yaw moves by dt times that mean and its variance by dt^2 times that variance."""
    so, sg, n = 1.0, 0.3, 30
    f = ekf(sigma_nu=(0.0, 0.0, so), sigma_gyro_radps=sg)
    for _ in range(n):
        f.predict(np.array([0.0, 0.0, 0.2]), DT)
    assert math.isclose(f.P[3, 3], n * (so * DT) ** 2, rel_tol=1e-12)
    assert math.isclose(f.s[3], n * DT * 0.2, rel_tol=1e-12)
    g = ekf(sigma_nu=(0.0, 0.0, so), sigma_gyro_radps=sg)
    m = 1.2
    post_var = 1.0 / (1.0 / so**2 + 1.0 / sg**2)
    post_mean = post_var * (0.2 / so**2 + m / sg**2)
    for _ in range(n):
        g.predict(np.array([0.0, 0.0, 0.2]), DT, gyro_radps=m)
    assert math.isclose(g.s[3], n * DT * post_mean, rel_tol=1e-12)
    assert math.isclose(g.P[3, 3], n * DT**2 * post_var, rel_tol=1e-12)
    assert g.updates["gyro"] == n
    h = ekf(sigma_nu=(0.0, 0.0, so), sigma_gyro_radps=sg)
    h.predict(np.array([0.0, 0.0, 0.2]), DT, gyro_radps=math.nan)  # a bad sample: ignored
    assert h.updates["gyro"] == 0 and math.isclose(h.P[3, 3], (so * DT) ** 2)


def test_yaw_stays_wrapped_through_prediction_and_start():
    f = ekf(s0=(0.0, 0.0, 30.0, 3.0 * math.pi))  # start wrapped to (-pi, pi]
    assert math.isclose(f.yaw_rad, math.pi)
    for _ in range(20):
        f.predict(np.array([0.0, 0.0, 5.0]), DT)  # +1 rad across the +-pi cut
    assert math.isclose(f.yaw_rad, wrap_angle(math.pi + 1.0)) and -math.pi < f.yaw_rad <= math.pi


def test_gps_updates_give_the_precision_weighted_mean():
    """A static vehicle (no motion, no noise), prior N(x0, s0^2) per axis, GPS fixes m_k with
    variances r_k: the exact posterior is var = 1/(1/s0^2 + sum 1/r_k), mean = var (x0/s0^2 +
    sum m_k/r_k); height and yaw are untouched. A variance <= 0 means the configured sigma_gps."""
    s0 = 4.0
    f = ekf(initial=(s0, s0, 1.0, 0.1), s0=(100.0, 200.0, 30.0, 0.5), sigma_gps_m=3.0)
    fixes = [(103.0, 195.0, 2.0), (99.0, 199.0, 5.0), (104.0, 202.0, 0.0), (98.0, 201.0, -1.0)]
    for x, y, r in fixes:
        f.update_gps(x, y, r)
    rs = [r if r > 0 else 9.0 for *_, r in fixes]
    var = 1.0 / (1.0 / s0**2 + sum(1.0 / r for r in rs))
    mx = var * (100.0 / s0**2 + sum(x / r for (x, _, _), r in zip(fixes, rs, strict=True)))
    my = var * (200.0 / s0**2 + sum(y / r for (_, y, _), r in zip(fixes, rs, strict=True)))
    assert np.allclose(f.s, [mx, my, 30.0, 0.5], rtol=1e-12)
    assert np.allclose(f.P, np.diag([var, var, 1.0, 0.01]), rtol=1e-12, atol=1e-15)
    assert f.updates == {"gps": 4, "alt": 0, "gyro": 0}
    # no variance given: the configured one
    g = ekf(initial=(s0, s0, 1.0, 0.1), s0=(0.0, 0.0, 30.0, 0.0), sigma_gps_m=3.0)
    g.update_gps(10.0, 0.0)
    assert math.isclose(g.s[0], 10.0 * s0**2 / (s0**2 + 9.0)) and math.isclose(g.s[1], 0.0)


def test_altimeter_on_a_plane_is_the_exact_linear_gaussian_posterior():
    """h(s) = z - E(x, y) with E = 5 + 0.2 x - 0.1 y is linear: the EKF update must equal the
    information-form posterior P+ = (P^-1 + H^T H / r)^-1, s+ = P+ (P^-1 s + H^T (m + 5) / r),
    H = [-0.2, 0.1, 1, 0]; on a slope it corrects the horizontal position too."""
    terrain = Terrain(base_m=5.0, slope_x=0.2, slope_y=-0.1)
    p0 = np.diag([9.0, 4.0, 2.25, 0.01])
    s0 = np.array([50.0, 40.0, 60.0, 0.3])
    f = StateEkf(EkfConfig(initial_sigma=tuple(np.sqrt(np.diag(p0))), sigma_alt_m=1.5), s0, terrain)
    m = 38.0  # measured height above ground; predicted 60 - (5 + 10 - 4) = 49
    f.update_altimeter(m)
    h = np.array([[-0.2, 0.1, 1.0, 0.0]])
    info = np.linalg.inv(p0) + h.T @ h / 2.25
    p_post = np.linalg.inv(info)
    s_post = p_post @ (np.linalg.inv(p0) @ s0 + h.T[:, 0] * (m + 5.0) / 2.25)
    assert np.allclose(f.P, p_post, rtol=1e-9, atol=1e-12)
    assert np.allclose(f.s, s_post, rtol=1e-9)
    assert f.s[0] > 50.0 and f.s[1] < 40.0 and f.updates["alt"] == 1


def test_covariance_stays_symmetric_and_positive_definite_over_a_turn():
    f = ekf(sigma_nu=(1.0, 1.0, 1.0), initial=(3.0, 3.0, 1.5, 0.05))
    for k in range(300):
        f.predict(np.array([60.0, 0.0, 0.4]), DT, gyro_radps=0.4 if k % 2 else None)
        if k % 10 == 9:
            f.update_gps(f.s[0] + 1.0, f.s[1] - 1.0, 9.0)
        if k % 4 == 3:
            f.update_altimeter(30.0)
    assert np.array_equal(f.P, f.P.T) and np.linalg.eigvalsh(f.P).min() > 0


# --- process(): when each sample is applied -------------------------------------------------
V = 100.0  # [m/s] along +x, no noise: x at the end of substep j is x0 + V j dt


def _pinned(t_gps: float, t0: float = 2.0, t1: float = 2.1) -> float:
    """x after ``process`` over [t0, t1] with one near-exact GPS fix x = 0 stamped t_gps."""
    f = ekf(initial=(50.0, 50.0, 1.0, 0.0))
    smp = Samples(np.array([[t_gps, 0.0, 0.0]]), np.array([1e-8]))
    f.process(smp, np.array([V, 0.0, 0.0]), t0, t1)
    return float(f.s[0])


def test_a_sample_is_applied_at_the_end_of_the_substep_that_contains_it():
    """Substep j covers (t0 + (j-1) dt, t0 + j dt]: a fix stamped in substep j pins x to 0 after
    j predictions, so the step ends at V (10 - j) dt. A stamp on a boundary belongs to the substep
    it ends; stamps outside [t0, t1] go to the first / last substep."""
    for t_gps, j in ((2.035, 4), (2.04, 4), (2.0401, 5), (2.001, 1), (2.1, 10), (1.5, 1), (2.5, 10)):
        assert math.isclose(_pinned(t_gps), V * (10 - j) * DT, abs_tol=1e-4), (t_gps, j)


def test_samples_are_fused_in_time_order_and_bad_ones_are_skipped():
    """Rows in any order are applied by time: the fix of substep 2 (x = 1, configured variance 9:
    no variance given for its row), then the exact one of substep 10 (x = 5), so x ends at 5;
    a NaN fix, and heights outside [0, alt_max_range_m], are skipped."""
    f = ekf(initial=(50.0, 50.0, 50.0, 0.0), alt_max_range_m=40.0, sigma_alt_m=1e-4)
    gps = np.array([[0.095, 5.0, 0.0], [0.015, 1.0, 0.0], [0.05, np.nan, 0.0]])
    alt = np.array([[0.06, 0.0], [0.02, 41.0], [0.03, -0.5], [0.04, 40.0], [0.07, np.nan]])
    f.process(Samples(gps, np.array([1e-8]), alt), np.zeros(3), 0.0, 0.1)
    assert f.updates == {"gps": 2, "alt": 2, "gyro": 0}
    assert abs(f.s[0] - 5.0) < 1e-3 and abs(f.s[1]) < 1e-3
    assert abs(f.s[2] - 20.0) < 1e-3  # two equally exact readings, 40 m and 0 m: their mean
    assert math.isclose(f.P[0, 0], 1.0 / (1.0 / 2500.0 + 1.0 / 9.0 + 1e8), rel_tol=1e-6)


def test_gyro_samples_are_used_in_their_substep_and_a_short_window_is_one_substep():
    so, sg = 1.0, 0.3
    f = ekf(sigma_nu=(0.0, 0.0, so), sigma_gyro_radps=sg)
    gyro = np.array([[0.005, 1.0], [0.045, 1.0], [0.046, np.nan]])
    f.process(Samples(gyro=gyro), np.zeros(3), 0.0, 0.1)
    k = so**2 / (so**2 + sg**2)
    assert f.updates["gyro"] == 2  # the NaN sample leaves its substep without a gyro
    assert math.isclose(f.s[3], 2 * DT * k * 1.0, rel_tol=1e-12)
    assert math.isclose(f.P[3, 3], DT**2 * (8 * so**2 + 2 * (1 - k) * so**2), rel_tol=1e-12)
    g = ekf(sigma_nu=(0.0, 0.0, so))
    g.process(Samples(), np.array([0.0, 0.0, 1.0]), 0.0, 0.004)
    assert math.isclose(g.s[3], DT * 1.0)  # under one substep long: still one prediction


def test_no_prediction_on_the_ground_but_fixes_still_fused():
    f = ekf(sigma_nu=(1.0, 1.0, 1.0), initial=(3.0, 3.0, 1.0, 0.1), s0=(10.0, 20.0, 0.0, 0.0))
    p_before = f.P.copy()
    f.process(
        Samples(np.array([[0.05, 13.0, 20.0]]), np.array([9.0])), np.array([50.0, 1.0, 1.0]), 0.0, 0.1, False
    )
    assert math.isclose(f.s[0], 10.0 + 3.0 * 9.0 / 18.0) and f.s[1] == 20.0 and f.s[3] == 0.0
    assert f.P[3, 3] == p_before[3, 3] and f.P[2, 2] == p_before[2, 2]


def test_bad_configuration_and_start_state_are_errors():
    with pytest.raises(ValueError, match="dt_s must be > 0"):
        EkfConfig(dt_s=0.0)
    for name in ("sigma_gps_m", "sigma_alt_m", "sigma_gyro_radps"):
        with pytest.raises(ValueError, match=f"{name} must be > 0"):
            EkfConfig(**{name: 0.0})
    with pytest.raises(ValueError, match="s0 must be 4 finite numbers"):
        StateEkf(EkfConfig(), np.zeros(3))
    with pytest.raises(ValueError, match="s0 must be 4 finite numbers"):
        StateEkf(EkfConfig(), np.array([0.0, math.inf, 0.0, 0.0]))


def test_the_default_filter_is_the_papers_sensor_model():
    """EkfConfig() is FF II-C / III-B: GPS sigma 3 m, ultrasonic altimeter sigma 1.5 m over
    0..40 m, gyro sigma 0.3 rad/s, input noise sigma 1 (all three), 0.01 s physics substeps; and
    the start pose is as uncertain as one GPS fix / one altimeter sample. Consequences: the first
    GPS fix and the first altimeter sample each halve their variance; a 40 m height is fused, a
    40.5 m one is not; a gyro sample moves the rate 1/1.09 of the way; a 0.1 s step is 10
    substeps of 0.01 s."""
    f = StateEkf(EkfConfig(), np.array([0.0, 0.0, 30.0, 0.0]))
    f.update_gps(1.0, 1.0)
    assert math.isclose(f.P[0, 0], 4.5) and math.isclose(f.P[1, 1], 4.5)
    f.update_altimeter(30.0)
    assert math.isclose(f.P[2, 2], 2.25 / 2)
    g = StateEkf(EkfConfig(), np.array([0.0, 0.0, 30.0, 0.0]))
    g.process(Samples(alt=np.array([[0.05, 40.0], [0.06, 40.5]])), np.zeros(3), 0.0, 0.1, moving=False)
    assert g.updates["alt"] == 1
    h = StateEkf(EkfConfig(), np.array([0.0, 0.0, 30.0, 0.0]))
    p33 = h.P[3, 3]
    h.predict(np.zeros(3), 0.01, gyro_radps=1.09)
    assert math.isclose(h.s[3], 0.01 * 1.0) and math.isclose(h.P[3, 3] - p33, 1e-4 * 0.09 / 1.09)
    k = StateEkf(EkfConfig(), np.array([0.0, 0.0, 30.0, 0.0]))
    p0 = k.P.copy()
    k.process(Samples(), np.array([0.0, 0.0, 1.0]), 0.0, 0.1)
    assert math.isclose(k.s[3], 0.1) and math.isclose(k.P[3, 3] - p0[3, 3], 10 * 1e-4)


def _predict_matrix_form(f: StateEkf, u: np.ndarray, dt: float, gyro: float | None) -> None:
    """Eqs. 16-17 as numpy matrices, the filter's form before ``predict`` was cut (the reference)."""
    v, vz, om = float(u[0]), float(u[1]), float(u[2])
    q = np.square(np.asarray(f.cfg.sigma_nu, dtype=float))
    q_om = q[2]
    if gyro is not None and math.isfinite(gyro):
        k = q[2] / (q[2] + f.cfg.sigma_gyro_radps**2)
        om = om + k * (gyro - om)
        q_om = (1.0 - k) * q_om
    th = f.s[3]
    c, s = math.cos(th), math.sin(th)
    a = np.eye(4)
    a[0, 3] = -v * s * dt
    a[1, 3] = v * c * dt
    g = np.zeros((4, 3))
    g[0, 0] = c * dt
    g[1, 0] = s * dt
    g[2, 1] = dt
    g[3, 2] = dt
    f.s = f.s + np.array([v * c * dt, v * s * dt, vz * dt, om * dt])
    f.s[3] = wrap_angle(f.s[3])
    p = a @ f.P @ a.T + g @ np.diag([q[0], q[1], q_om]) @ g.T
    f.P = 0.5 * (p + p.T)


def test_predict_is_the_matrix_form_of_eqs_16_17_bit_for_bit():
    """``predict`` writes G Q G^T out and keeps A in one array; the state and covariance must be
    the matrix form's to the last bit (a 1e-15 difference once changed a 14-UAV mission), over
    turns, gyro samples (some NaN), every heading and covariances with cross terms."""
    rng = np.random.default_rng(7)
    for trial in range(40):
        s0 = (rng.uniform(-500, 500), rng.uniform(-500, 500), rng.uniform(0, 80), rng.uniform(-4, 4))
        cfg = dict(sigma_nu=tuple(rng.uniform(0.05, 3.0, 3)), sigma_gyro_radps=float(rng.uniform(0.05, 1.0)))
        f, ref = (
            ekf(initial=(3.0, 3.0, 1.5, 0.05), s0=s0, **cfg),
            ekf(initial=(3.0, 3.0, 1.5, 0.05), s0=s0, **cfg),
        )
        for step in range(60):
            u = np.array([rng.uniform(0, 100), rng.uniform(-5, 5), rng.uniform(-10, 10)])
            gyro = (
                None if step % 3 == 0 else (math.nan if step % 7 == 0 else float(u[2] + rng.normal(0, 0.3)))
            )
            dt = DT if trial % 2 else float(rng.uniform(0.001, 0.05))
            f.predict(u, dt, gyro)
            _predict_matrix_form(ref, u, dt, gyro)
            if step % 10 == 9:  # a GPS fix puts cross terms into P for the next predictions
                f.update_gps(float(ref.s[0]) + 1.0, float(ref.s[1]) - 2.0)
                ref.update_gps(float(ref.s[0]) + 1.0, float(ref.s[1]) - 2.0)
            assert f.s.tobytes() == ref.s.tobytes(), (trial, step, f.s - ref.s)
            assert f.P.tobytes() == ref.P.tobytes(), (trial, step, f.P - ref.P)


# --- edges named by the mutation run (docs/testing.md) ----------------------------------------------
def test_the_climb_is_the_commanded_vertical_speed_and_a_fix_pins_it_in_its_substep():
    """FF Eq. 16, z' = z + v_z dt, with v_z the command's second entry (not its turn rate): an exact
    altimeter fix of 30.5 m in substep 2 (t = 0.015 s), then 8 substeps at 2 m/s."""
    f = ekf(initial=(1.0, 1.0, 50.0, 0.0), sigma_alt_m=1e-4)
    f.process(Samples(alt=np.array([[0.015, 30.5]])), np.array([0.0, 2.0, 0.0]), 0.0, 0.1)
    assert math.isclose(f.s[2], 30.5 + 2.0 * 8 * DT, abs_tol=1e-6)
    g = ekf()
    g.process(Samples(), np.array([0.0, 2.0, 0.0]), 0.0, 0.1)
    assert math.isclose(g.s[2], 30.0 + 2.0 * 0.1, rel_tol=1e-12)


def test_a_fix_without_a_variance_takes_the_configured_one():
    """The row has no variance (an empty gps_var_m2): sigma_gps_m^2 = 9 m^2, the exact
    precision-weighted mean of the prior N(0, 50^2) and the fix 3 m."""
    f = ekf(initial=(50.0, 50.0, 1.0, 0.0), sigma_gps_m=3.0)
    f.process(Samples(np.array([[0.1, 3.0, 0.0]]), np.array([])), np.zeros(3), 0.0, 0.1)
    assert math.isclose(f.P[0, 0], 1.0 / (1.0 / 2500.0 + 1.0 / 9.0), rel_tol=1e-12)
    assert math.isclose(f.s[0], 3.0 * (1.0 / 9.0) / (1.0 / 2500.0 + 1.0 / 9.0), rel_tol=1e-12)


def test_integer_configuration_and_start_state_filter_as_their_float_values():
    """A start pose and sigmas written as integers (a YAML scenario may hold them so) give the
    filter the float one gives."""
    cfg_i = EkfConfig(sigma_nu=(1, 1, 1), initial_sigma=(2, 2, 1, 0))
    cfg_f = EkfConfig(sigma_nu=(1.0, 1.0, 1.0), initial_sigma=(2.0, 2.0, 1.0, 0.0))
    a, b = StateEkf(cfg_i, [0, 0, 30, 0]), StateEkf(cfg_f, np.array([0.0, 0.0, 30.0, 0.0]))
    smp = Samples(np.array([[0.05, 1.0, 2.0]]), np.array([4.0]), np.array([[0.07, 29.5]]))
    for f in (a, b):
        f.process(smp, np.array([10, 1, 0.5]), 0.0, 0.1)
    assert a.s.tolist() == b.s.tolist() and a.P.tolist() == b.P.tolist()


def test_the_altimeter_over_a_hill_is_linearised_at_the_estimate():
    """Over a Gaussian hill h(s) = z - E(x, y) is nonlinear: the EKF update (Eqs. 22-25) is the
    Kalman update of the model linearised at the prior mean, H = [-dE/dx, -dE/dy, 1, 0] with the
    hill's *analytic* gradient at the estimate (300, 40) (the hill is wide, so the terrain's
    central difference agrees to ~1e-6; at (40, 300) or (300, 300) the slope is another)."""
    hx, hy, a, sig = 120.0, -60.0, 80.0, 150.0
    terrain = Terrain(base_m=5.0, hills=(Hill(x_m=hx, y_m=hy, height_m=a, sigma_m=sig),))
    s0 = np.array([300.0, 40.0, 150.0, 0.3])
    p0 = np.diag([9.0, 4.0, 2.25, 0.01])
    f = StateEkf(EkfConfig(initial_sigma=tuple(np.sqrt(np.diag(p0))), sigma_alt_m=1.5), s0, terrain)
    m = 60.0
    f.update_altimeter(m)
    dx, dy = s0[0] - hx, s0[1] - hy
    g = a * math.exp(-(dx * dx + dy * dy) / (2.0 * sig * sig))
    e, de_dx, de_dy = 5.0 + g, -g * dx / sig**2, -g * dy / sig**2
    h = np.array([-de_dx, -de_dy, 1.0, 0.0])
    k = p0 @ h / (h @ p0 @ h + 2.25)
    s_post = s0 + k * (m - (s0[2] - e))
    p_post = (np.eye(4) - np.outer(k, h)) @ p0
    assert abs(de_dx) > 0.1 and abs(de_dy) > 0.03  # a slope the update must follow
    np.testing.assert_allclose(f.s, s_post, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(f.P, p_post, rtol=1e-5, atol=1e-8)


def test_a_fix_with_a_nan_stamp_goes_to_the_first_substep():
    """``process``: a non-finite stamp is taken as the window's first substep (its doc), so an exact
    fix x = 0 stamped NaN pins x after one prediction, and 9 more at V follow."""
    assert math.isclose(_pinned(math.nan), V * 9 * DT, abs_tol=1e-4)


def _reference_process(f: StateEkf, samples: Samples, u, t0: float, t1: float, moving: bool) -> None:
    """``process`` as it was written before it kept the state in floats between measurements: one
    ``predict`` (numpy state) per substep, then that substep's fixes in time order."""
    dt = f.cfg.dt_s
    n_sub = max(1, int(round((t1 - t0) / dt)))

    def sub(t):
        x = (t - t0 - 1e-6 * dt) / dt
        return min(max(math.ceil(x), 1), n_sub) if math.isfinite(x) else 1

    gyro = {sub(t): w for t, w in samples.gyro.tolist() if math.isfinite(w)}
    ev = sorted(
        [(sub(t), t, 0, r) for r, t in enumerate(samples.gps[:, 0].tolist())]
        + [(sub(t), t, 1, r) for r, t in enumerate(samples.alt[:, 0].tolist())]
    )
    for j in range(1, n_sub + 1):
        if moving:
            f.predict(np.asarray(u, dtype=float), dt, gyro.get(j))
        for _, _, kind, r in [e for e in ev if e[0] == j]:
            if kind == 0:
                f.update_gps(float(samples.gps[r, 1]), float(samples.gps[r, 2]), float(samples.gps_var_m2[r]))
            elif 0.0 <= samples.alt[r, 1] <= f.cfg.alt_max_range_m:
                f.update_altimeter(float(samples.alt[r, 1]))


@pytest.mark.parametrize("seed", range(8))
def test_process_is_substep_by_substep_predict_and_updates_bit_for_bit(seed):
    """``process`` runs the substeps between two fixes on the state as floats (no array per substep):
    state and covariance must be byte for byte those of one ``predict`` per substep and the fixes
    in their substeps, over random steps with GPS, altimeter and gyro samples at random instants."""
    rng = np.random.default_rng(seed)
    kw = dict(sigma_nu=(1.0, 0.5, 0.2), initial=(3.0, 3.0, 1.5, 0.05), s0=(5.0, -3.0, 20.0, 3.1))
    terrain = Terrain(base_m=2.0, slope_x=0.01, slope_y=-0.02)
    a, b = (StateEkf(EkfConfig(sigma_nu=kw["sigma_nu"], initial_sigma=kw["initial"]), np.array(kw["s0"]), terrain)
            for _ in range(2))  # fmt: skip
    t0 = 0.0
    for k in range(60):
        t1 = t0 + 0.1
        n_gps, n_alt, n_gyro = rng.integers(0, 3), rng.integers(0, 4), rng.integers(0, 11)
        gps_t = np.sort(rng.uniform(t0, t1, n_gps))
        samples = Samples(
            np.column_stack([gps_t, rng.normal(0, 50, n_gps), rng.normal(0, 50, n_gps)]).reshape(-1, 3),
            rng.uniform(1.0, 16.0, n_gps),
            np.column_stack([rng.uniform(t0, t1, n_alt), rng.uniform(-1.0, 45.0, n_alt)]).reshape(-1, 2),
            np.column_stack([t0 + 0.01 * np.arange(1, n_gyro + 1), rng.normal(0.1, 0.3, n_gyro)]).reshape(
                -1, 2
            ),
        )
        u = (rng.uniform(10, 25), rng.normal(0, 1), rng.normal(0, 0.3))
        moving = k % 13 != 5
        a.process(samples, np.array(u), t0, t1, moving=moving)
        _reference_process(b, samples, u, t0, t1, moving)
        assert a.s.tobytes() == b.s.tobytes(), k
        assert a.P.tobytes() == b.P.tobytes(), k
        t0 = t1
    assert a.updates == b.updates and a.updates["gps"] > 0 and a.updates["alt"] > 0


def test_the_update_solve_is_numpys_bit_for_bit_and_raises_as_numpy_does():
    from fire_uav_agent.estimation import _solve

    rng = np.random.default_rng(3)
    for n in (1, 2):
        for _ in range(200):
            m = rng.normal(size=(n, n))
            a = m @ m.T + rng.uniform(0.1, 5.0) * np.eye(n)
            b = rng.normal(size=(n, 4))
            assert _solve(a, b).tobytes() == np.linalg.solve(a, b).tobytes()
    with pytest.raises(np.linalg.LinAlgError):
        _solve(np.zeros((2, 2)), np.ones((2, 4)))
    # a non-finite S (a NaN reading upstream): numpy returns NaNs without raising, and so must _solve
    a_nan, b = np.array([[1.0, np.nan], [0.0, 1.0]]), np.ones((2, 4))
    with np.errstate(invalid="ignore"):
        assert _solve(a_nan, b).tobytes() == np.linalg.solve(a_nan, b).tobytes()
