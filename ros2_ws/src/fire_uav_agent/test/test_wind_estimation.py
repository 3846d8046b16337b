"""The fixed-wing EKF with wind states (fire_uav_agent.wind_estimation) against the world's own truth.

The truth is the world's ``coordinated_turn`` backend (its process noise: white speed and climb
noise per substep, FF Eq. 4) drifting in a constant wind, read by the world's own sensors
(``fire_world_sim.sensors.SensorSuite``: GPS, altimeter, gyro with their noise and dropouts);
the filter's input is the agent's own flown-input model (``FlownInput``), as in ``Agent``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.airframe_model import FlownInput, input_noise_sigma
from fire_uav_agent.coverage import VehicleLimits
from fire_uav_agent.errors import ConfigError
from fire_uav_agent.estimation import EkfConfig, Samples, StateEkf
from fire_uav_agent.wind_estimation import WindEkfConfig, WindStateEkf
from fire_uav_common import scenario as sc
from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario import AIRFRAMES
from fire_world_sim.sensors import SensorSuite
from fire_world_sim.vehicles.base import Command, FlightState
from fire_world_sim.vehicles.coordinated_turn import CoordinatedTurnModel
from scipy import stats

SMALL = AIRFRAMES["small_uav"]
LIM = VehicleLimits.of(sc.airframes.envelope_vehicle(sc.Vehicle(), SMALL))
AIR = VehicleStatus.AIRBORNE
DT, T = 0.01, 0.1
WIND = (3.0 * math.cos(math.radians(20.0)), 3.0 * math.sin(math.radians(20.0)))  # grass_running's


def _command(t: float) -> tuple[float, float, float]:
    """Straight for 30 s (the crosswind not yet separable from a heading error), then turns."""
    if t < 30.0:
        return (20.0, 0.0, 0.0)
    return (22.0 + 4.0 * math.sin(0.07 * t), 0.0, 0.35 * math.sin(0.05 * (t - 30.0)))


def _fly(make_ekf, seconds: float, seed: int = 3, wind=WIND):
    """Fly the world's model in ``wind`` (east, north) [m/s], or ``wind(t)``; return per step (t, pose
    error, NEES, wind estimate, its covariance) and the filter."""
    wind_at = wind if callable(wind) else (lambda _t: wind)
    model = CoordinatedTurnModel(SMALL, sc.Vehicle().process_noise_sigma)
    rng = np.random.default_rng(seed)
    sensors = SensorSuite(sc.Sensors(), seed, 0)
    truth = model.launch(FlightState(100.0, 100.0, 30.0, 0.0, water_kg=5.0), Command(20.0, 0.0, 0.0))
    flown = FlownInput(SMALL, LIM, DT, T)
    ekf = make_ekf(np.array([100.0, 100.0, 30.0, 0.0]))
    out = []
    prev = False
    for k in range(int(round(seconds / T))):
        t0 = k * T
        cmd = _command(t0)
        gps, alt, gyro = [], [], []
        c = Command(*cmd)
        for j in range(1, 11):
            (truth,) = model.step([truth], [c], DT, [rng], wind_at(t0 + (j - 1) * DT))
            ns = int(round((t0 + j * DT) * 1e9))
            g = sensors.sample_gyro(ns, truth.yaw_rate_radps)
            if g is not None:
                gyro.append((ns * 1e-9, g.omega_z_radps))
            if j % 4 == 0 and (a := sensors.sample_altimeter(ns, truth.z_m)) is not None:
                alt.append((ns * 1e-9, a.range_m))
            if j == 10 and (p := sensors.sample_gps(ns, truth.x_m, truth.y_m)) is not None:
                gps.append((ns * 1e-9, p.x_m, p.y_m))
        smp = Samples(
            np.array(gps).reshape(-1, 3),
            np.full(len(gps), 9.0),
            np.array(alt).reshape(-1, 2),
            np.array(gyro).reshape(-1, 2),
        )
        u = flown.input(np.array(cmd), prev, AIR, 5.0)
        prev = True
        ekf.process(smp, u, t0, t0 + T)
        e = ekf.s - np.array([truth.x_m, truth.y_m, truth.z_m, truth.yaw_rad])
        e[3] = math.remainder(float(e[3]), math.tau)
        w, wc = (ekf.wind_mps, ekf.wind_cov) if isinstance(ekf, WindStateEkf) else ((0.0, 0.0), np.eye(2))
        out.append((t0 + T, e, float(e @ np.linalg.solve(ekf.P, e)), w, wc))
    return out, ekf


def _wind_ekf(s0: np.ndarray) -> WindStateEkf:
    sigma_nu = input_noise_sigma(SMALL, sc.Vehicle().process_noise_sigma, DT)
    return WindStateEkf(WindEkfConfig(EkfConfig(dt_s=DT, sigma_nu=sigma_nu, alt_min_m=-math.inf)), s0)


def _ff_ekf(s0: np.ndarray) -> StateEkf:
    sigma_nu = input_noise_sigma(SMALL, sc.Vehicle().process_noise_sigma, DT)
    return StateEkf(EkfConfig(dt_s=DT, sigma_nu=sigma_nu, alt_min_m=-math.inf), s0)


def _nees_bounds(n: int) -> tuple[float, float]:
    """Two-sided 99.9 % bounds on the mean of n NEES(4) samples, counted as n / 20 independent
    ones (the samples are correlated in time, as in test_estimation.py)."""
    n_eff = max(1, n // 20)
    lo, hi = stats.chi2.ppf([0.0005, 0.9995], 4 * n_eff) / n_eff
    return float(lo), float(hi)


@pytest.fixture(scope="module")
def flight():
    return _fly(_wind_ekf, 100.0)


def test_the_wind_filter_is_consistent_in_a_steady_wind(flight):
    rows, ekf = flight
    nees = np.array([r[2] for r in rows if r[0] > 10.0])
    lo, hi = _nees_bounds(nees.size)
    # above: the chi-square bound. Below, looser: the filter assumes FF's turn-rate noise (Eq. 4),
    # which the world's coordinated_turn does not draw (its heading turns only as the bank allows),
    # so its yaw variance is conservative (FF's filter in calm air: NEES 3.0-3.3, docs/airframes.md)
    assert 0.5 * lo < nees.mean() < hi, (nees.mean(), lo, hi)
    assert max(math.hypot(r[1][0], r[1][1]) for r in rows) < 8.0
    p = ekf.P_full
    assert np.all(np.linalg.eigvalsh(p) > 0) and np.array_equal(p, p.T)


def test_the_wind_estimate_converges_to_the_true_wind_after_the_turns(flight):
    rows, _ = flight
    # straight for 30 s: the crosswind (north-west of the +x heading) is shared with the heading
    # error, and stays uncertain; the turns (from 30 s) separate them: within 40 s of the first turn
    # the estimate is within 0.5 m/s of the truth, and its covariance covers the error (chi2(2), 99.9 %)
    straight = rows[int(round(29.9 / T))]
    assert math.sqrt(straight[4][1, 1]) > 2.0 * math.sqrt(rows[-1][4][1, 1])
    for _, _, _, w, cov in [r for r in rows if r[0] > 70.0][::25]:
        err = np.array(w) - np.array(WIND)
        assert float(np.hypot(*err)) < 0.5, (w, WIND)
        assert float(err @ np.linalg.solve(cov, err)) < stats.chi2.ppf(0.999, 2)


def _polar(speed_mps: float, toward_deg: float) -> tuple[float, float]:
    return (speed_mps * math.cos(math.radians(toward_deg)), speed_mps * math.sin(math.radians(toward_deg)))


def test_a_veering_wind_is_followed_within_half_a_minute():
    # grass_brush_hill's first veer: 3 m/s toward 15 deg, then 3.5 m/s toward 45 deg (a 2.0 m/s step)
    before, after = _polar(3.0, 15.0), _polar(3.5, 45.0)
    rows, _ = _fly(_wind_ekf, 95.0, seed=4, wind=lambda t: before if t < 60.0 else after)
    assert float(np.hypot(*(np.array(rows[int(round(59.9 / T))][3]) - before))) < 0.5
    for r in [r for r in rows if r[0] > 85.0]:
        assert float(np.hypot(*(np.array(r[3]) - after))) < 0.5, (r[0], r[3], after)
    assert max(math.hypot(r[1][0], r[1][1]) for r in rows) < 8.0


def test_without_the_wind_states_the_ff_filter_is_not_consistent_in_that_wind():
    # the same flight with FF's filter (no wind state: it predicts over the ground with the
    # airspeed alone): the failure the wind states fix (docs/airframes.md: NEES 300-840)
    out, _ = _fly(_ff_ekf, 30.0)
    nees = np.array([r[2] for r in out if r[0] > 10.0])
    assert nees.mean() > 3.0 * _nees_bounds(nees.size)[1]


def test_in_calm_air_the_wind_estimate_stays_near_zero():
    out, _ = _fly(_wind_ekf, 60.0, seed=5, wind=(0.0, 0.0))
    assert float(np.hypot(*out[-1][3])) < 0.4
    nees = np.array([r[2] for r in out if r[0] > 10.0])
    lo, hi = _nees_bounds(nees.size)
    assert 0.5 * lo < nees.mean() < hi


def test_the_wind_moves_the_prediction_and_the_covariance_grows_by_the_random_walk():
    cfg = WindEkfConfig(EkfConfig(sigma_nu=(0.0, 0.0, 0.0), initial_sigma=(0.0, 0.0, 0.0, 0.0)))
    f = WindStateEkf(cfg, np.array([0.0, 0.0, 30.0, 0.0]), wind0_mps=(1.0, -2.0))
    for _ in range(100):
        f.predict(np.array([20.0, 0.0, 0.0]), 0.01)
    assert f.s[:2] == pytest.approx([21.0, -2.0], abs=1e-9)  # (20 + 1, -2) m/s for 1 s
    # the wind's variance grows by q_w^2 per second; the position's by its integral (prior 5 m/s
    # over 1 s: 25 m^2 plus q_w^2 / 3)
    q = 0.1**2
    assert f.wind_cov[0, 0] == pytest.approx(25.0 + q, rel=1e-9)
    assert f.P[0, 0] == pytest.approx(25.0 + q / 3.0, rel=1e-3)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"wind_prior_sigma_mps": 0.0}, "wind_prior_sigma_mps"),
        ({"wind_prior_sigma_mps": math.nan}, "wind_prior_sigma_mps"),
        ({"wind_walk_mps_per_sqrt_s": -0.1}, "wind_walk_mps_per_sqrt_s"),
        ({"wind_walk_mps_per_sqrt_s": math.inf}, "wind_walk_mps_per_sqrt_s"),
    ],
)
def test_bad_wind_configuration_is_an_error_naming_the_field(kwargs, field):
    with pytest.raises(ConfigError, match=field):
        WindEkfConfig(**kwargs)


def test_bad_start_state_and_wind_are_errors():
    with pytest.raises(ConfigError, match="s0"):
        WindStateEkf(WindEkfConfig(), np.array([0.0, 0.0, math.nan, 0.0]))
    with pytest.raises(ConfigError, match="wind0_mps"):
        WindStateEkf(WindEkfConfig(), np.zeros(4), wind0_mps=(1.0, math.inf))
