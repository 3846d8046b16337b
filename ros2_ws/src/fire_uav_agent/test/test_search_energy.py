"""Cruise/turn energy model (CP Eq. 10, gamma = 1.5) on hand-computed cases."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.search.energy import EnergyModel
from fire_uav_agent.search.errors import SearchConfigError
from fire_uav_agent.search.stc import stc_path


def test_eq10_segments() -> None:
    m = EnergyModel(cruise_power_w=1000.0, turn_factor=1.5, speed_mps=50.0)
    # 1000 m cruise = 20 s at 1 kW; 100 m of turns = 2 s at 1.5 kW
    assert m.segment_energy_j(np.array([400.0, 600.0]), np.array([100.0])) == pytest.approx(20000.0 + 3000.0)
    assert m.energy_j(cruise_time_s=10.0, turn_time_s=0.0) == pytest.approx(10000.0)
    assert m.energy_j(cruise_time_s=0.0, turn_time_s=10.0) == pytest.approx(15000.0)


def test_single_cell_tour_is_a_circle() -> None:
    # one 120 m cell: square of side 60 m through the sub-cell centres, all four corners filleted
    # with r = 30 m -> a full circle of radius 30 m, all of it turning
    m = EnergyModel(cruise_power_w=1000.0, speed_mps=50.0)
    path = stc_path(np.ones((1, 1), dtype=bool), x_min_m=0, y_min_m=0, cell_size_m=120.0)
    assert path.straight_length_m == pytest.approx(0.0, abs=1e-9)
    assert path.length_m == pytest.approx(2 * math.pi * 30.0)
    assert m.path_energy_j(path) == pytest.approx(1.5 * 1000.0 * 2 * math.pi * 30.0 / 50.0)


def test_two_cell_tour() -> None:
    # 240 x 120 m: rectangle 180 x 60 m through sub-cell centres; straights 2 x (180 - 60) m,
    # turns one full circle of r = 30 m
    m = EnergyModel(cruise_power_w=2000.0, speed_mps=40.0)
    path = stc_path(np.ones((1, 2), dtype=bool), x_min_m=0, y_min_m=0, cell_size_m=120.0)
    expected = 2000.0 * (240.0 / 40.0) + 1.5 * 2000.0 * (2 * math.pi * 30.0 / 40.0)
    assert m.path_energy_j(path) == pytest.approx(expected)
    # sampled version converges to the exact one
    assert m.sampled_energy_j(path.sample(0.1)) == pytest.approx(expected, rel=2e-3)


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"cruise_power_w": 0.0}, r"cruise_power_w must be > 0, got 0.0"),
        ({"cruise_power_w": math.inf}, r"cruise_power_w must be > 0, got inf"),
        ({"turn_factor": 0.5}, r"turn_factor must be >= 1, got 0.5"),
        ({"turn_factor": math.nan}, r"turn_factor must be >= 1, got nan"),
        ({"speed_mps": 0.0}, r"speed_mps must be > 0, got 0.0"),
    ],
)
def test_bad_parameters(kw, match) -> None:
    with pytest.raises(SearchConfigError, match=match):
        EnergyModel(**kw)


def test_the_edges_of_the_valid_parameters_are_accepted() -> None:
    """A turn costs no more than cruising (gamma = 1), and small powers and speeds are physical."""
    m = EnergyModel(cruise_power_w=0.5, turn_factor=1.0, speed_mps=0.5)
    assert m.energy_j(cruise_time_s=2.0, turn_time_s=2.0) == pytest.approx(2.0)


def test_negative_durations_are_refused() -> None:
    with pytest.raises(SearchConfigError, match=r"^durations must be >= 0"):
        EnergyModel().energy_j(-1.0, 0.0)
    with pytest.raises(SearchConfigError, match=r"^durations must be >= 0"):
        EnergyModel().energy_j(0.0, -1.0)
