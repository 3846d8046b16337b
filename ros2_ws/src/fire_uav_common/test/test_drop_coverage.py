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


def test_no_load_or_no_flow_lays_nothing_and_any_positive_one_lays_something():
    from fire_uav_common.drop_coverage import peak_coverage_lpm2

    assert peak_coverage_lpm2(10.0, 0.0, 15.0, 8.0) == 0.0  # no flow: nothing leaves the tank
    assert peak_coverage_lpm2(0.0, 5.0, 15.0, 8.0) == 0.0
    assert peak_coverage_lpm2(-1.0, 5.0, 15.0, 8.0) == 0.0
    # half a litre, or half a litre a second, is still water on the ground
    assert peak_coverage_lpm2(0.5, 5.0, 15.0, 8.0) > 0.0
    assert peak_coverage_lpm2(10.0, 0.5, 15.0, 8.0) > 0.0


def test_a_lost_share_of_the_load_lowers_the_peak_in_proportion():
    """Mass balance: what reaches the ground is (1 - loss) of the load, spread the same way."""
    from fire_uav_common.drop_coverage import PatternModel, peak_coverage_lpm2

    full = peak_coverage_lpm2(3000.0, 757.0, 46.8, 20.0)
    assert peak_coverage_lpm2(3000.0, 757.0, 46.8, 20.0, PatternModel(loss_fraction=0.25)) == pytest.approx(
        0.75 * full, rel=1e-12
    )


def test_a_spread_of_zero_is_refused_and_a_narrow_one_is_a_round_heap():
    from fire_uav_common.drop_coverage import PatternModel, peak_coverage_lpm2
    from fire_uav_common.errors import ArgumentError

    with pytest.raises(ArgumentError, match="sigma must be > 0, got 0"):
        peak_coverage_lpm2(10.0, 5.0, 15.0, 8.0, PatternModel(sigma0_m=0.0, spread_per_m=0.0))
    # sigma 0.5 m, no ground speed: the Gaussian heap's centre, V / (2 pi sigma^2)
    heap = peak_coverage_lpm2(10.0, 5.0, 0.0, 8.0, PatternModel(sigma0_m=0.5, spread_per_m=0.0))
    assert heap == pytest.approx(10.0 / (2.0 * math.pi * 0.25), rel=1e-12)


def test_a_grid_ends_at_its_last_cell_north_and_east():
    grid = np.array([[1.0, 2.0], [3.0, 4.0]])
    lv = CoverageLevels(base_cl=9.0, grid=grid, x0_m=0.0, y0_m=0.0, cell_m=10.0)
    assert lv.at(19.9, 19.9) == 4.0
    assert lv.at(20.0, 5.0) == 9.0 and lv.at(5.0, 20.0) == 9.0  # one cell beyond: the base level


def test_a_patch_holds_its_south_and_west_edges_not_its_north_and_east():
    """As the raster fire lays fuel patches: x_min <= x < x_max and y_min <= y < y_max."""
    lv = CoverageLevels(base_cl=1.0, patches=((100.0, 200.0, 300.0, 400.0, 3.0),))
    assert lv.at(100.0, 350.0) == 3.0 and lv.at(150.0, 300.0) == 3.0
    assert lv.at(200.0, 350.0) == 1.0 and lv.at(150.0, 400.0) == 1.0
