"""EKF (FF III-B): consistency (NEES) against a vehicle simulated with Eq. 4, P stays SPD."""

import math

import numpy as np
from fire_uav_agent.estimation import EkfConfig, Samples, StateEkf, wrap_angle
from fire_uav_common import rng
from fire_uav_common.terrain import Hill, Terrain
from scipy import stats


def _run(steps: int, seed: int, terrain: Terrain):
    g = rng.stream(seed, "test_ekf")
    cfg = EkfConfig()
    truth = np.array([100.0, 100.0, terrain.elevation(100.0, 100.0) + 30.0, 0.3])
    ekf = StateEkf(cfg, truth + g.normal(0, cfg.initial_sigma))
    ekf.terrain = terrain
    nees, min_eig, asym = [], math.inf, 0.0
    for k in range(steps):
        t0 = k * 0.1
        u = np.array([60.0 + 20 * math.sin(0.05 * t0), 0.0, 0.4 * math.sin(0.2 * t0)])
        gps, alt, gyro = [], [], []
        for j in range(1, 11):
            t = t0 + j * 0.01
            w = u + g.normal(0.0, 1.0, 3)
            th = truth[3]
            truth = truth + 0.01 * np.array([w[0] * math.cos(th), w[0] * math.sin(th), w[1], w[2]])
            truth[3] = wrap_angle(truth[3])
            if g.random() < 0.7:
                gyro.append((t, w[2] + g.normal(0, 0.3)))
            if j % 4 == 0 and g.random() < 0.8:
                alt.append((t, truth[2] - terrain.elevation(truth[0], truth[1]) + g.normal(0, 1.5)))
            if j == 10 and g.random() < 0.9:
                gps.append((t, *(truth[:2] + g.normal(0, 3.0, 2))))
        smp = Samples(
            np.array(gps).reshape(-1, 3),
            np.full(len(gps), 9.0),
            np.array(alt).reshape(-1, 2),
            np.array(gyro).reshape(-1, 2),
        )
        ekf.process(smp, u, t0, t0 + 0.1)
        e = ekf.s - truth
        e[3] = wrap_angle(e[3])
        if k >= 100:
            nees.append(float(e @ np.linalg.solve(ekf.P, e)))
        min_eig = min(min_eig, float(np.linalg.eigvalsh(ekf.P).min()))
        asym = max(asym, float(np.abs(ekf.P - ekf.P.T).max()))
    return np.array(nees), min_eig, asym, ekf


def test_nees_within_chi_square_bounds_and_p_spd():
    terrain = Terrain(hills=(Hill(300.0, 300.0, 20.0, 80.0),))
    nees, min_eig, asym, ekf = _run(3000, seed=7, terrain=terrain)
    n = nees.size
    # average NEES of a 4-dof quantity over n samples: chi2(4 n) / n, two-sided 99.9 %; the
    # samples are correlated in time, so use the (wider) bounds of ~n/20 independent ones
    n_eff = n // 20
    lo, hi = stats.chi2.ppf([0.0005, 0.9995], 4 * n_eff) / n_eff
    assert lo < nees.mean() < hi, (nees.mean(), lo, hi)
    assert min_eig > 0
    assert asym == 0.0
    assert ekf.updates["gps"] > 2000 and ekf.updates["alt"] > 4000 and ekf.updates["gyro"] > 15000


def test_no_prediction_on_ground_and_bad_samples_ignored():
    ekf = StateEkf(EkfConfig(), np.array([10.0, 20.0, 0.0, 0.0]))
    smp = Samples(np.array([[0.05, np.nan, 1.0]]), np.zeros(1), np.array([[0.04, 99.0]]), np.zeros((0, 2)))
    ekf.process(smp, np.array([50.0, 0.0, 0.0]), 0.0, 0.1, moving=False)
    assert np.allclose(ekf.s, [10.0, 20.0, 0.0, 0.0])
    assert ekf.updates == {"gps": 0, "alt": 0, "gyro": 0}


def test_wrap_angle():
    assert wrap_angle(math.pi) == math.pi
    assert math.isclose(wrap_angle(-math.pi), math.pi)
    assert math.isclose(wrap_angle(3 * math.pi / 2), -math.pi / 2)
