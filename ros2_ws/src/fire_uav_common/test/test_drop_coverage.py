"""The coverage levels an agent reads from the fuel map (fire_uav_common.drop_coverage.CoverageLevels).

Truth: the drop guides' Table 1 (grass FBFM 1: CL 1, brush FBFM 5: CL 3) and where the scenario
lays its fuel patches (grass_brush_hill: brush from x = 450 m on, as the raster fire lays it).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from fire_uav_common.drop_coverage import CoverageLevels, coverage_levels_of
from fire_uav_common.scenario import load_scenario

SCENARIOS = Path(__file__).resolve().parents[2] / "fire_world_sim" / "scenarios"


def test_the_levels_follow_the_scenarios_fuel_patches():
    sc = load_scenario(SCENARIOS / "grass_brush_hill.yaml")
    lv = coverage_levels_of(sc.fires.raster)
    assert lv is not None
    assert lv.at(449.9, 500.0) == 1.0 and lv.at(450.0, 500.0) == 3.0 and lv.at(999.0, 10.0) == 3.0
    assert coverage_levels_of(None) is None


def test_a_grid_of_levels_is_read_by_cell_row_zero_south():
    grid = np.array([[1.0, 2.0], [3.0, math.inf]])  # row 0 the southern row
    lv = CoverageLevels(base_cl=math.inf, grid=grid, x0_m=100.0, y0_m=200.0, cell_m=30.0)
    assert lv.at(101.0, 201.0) == 1.0 and lv.at(131.0, 201.0) == 2.0 and lv.at(101.0, 231.0) == 3.0
    assert lv.at(131.0, 231.0) == math.inf and lv.at(99.0, 201.0) == math.inf  # outside: base
    with pytest.raises(ValueError, match="sigma"):
        from fire_uav_common.drop_coverage import PatternModel, peak_coverage_lpm2

        peak_coverage_lpm2(10.0, 5.0, 15.0, 8.0, PatternModel(sigma0_m=-10.0))
