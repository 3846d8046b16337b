"""Rothermel (1972) against published values and analytic properties (no raster: fast, so the
mutation run of fire_world_sim.fires.rothermel runs only these and test_rothermel_behave.py)."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from fire_world_sim.fires.fuel_models import fuel_model
from fire_world_sim.fires.rothermel import (
    ellipse_eccentricity,
    head_spread,
    length_to_breadth,
    rate_of_spread,
    spread_params,
)

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


def test_ellipse_eccentricity_is_the_geometry_of_an_ellipse() -> None:
    # semi-axes a = L/B, b = 1: e = sqrt(1 - b^2 / a^2); a circle has e = 0
    assert ellipse_eccentricity(1.0) == 0.0 and isinstance(ellipse_eccentricity(1.0), float)
    assert ellipse_eccentricity(2.0) == pytest.approx(np.sqrt(3.0) / 2.0, rel=1e-12)
    lb = np.array([1.0, 1.25, 3.0, 8.0])
    e = ellipse_eccentricity(lb)
    assert isinstance(e, np.ndarray) and e.shape == (4,)
    assert np.sqrt(1.0 - e**2) * lb == pytest.approx(np.ones(4), rel=1e-12)  # b / a = 1 / (L/B)


def test_backing_rate_from_the_eccentricity_matches_behave() -> None:
    """Behave's backing rate is the head rate times (1 - e) / (1 + e) (the ignition at the rear
    focus of the ellipse); with our e from our L/W it must match Behave's own backing rate."""
    table = Path(__file__).parent / "data" / "behave_tables.csv"
    with table.open() as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    checked = 0
    for row in rows:
        head, back = float(row["head_ft_min"]), float(row["back_ft_min"])
        if head == 0.0 or int(row["cross"]) or float(row["slope_pct"]) or float(row["wind_mph"]) == 0:
            continue
        p = spread_params(fuel_model(int(row["fuel_model"])), float(row["moisture"]))
        r, _, u = head_spread(p, float(row["wind_mph"]) * MPH, 0.0, 0.0, 0.0)
        e = ellipse_eccentricity(length_to_breadth(u))
        assert r / 0.3048 * 60.0 * (1 - e) / (1 + e) == pytest.approx(back, rel=0.02), row
        checked += 1
    assert checked >= 100
