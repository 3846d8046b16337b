"""Rothermel edges not reached by the Behave table (which holds 1-h = 10-h = 100-h moisture,
100 % live moisture and the 13 standard models): fuels outside the standard set, the moisture
classes one at a time, Rothermel's additive wind + slope factor (1972 Eq. 52), the Andrews,
Cruz & Rothermel (2013) cap, and the scalar / array contract of the public functions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_world_sim.fires.fuel_models import FuelModel, fuel_model
from fire_world_sim.fires.rothermel import (
    ellipse_eccentricity,
    head_spread,
    length_to_breadth,
    rate_of_spread,
    spread_params,
)
from hypothesis import given, settings
from hypothesis import strategies as st


def custom(load_1h=0.0, herb=0.0, depth=1.0, mx=0.12) -> FuelModel:
    return FuelModel(99, "custom", load_1h, 0.0, 0.0, herb, 0.0, 3500, 1500, 1500, depth, mx)


def test_a_fuel_without_load_does_not_spread() -> None:
    p = spread_params(custom(), 0.06)
    r, _, u = head_spread(p, 5.0, 0.0, 0.3, 0.0)
    assert p.r0_mps == 0.0 and r == 0.0 and u == 0.0


def test_any_dry_enough_fine_fuel_spreads_however_light() -> None:
    # Rothermel's R0 = I_R xi / (rho_b eps Q_ig) > 0 for any load below the moisture of
    # extinction: a light 0.01 t/ac grass still spreads, slower than the 0.74 t/ac of model 1
    light = spread_params(custom(load_1h=0.01), 0.06).r0_mps
    assert 0.0 < light < spread_params(fuel_model(1), 0.06).r0_mps


def test_live_only_fuel_takes_the_dead_extinction_moisture() -> None:
    # Albini (1976): M_x,live = 2.9 W' (1 - M_f/M_x,dead) - 0.226 with W' = 0 without dead fuel,
    # so the max() leaves M_x,dead (0.20): herb at 60 % does not burn, at 10 % it does
    assert spread_params(custom(herb=1.0, mx=0.20), 0.06, m_live_herb=0.6).r0_mps == 0.0
    assert spread_params(custom(herb=1.0, mx=0.20), 0.06, m_live_herb=0.1).r0_mps > 0.0


def test_characteristic_sav_of_a_single_class_is_its_sav_and_residence_time() -> None:
    # one class: the surface-weighted SAV is the class's own; Anderson (1969) residence time
    # 384 / sigma min: 0.11 min for model 1 (sigma 3500 1/ft), 0.256 min for model 3 (1500)
    for model, sav, tau_min in ((1, 3500.0, 0.1097), (3, 1500.0, 0.256)):
        p = spread_params(fuel_model(model), 0.06)
        assert p.sigma_per_ft == pytest.approx(sav)
        assert p.residence_time_s == pytest.approx(tau_min * 60.0, rel=1e-3)


@pytest.mark.parametrize("model", [2, 4, 5, 7, 10])
def test_wetter_live_fuel_spreads_slower(model: int) -> None:
    rates = [
        rate_of_spread(spread_params(fuel_model(model), 0.06, m_live_herb=m, m_live_woody=m), 2.0)
        for m in (0.6, 1.0, 1.5, 2.0)
    ]
    assert np.all(np.diff(rates) < 0), rates


@pytest.mark.parametrize("which", ["m_10h", "m_100h"])
def test_each_dead_moisture_class_is_used(which: str) -> None:
    # model 2 has 10-h and 100-h fuel: wetting either one alone slows the fire
    dry = spread_params(fuel_model(2), 0.06, 0.06, 0.06).r0_mps
    wet = spread_params(fuel_model(2), 0.06, **{"m_10h": 0.06, "m_100h": 0.06, which: 0.12}).r0_mps
    assert wet < dry


@settings(max_examples=25, deadline=None)
@given(
    st.sampled_from([1, 2, 4, 8, 10]),
    st.floats(0.0, 4.0),
    st.floats(0.0, 0.8),
    st.floats(-math.pi, math.pi),
)
def test_wind_and_slope_factors_add_when_aligned(model: int, wind: float, slope: float, th: float) -> None:
    """Rothermel 1972 Eq. 52: R = R0 (1 + phi_w + phi_s) with the wind blowing upslope, for
    any common direction; each phi read from a run with the other effect off."""
    p = spread_params(fuel_model(model), 0.06)
    r0 = p.r0_mps
    phi_w = rate_of_spread(p, wind, wind_limit="none") / r0 - 1.0
    phi_s = rate_of_spread(p, 0.0, slope, wind_limit="none") / r0 - 1.0
    r, d, _ = head_spread(p, wind, th, slope, th, wind_limit="none")
    assert rate_of_spread(p, wind, slope, wind_limit="none") == pytest.approx(
        r0 * (1 + phi_w + phi_s), rel=1e-9
    )
    assert r == pytest.approx(r0 * (1 + phi_w + phi_s), rel=1e-9)
    if phi_w + phi_s > 1e-9:
        assert math.cos(d - th) == pytest.approx(1.0)


@settings(max_examples=25, deadline=None)
@given(st.floats(0.0, 25.0), st.sampled_from([1, 3, 4]))
def test_andrews_2013_caps_the_rate_at_the_effective_wind(wind: float, model: int) -> None:
    """Andrews, Cruz & Rothermel (2013): R <= U_eff (never below the no-wind R0)."""
    p = spread_params(fuel_model(model), 0.06)
    r, _, u = head_spread(p, wind, 0.0, 0.0, 0.0, wind_limit="andrews2013")
    assert r <= max(u, p.r0_mps) * (1 + 1e-12)
    r_none, _, _ = head_spread(p, wind, 0.0, 0.0, 0.0, wind_limit="none")
    assert r == pytest.approx(min(r_none, max(u, p.r0_mps)), rel=1e-12)


def test_andrews_2013_binds_on_grass_in_strong_wind() -> None:
    p = spread_params(fuel_model(1), 0.06)
    r, _, u = head_spread(p, 20.0, 0.0, 0.0, 0.0, wind_limit="andrews2013")
    r_none = head_spread(p, 20.0, 0.0, 0.0, 0.0, wind_limit="none")[0]
    assert r == pytest.approx(20.0) and u == pytest.approx(20.0) and r_none > 2 * r


def test_scalars_give_floats_and_arrays_give_elementwise_arrays() -> None:
    for p in (spread_params(fuel_model(1), 0.06), spread_params(fuel_model(1), 0.13)):  # burns / not
        winds = np.array([0.0, 2.0, 9.0])
        r, d, u = head_spread(p, winds, 0.5, 0.2, 0.5)
        assert isinstance(r, np.ndarray) and r.shape == (3,) and u.shape == (3,)
        for k, w in enumerate(winds):
            rk, _, uk = head_spread(p, float(w), 0.5, 0.2, 0.5)
            assert isinstance(rk, float) and isinstance(uk, float)
            assert (rk, uk) == pytest.approx((r[k], u[k]), rel=1e-12)
    assert head_spread(spread_params(fuel_model(1), 0.13), 3.0, 0.5, 0.0, 0.0)[2] == 0.0
    lb = length_to_breadth(np.array([0.0, 3.0]))
    assert isinstance(lb, np.ndarray) and isinstance(length_to_breadth(3.0), float)
    assert isinstance(ellipse_eccentricity(lb), np.ndarray)


def test_length_to_breadth_is_at_least_one() -> None:
    # an ellipse is at least as long as it is broad: L/B >= 1 for every wind, also below zero
    lb = length_to_breadth(np.linspace(-5.0, 0.5, 23))
    assert np.all(lb >= 1.0)
