"""The ``auto`` tactic against its written rule (tactics module doc).

Truths: Byram's flame length L = 0.0775 I^0.46 with I = H w R at hand-computed points; the NWCG
limit of 8 ft = 2.44 m put back into Byram's relations (the head ROS at the limit); per fire,
auto's weights equal the head or flank weights of that fire alone.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.tactics import TacticConfig, auto_choice, byram_flame_length_m, fire_groups, front_weights
from fire_uav_common.constants import CellState

B = int(CellState.BURNING)


def front(x, y, ros) -> FrontCells:
    x = np.asarray(x, dtype=float)
    return FrontCells(
        x, np.asarray(y, dtype=float), np.full(x.size, B), np.zeros(x.size), np.asarray(ros, dtype=float)
    )


def test_byram_flame_length_at_hand_computed_points() -> None:
    cfg = TacticConfig(tactic="auto", auto_heat_kj_kg=18_000.0, auto_fuel_kg_m2=0.5)
    # R = 0.1 m/s: I = 18000 * 0.5 * 0.1 = 900 kW/m; L = 0.0775 * 900^0.46
    assert byram_flame_length_m(0.1, cfg) == pytest.approx(0.0775 * math.exp(0.46 * math.log(900.0)))
    assert byram_flame_length_m(0.1, cfg) == pytest.approx(1.7711, abs=1e-3)
    assert byram_flame_length_m(0.0, cfg) == 0.0


def test_the_head_attack_limit_is_8_ft_of_flame_on_fuel_model_1() -> None:
    cfg = TacticConfig(tactic="auto")
    # ROS at which L = 2.44 m: I = (2.44 / 0.0775)^(1 / 0.46), R = I / (H w)
    r_lim = (2.44 / 0.0775) ** (1 / 0.46) / (18_608.0 * 0.166)
    assert 0.55 < r_lim < 0.62
    assert auto_choice(np.array([0.2, r_lim * 0.99]), cfg) == "head"
    assert auto_choice(np.array([0.2, r_lim * 1.01]), cfg) == "flank"
    assert auto_choice(np.array([0.9]), cfg) == "flank"  # grass_running's head (~0.9 m/s)
    assert auto_choice(np.array([np.nan, np.nan]), cfg) == "flank"  # head unknown: anchor and flank
    assert auto_choice(np.array([np.nan, 0.1]), cfg) == "head"


def test_front_cells_are_grouped_into_fires_by_gap() -> None:
    f = front([0, 10, 20, 500, 510], [0, 0, 0, 0, 0], [0.1] * 5)
    assert fire_groups(f, 30.0).tolist() == [0, 0, 0, 1, 1]
    assert fire_groups(f, 5.0).tolist() == [0, 1, 2, 3, 4]
    assert fire_groups(front([], [], []), 30.0).tolist() == []


def test_each_fire_gets_the_weights_of_its_own_choice() -> None:
    cfg = TacticConfig(tactic="auto")
    slow_x, fast_x = np.array([0.0, 10, 20, 30]), np.array([600.0, 610, 620, 630, 640])
    slow_r, fast_r = np.array([0.05, 0.1, 0.2, 0.15]), np.array([0.9, 0.3, 0.1, 0.4, 0.2])
    f = front(np.r_[slow_x, fast_x], np.zeros(9), np.r_[slow_r, fast_r])
    w = front_weights(f, cfg)
    head = front_weights(front(slow_x, np.zeros(4), slow_r), TacticConfig(tactic="head"))
    flank = front_weights(front(fast_x, np.zeros(5), fast_r), TacticConfig(tactic="flank"))
    np.testing.assert_allclose(w[:4], head)
    np.testing.assert_allclose(w[4:], flank)
    # the fast fire's flank anchor is its own slowest cell (x = 620), not the slow fire's
    assert w[4 + 2] == pytest.approx(1.0 + cfg.min_weight)
    assert np.argmax(w[:4]) == 2  # the slow fire's head: its fastest cell


def test_bad_auto_fields_are_named() -> None:
    with pytest.raises(ValueError, match="tactic auto_max_flame_m must be > 0, got 0.0"):
        TacticConfig(tactic="auto", auto_max_flame_m=0.0)
