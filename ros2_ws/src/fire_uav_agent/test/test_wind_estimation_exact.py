"""The wind EKF (fire_uav_agent.wind_estimation) on cases with a closed-form answer, and its pose
part against FF's filter.

Two truths. (1) With a calm, certain wind (prior sigma 1e-12 m/s, no random walk) the filter is
FF's (its module doc: "everything else ... is StateEkf's"): pose, pose covariance and the update
counts must be :class:`.estimation.StateEkf`'s, whose stages test_estimation_exact.py checks
against the exact Kalman / Bayes answers, over random steps with every sample kind and the
schedule's edges. (2) The wind's own part against the linear-Gaussian model of a vehicle drifting
in an unknown constant wind: the covariance propagation of the wind triangle, and one GPS fix's
exact posterior of the wind. Fast (~0.3 s): the mutation selection of ``wind_estimation`` runs it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from fire_uav_agent.estimation import EkfConfig, Samples, StateEkf
from fire_uav_agent.wind_estimation import WindEkfConfig, WindStateEkf
from fire_uav_common.terrain import Hill, Terrain

DT = 0.01
CALM = 1e-12  # [m/s] a wind prior so certain that the wind states change nothing measurable
HILL = Terrain(
    base_m=2.0, slope_x=0.03, slope_y=-0.05, hills=(Hill(x_m=40.0, y_m=-30.0, height_m=12.0, sigma_m=25.0),)
)


def _pair(
    sigma_nu=(1.0, 0.5, 0.2), initial=(3.0, 2.0, 1.5, 0.05), s0=(15.0, -8.0, 20.0, 0.7), terrain=HILL, **kw
):
    cfg = EkfConfig(sigma_nu=sigma_nu, initial_sigma=initial, **kw)
    ff = StateEkf(cfg, np.array(s0, dtype=float), terrain)
    wind = WindStateEkf(
        WindEkfConfig(cfg, wind_prior_sigma_mps=CALM, wind_walk_mps_per_sqrt_s=0.0), np.array(s0), terrain
    )
    return ff, wind


def _same(ff: StateEkf, w: WindStateEkf, what=None) -> None:
    assert np.allclose(w.s, ff.s, rtol=1e-12, atol=1e-12), (what, w.s, ff.s)
    assert np.allclose(w.P, ff.P, rtol=1e-9, atol=1e-15), (what, w.P, ff.P)
    assert w.updates == ff.updates, (what, w.updates, ff.updates)


def test_a_fresh_filter_has_counted_nothing_and_keeps_ffs_config():
    cfg = WindEkfConfig(wind_prior_sigma_mps=0.5, wind_walk_mps_per_sqrt_s=0.0)  # both valid
    f = WindStateEkf(cfg, np.zeros(4))
    assert f.updates == {"gps": 0, "alt": 0, "gyro": 0}
    assert f.cfg is cfg.ekf
    assert np.array_equal(f.wind_cov, np.diag([0.25, 0.25]))


def _one_step(cfg: WindEkfConfig) -> np.ndarray:
    """State and covariance after one 0.1 s step with a GPS fix, a height and gyro samples."""
    t0 = 5.0
    samples = Samples(
        gps=np.array([[t0 + 0.05, 3.0, -2.0]]),
        gps_var_m2=np.zeros(1),  # <= 0: the configured sigma_gps_m
        alt=np.array([[t0 + 0.06, 30.0]]),
        gyro=np.array([[t0 + 0.015, 0.12], [t0 + 0.045, 0.08]]),
    )
    f = WindStateEkf(cfg, np.array([0.0, 0.0, 31.0, 0.7]))
    f.process(samples, np.array([20.0, 0.5, 0.1]), t0, t0 + 0.1)
    return np.concatenate([f.x, f.P_full.ravel()])


# one change per field of WindEkfConfig and of FF's EkfConfig in it: (field name, the change)
_FIELD_CASES = [
    ("wind_prior_sigma_mps", {"wind_prior_sigma_mps": 2.0}),
    ("wind_walk_mps_per_sqrt_s", {"wind_walk_mps_per_sqrt_s": 1.0}),
    ("dt_s", {"ekf": EkfConfig(dt_s=0.02)}),
    ("sigma_nu", {"ekf": EkfConfig(sigma_nu=(2.0, 1.0, 1.0))}),
    ("sigma_nu", {"ekf": EkfConfig(sigma_nu=(1.0, 2.0, 1.0))}),
    ("sigma_nu", {"ekf": EkfConfig(sigma_nu=(1.0, 1.0, 2.0))}),
    ("sigma_gps_m", {"ekf": EkfConfig(sigma_gps_m=6.0)}),
    ("sigma_alt_m", {"ekf": EkfConfig(sigma_alt_m=3.0)}),
    ("sigma_gyro_radps", {"ekf": EkfConfig(sigma_gyro_radps=0.1)}),
    ("alt_max_range_m", {"ekf": EkfConfig(alt_max_range_m=25.0)}),  # the 30 m height out of range
    ("alt_min_m", {"ekf": EkfConfig(alt_min_m=35.0)}),
    ("initial_sigma", {"ekf": EkfConfig(initial_sigma=(3.0, 3.0, 1.5, 0.1))}),
]


def test_the_field_cases_cover_every_field_of_the_config():
    fields = {f.name for f in dataclasses.fields(WindEkfConfig) if f.name != "ekf"}
    assert {name for name, _ in _FIELD_CASES} == fields | {f.name for f in dataclasses.fields(EkfConfig)}


@pytest.mark.parametrize(
    ("name", "change"), _FIELD_CASES, ids=[f"{n}-{k}" for k, (n, _) in enumerate(_FIELD_CASES)]
)
def test_no_field_of_the_config_is_ignored(name, change):
    """Each field of WindEkfConfig (and of FF's EkfConfig in it) changes the filter's state or
    covariance after one step: none is stored and silently left unread."""
    base = _one_step(WindEkfConfig())
    changed = _one_step(dataclasses.replace(WindEkfConfig(), **change))
    assert not np.allclose(changed, base, rtol=1e-9, atol=0), name


def test_predict_in_a_calm_certain_wind_is_ffs_prediction():
    """Off the axes (heading 0.7 rad, so the speed noise has cross terms), with a climb and a turn,
    with and without gyro samples: Eqs. 16-17 as StateEkf computes them."""
    ff, w = _pair()
    for k in range(40):
        u = np.array([20.0 + k, 1.5 - 0.1 * k, 0.3 - 0.02 * k])
        g = None if k % 3 == 0 else 0.1 + 0.05 * k
        ff.predict(u, DT, g)
        w.predict(u, DT, g)
        _same(ff, w, k)
    assert w.updates["gyro"] == 26


@pytest.mark.parametrize("seed", [1, 2])
def test_process_in_a_calm_certain_wind_is_ffs_over_random_steps(seed):
    """Random steps of GPS (with, without and with short variance arrays; NaN positions),
    altimeter (in and out of range, at its bounds) and gyro samples at random instants, over a
    hill, turning and climbing, some steps on the ground: StateEkf's pose, covariance and counts."""
    rng = np.random.default_rng(seed)
    ff, w = _pair()
    t0 = 3.0
    for k in range(50):
        t1 = t0 + 0.1
        n_gps, n_alt, n_gyro = rng.integers(0, 3), rng.integers(0, 4), rng.integers(0, 11)
        gps = np.column_stack(
            [np.sort(rng.uniform(t0, t1, n_gps)), rng.normal(15, 20, n_gps), rng.normal(-8, 20, n_gps)]
        )
        if n_gps and k % 7 == 3:
            gps[0, 1 + k % 2] = math.nan  # a fix without one coordinate is skipped
        var = [
            rng.uniform(1.0, 16.0, n_gps),
            np.zeros(0),
            np.full(n_gps, -1.0),
            rng.uniform(1.0, 16.0, max(0, n_gps - 1)),
        ][k % 4]
        alt = np.column_stack([rng.uniform(t0, t1, n_alt), rng.uniform(-5.0, 45.0, n_alt)])
        if n_alt and k % 5 == 1:
            alt[0, 1] = [0.0, 40.0][k % 2]  # the altimeter's bounds are in range
        gyro = np.column_stack([t0 + DT * np.arange(1, n_gyro + 1), rng.normal(0.1, 0.3, n_gyro)])
        samples = Samples(gps.reshape(-1, 3), var, alt.reshape(-1, 2), gyro.reshape(-1, 2))
        u = np.array([rng.uniform(10, 25), rng.normal(0, 1), rng.normal(0, 0.3)])
        moving = k % 13 != 5
        ff.process(samples, u, t0, t1, moving=moving)
        w.process(samples, u, t0, t1, moving=moving)
        _same(ff, w, k)
        t0 = t1
    assert min(w.updates.values()) > 0


def test_process_edges_in_a_calm_certain_wind_are_ffs():
    """Samples at a substep's boundary, just after it, in the first substep, with a NaN stamp; a
    window shorter than a substep; integer commands; a GPS fix with one NaN coordinate; altimeter
    heights at and past its bounds."""
    t0 = 2.0
    cases = [
        Samples(np.array([[t0 + 3 * DT, 20.0, -5.0]]), np.array([4.0])),
        Samples(np.array([[t0 + 3 * DT + 5e-5, 20.0, -5.0]]), np.array([4.0])),
        Samples(np.array([[t0 + 0.5 * DT, 20.0, -5.0]]), np.array([4.0])),
        Samples(np.array([[math.nan, 20.0, -5.0]]), np.array([4.0])),
        Samples(np.array([[t0 + 0.05, math.nan, -5.0], [t0 + 0.06, 20.0, math.nan]]), np.array([4.0, 4.0])),
        Samples(np.array([[t0 + 0.05, 20.0, -5.0], [t0 + 0.07, 30.0, -9.0]]), np.zeros(0)),
        Samples(alt=np.array([[t0 + 0.02, 0.0], [t0 + 0.04, 40.0], [t0 + 0.06, -0.01], [t0 + 0.08, 40.01]])),
        Samples(alt=np.array([[math.nan, 20.0], [t0 + 0.03, math.nan]])),
        Samples(
            gyro=np.array(
                [[t0 + 0.5 * DT, 0.4], [t0 + 4 * DT, -0.2], [math.nan, 0.9], [t0 + 7 * DT, math.nan]]
            )
        ),
    ]
    for i, smp in enumerate(cases):
        for t1, cmd in ((t0 + 0.1, np.array([20, 1, 0])), (t0 + 0.004, np.array([20.0, 1.0, 0.3]))):
            ff, w = _pair()
            ff.process(smp, cmd, t0, t1)
            w.process(smp, cmd, t0, t1)
            _same(ff, w, (i, t1))


def test_the_wind_triangle_spreads_the_winds_uncertainty_into_the_position():
    """No input noise, a known pose, an unknown constant wind N(0, sigma_w^2 I) (no walk): after
    time T the position is x0 + (v cos, v sin) T + w T, so P_pos = T^2 sigma_w^2 I,
    P_pos,w = T sigma_w^2 I and the wind's covariance is unchanged; the wind moves the mean."""
    sw, n, th, v = 2.0, 70, 0.9, 18.0
    cfg = WindEkfConfig(EkfConfig(sigma_nu=(0.0, 0.0, 0.0), initial_sigma=(0.0, 0.0, 0.0, 0.0)), sw, 0.0)
    f = WindStateEkf(cfg, np.array([5.0, -4.0, 30.0, th]), wind0_mps=(1.5, -0.5))
    for _ in range(n):
        f.predict(np.array([v, 0.0, 0.0]), DT)
    t = n * DT
    assert np.allclose(
        f.s, [5.0 + (v * math.cos(th) + 1.5) * t, -4.0 + (v * math.sin(th) - 0.5) * t, 30.0, th]
    )
    p = f.P_full
    assert np.allclose(p[:2, :2], t**2 * sw**2 * np.eye(2), rtol=1e-12, atol=1e-15)
    assert np.allclose(p[:2, 4:], t * sw**2 * np.eye(2), rtol=1e-12, atol=1e-15)
    assert np.allclose(p[4:, 4:], sw**2 * np.eye(2), rtol=1e-12)
    assert np.allclose(p[2:4], 0.0) and np.allclose(p[:, 2:4], 0.0)
    assert f.wind_mps == (1.5, -0.5)


def test_the_random_walk_and_the_input_noise_add_as_the_module_doc_writes_them():
    """P' = A P A^T + G Q G^T + Q_w per substep, written out here with the matrices of the module doc."""
    q_w, sn = 0.3, (1.2, 0.7, 0.25)
    cfg = WindEkfConfig(EkfConfig(sigma_nu=sn, initial_sigma=(2.0, 1.0, 0.5, 0.1), dt_s=DT), 1.5, q_w)
    f = WindStateEkf(cfg, np.array([0.0, 0.0, 30.0, -2.2]))
    p = np.diag(np.square([2.0, 1.0, 0.5, 0.1, 1.5, 1.5]))
    th = -2.2
    for k in range(25):
        v, om = 20.0 + k, 0.2
        a = np.eye(6)
        a[0, 3], a[1, 3] = -v * math.sin(th) * DT, v * math.cos(th) * DT
        a[0, 4] = a[1, 5] = DT
        g = np.zeros((6, 3))
        g[0, 0], g[1, 0], g[2, 1], g[3, 2] = math.cos(th) * DT, math.sin(th) * DT, DT, DT
        p = a @ p @ a.T + g @ np.diag(np.square(sn)) @ g.T + np.diag([0, 0, 0, 0, q_w**2 * DT, q_w**2 * DT])
        f.predict(np.array([v, 0.0, om]), DT)
        th += om * DT
        assert np.allclose(f.P_full, p, rtol=1e-10, atol=1e-14), k


def test_a_gps_fix_after_a_drift_gives_the_exact_posterior_of_the_wind():
    """x_T = x0 + v T + w T with w ~ N(0, sigma_w^2), fixed x0 and v; a fix z = x_T + N(0, r):
    the wind's posterior mean is T sigma_w^2 (z - x0 - v T) / (T^2 sigma_w^2 + r), its variance
    sigma_w^2 r / (T^2 sigma_w^2 + r); north likewise, independent of east."""
    sw, r, n, v = 3.0, 4.0, 200, 20.0
    cfg = WindEkfConfig(EkfConfig(sigma_nu=(0.0, 0.0, 0.0), initial_sigma=(0.0, 0.0, 0.0, 0.0)), sw, 0.0)
    f = WindStateEkf(cfg, np.array([0.0, 0.0, 30.0, 0.0]))
    for _ in range(n):
        f.predict(np.array([v, 0.0, 0.0]), DT)
    t = n * DT
    zx, zy = v * t + 5.0, -3.0  # drifted 5 m east and 3 m south of dead reckoning
    f.update_gps(zx, zy, r)
    d = t**2 * sw**2 + r
    assert f.wind_mps == pytest.approx((t * sw**2 * 5.0 / d, t * sw**2 * -3.0 / d), rel=1e-12)
    assert np.allclose(f.wind_cov, sw**2 * r / d * np.eye(2), rtol=1e-12)
    assert f.updates["gps"] == 1


def test_a_fix_on_a_fresh_filter_moves_the_pose_not_the_wind():
    """Before any drift the wind is uncorrelated with the pose: a GPS fix or an altimeter height
    tells nothing about it (the altimeter row has zero wind columns), and leaves its mean and
    covariance as they were; the height's posterior is the precision-weighted mean (flat ground)."""
    cfg = WindEkfConfig(EkfConfig(initial_sigma=(3.0, 3.0, 2.0, 0.1), sigma_alt_m=1.5), 4.0, 0.1)
    f = WindStateEkf(cfg, np.array([10.0, 20.0, 30.0, 0.3]), Terrain(base_m=5.0), wind0_mps=(1.0, 2.0))
    f.update_altimeter(27.0)  # z - 5 measured as 27: z = 32
    post = 1.0 / (1.0 / 2.0**2 + 1.0 / 1.5**2)
    assert f.s[2] == pytest.approx(post * (30.0 / 2.0**2 + 32.0 / 1.5**2), rel=1e-12)
    assert f.P[2, 2] == pytest.approx(post, rel=1e-12)
    assert f.s[3] == pytest.approx(0.3) and f.P[3, 3] == pytest.approx(0.01)
    f.update_gps(12.0, 18.0)
    assert f.wind_mps == (1.0, 2.0) and np.array_equal(f.wind_cov, np.diag([16.0, 16.0]))
    assert f.updates == {"gps": 1, "alt": 1, "gyro": 0}


def test_the_climb_and_the_turn_are_integrated_per_substep():
    cfg = WindEkfConfig(EkfConfig(sigma_nu=(0.0, 0.0, 0.0), initial_sigma=(0.0, 0.0, 0.0, 0.0)), 1.0, 0.0)
    f = WindStateEkf(cfg, np.array([0.0, 0.0, 30.0, 0.0]))
    for _ in range(10):
        f.predict(np.array([0.0, 2.5, 0.4]), DT)
    assert f.s[2:] == pytest.approx([30.0 + 2.5 * 0.1, 0.4 * 0.1], rel=1e-12)


@pytest.mark.parametrize("var", [0.25, 1.0, 9.0])
def test_a_fix_with_its_own_variance_uses_it_however_small(var):
    """A reported variance > 0 is the fix's (Samples doc: <= 0 means the configured one), also
    below 1 m^2: the posterior is the precision-weighted mean of prior N(10, 9) and the fix."""
    cfg = WindEkfConfig(EkfConfig(initial_sigma=(3.0, 3.0, 1.0, 0.1), sigma_gps_m=3.0), 4.0, 0.1)
    f = WindStateEkf(cfg, np.array([10.0, 20.0, 30.0, 0.3]))
    f.update_gps(14.0, 20.0, var)
    post = 1.0 / (1.0 / 9.0 + 1.0 / var)
    assert f.s[0] == pytest.approx(post * (10.0 / 9.0 + 14.0 / var), rel=1e-12)
    assert f.P[0, 0] == pytest.approx(post, rel=1e-12) and f.P[1, 1] == pytest.approx(post, rel=1e-12)
