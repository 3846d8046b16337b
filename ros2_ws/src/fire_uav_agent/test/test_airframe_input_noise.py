"""The EKF's input noise for an airframe whose flight departs from the agents' first-order model
(fire_uav_agent.airframe_model.input_noise_sigma, module doc "The EKF's process noise").

Truth: the closed-form variance of the integral of a first-order Gauss-Markov (Ornstein-Uhlenbeck)
error of rms sigma and correlation time tau, Var(t) = 2 sigma^2 int_0^t (t - u) exp(-u / tau) du
= 2 sigma^2 tau (t - tau (1 - exp(-t / tau))) (its autocorrelation sigma^2 exp(-|u| / tau)
integrated twice), against the variance the EKF's white input noise adds over the same time,
(t / dt) (sigma_nu dt)^2 (FF Eqs. 4, 16-17: one draw per physics substep). Over long horizons
the two must agree; the turn rate keeps FF's sigma.
"""

from __future__ import annotations

import dataclasses
import math

import pytest
from fire_uav_agent.airframe_model import MODEL_ERROR_TIME_S, input_noise_sigma
from fire_uav_common.scenario import AIRFRAMES


def _gauss_markov_position_var(sigma: float, tau: float, t: float) -> float:
    return 2.0 * sigma * sigma * tau * (t - tau * (1.0 - math.exp(-t / tau)))


@pytest.mark.parametrize("dt_s", [0.01, 0.005, 0.02])
def test_the_white_noise_grows_the_position_variance_of_the_model_error(dt_s) -> None:
    """j3cub (model error 0.7 m/s rms): over 2000 s the EKF's white speed and climb-rate noise adds
    the position variance of the correlated error (within its 0.1 % start-up term), at any
    physics period; FF's 1 m/s per substep would add a hundredth of it or less."""
    air = AIRFRAMES["j3cub"]
    assert air.model_error_mps == 0.7
    sv, sz, so = input_noise_sigma(air, 1.0, dt_s)
    t = 2000.0
    truth = _gauss_markov_position_var(air.model_error_mps, MODEL_ERROR_TIME_S, t)
    for s in (sv, sz):
        white = (t / dt_s) * (s * dt_s) ** 2
        assert white == pytest.approx(truth, rel=2e-3)
    assert so == 1.0  # the gyro measures the turn rate at every substep: FF's sigma
    assert (t / dt_s) * (1.0 * dt_s) ** 2 < 0.02 * truth


def test_ffs_sigma_where_there_is_no_model_error_or_it_is_the_larger() -> None:
    """No airframe (ff_paper), or an airframe that is the model (coordinated_turn presets: model
    error 0): FF's sigma for every input. A process noise above the model error's equivalent is
    kept (the noise is raised to the equivalent, never lowered)."""
    assert input_noise_sigma(None, 1.5, 0.01) == (1.5, 1.5, 1.5)
    assert AIRFRAMES["small_uav"].model_error_mps == 0.0
    assert input_noise_sigma(AIRFRAMES["small_uav"], 1.5, 0.01) == (1.5, 1.5, 1.5)
    air = AIRFRAMES["j3cub"]
    eq = input_noise_sigma(air, 0.0, 0.01)[0]
    assert eq > 1.0
    assert input_noise_sigma(air, 2.0 * eq, 0.01) == (2.0 * eq, 2.0 * eq, 2.0 * eq)
    tiny = dataclasses.replace(air, model_error_mps=1e-3)  # equivalent ~0.02 m/s: FF's 1 m/s wins
    assert input_noise_sigma(tiny, 1.0, 0.01) == (1.0, 1.0, 1.0)
