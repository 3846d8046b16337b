"""Rothermel (1972) against published values and analytic properties (no raster: fast, so the
mutation run of fire_world_sim.fires.rothermel runs only these and test_rothermel_behave.py)."""

from __future__ import annotations

import numpy as np
import pytest
from fire_world_sim.fires.fuel_models import fuel_model
from fire_world_sim.fires.rothermel import length_to_breadth, rate_of_spread, spread_params

CHAINS_PER_HOUR = 20.1168 / 3600.0  # [m/s]
MPH = 0.44704  # [m/s]


# Anderson, H.E. 1982. Aids to determining fuel models for estimating fire behavior.
# USDA For. Serv. Gen. Tech. Rep. INT-122, Table 1 ("fire behavior ... at 8 percent dead fuel
# moisture, 100 percent live fuel moisture, 5 mi/h midflame wind", flat ground): rate of
# spread in chains/hour.
@pytest.mark.parametrize(
    ("model", "published_ch_h"),
    [(1, 78.0), (2, 35.0), (3, 104.0), (4, 75.0), (9, 7.5), (10, 7.9), (13, 13.5)],
)
def test_rothermel_matches_anderson_1982(model: int, published_ch_h: float) -> None:
    p = spread_params(fuel_model(model), 0.08, 0.08, 0.08, 1.0, 1.0)
    ros = rate_of_spread(p, 5.0 * MPH) / CHAINS_PER_HOUR
    assert ros == pytest.approx(published_ch_h, rel=0.10)


def test_rothermel_wind_and_slope_increase_spread() -> None:
    p = spread_params(fuel_model(1), 0.06)
    r0 = rate_of_spread(p, 0.0)
    assert r0 == pytest.approx(p.r0_mps)
    assert rate_of_spread(p, 2.0) > r0 * 5
    # slope factor by hand: phi_s = 5.275 beta^-0.3 tan^2 -> R = R0 (1 + phi_s)
    assert rate_of_spread(p, 0.0, 0.3) == pytest.approx(r0 * (1 + p.slope_k * 0.09))
    # above the moisture of extinction nothing spreads
    assert spread_params(fuel_model(1), 0.13).r0_mps == 0.0


def test_length_to_breadth_is_one_without_wind_grows_and_caps() -> None:
    # the values themselves are checked against Behave in test_rothermel_behave.py
    assert length_to_breadth(0.0) == pytest.approx(1.0)
    u = np.linspace(0.0, 30.0, 61)
    lb = length_to_breadth(u)
    assert np.all(np.diff(lb) >= 0) and lb[-1] == pytest.approx(8.0)
