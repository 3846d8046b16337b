from __future__ import annotations

from pathlib import Path

import pytest
from fire_uav_common.scenario import Scenario, load_scenario, scenario_from_dict

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


@pytest.fixture
def tiny() -> Scenario:
    return load_scenario(SCENARIOS / "tiny_test.yaml")


def make_scenario(**sections: object) -> Scenario:
    d = {"name": "t", "area": {"x_min_m": 0, "x_max_m": 1000, "y_min_m": 0, "y_max_m": 1000}}
    d.update(sections)
    return scenario_from_dict(d)
