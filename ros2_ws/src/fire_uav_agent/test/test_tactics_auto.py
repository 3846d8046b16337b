"""The ``auto`` tactic against its written rule (tactics module doc).

Truths: Byram's flame length L = 0.0775 I^0.46 with I = H w R at hand-computed points; the NWCG
limit of 8 ft = 2.44 m put back into Byram's relations (the head ROS at the limit); per fire,
auto's weights equal the head or flank weights of that fire alone.
"""

from __future__ import annotations

import dataclasses
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


def test_fire_labels_are_integer_indices_one_fire_per_chain() -> None:
    """Labels index per-fire arrays: np.bincount counts each fire's cells (counted by hand); a
    one-cell front is one fire, an empty front none."""
    f = front([0, 10, 500, 20, 900], [0] * 5, [0.1] * 5)  # fires {0, 10, 20}, {500}, {900}
    labels = fire_groups(f, 30.0)
    assert labels.tolist() == [0, 0, 1, 0, 2]
    assert np.bincount(labels).tolist() == [3, 1, 1]
    assert fire_groups(front([5.0], [7.0], [0.1]), 30.0).tolist() == [0]
    assert np.bincount(fire_groups(front([], [], []), 30.0), minlength=1).tolist() == [0]


def test_auto_weights_of_one_fire_and_of_three_fires_by_hand() -> None:
    """Per fire, the written head or flank rule (module doc), computed by hand: one slow fire gets
    (R / R_max)^2 + w_min; of three fires, the two slow ones head weights of their own cells, the
    fast one flank weights exp(-(d - d_min) / L) + w_min from its own slowest cell."""
    cfg = TacticConfig(tactic="auto")
    wm = cfg.min_weight
    one = front([0.0, 10.0, 20.0], [0.0] * 3, [0.05, 0.2, 0.1])
    np.testing.assert_allclose(front_weights(one, cfg), [0.25**2 + wm, 1.0 + wm, 0.5**2 + wm])
    x = [0.0, 10.0, 20.0, 600.0, 610.0, 620.0, 1200.0, 1210.0]
    ros = [0.05, 0.2, 0.1, 0.9, 0.3, 0.8, 0.1, 0.4]
    w = front_weights(front(x, [0.0] * 8, ros), cfg)
    flank = [math.exp(-d / cfg.flank_scale_m) + wm for d in (10.0, 0.0, 10.0)]  # anchor x = 610
    want = [0.25**2 + wm, 1.0 + wm, 0.5**2 + wm, *flank, 0.25**2 + wm, 1.0 + wm]
    np.testing.assert_allclose(w, want)


def test_a_head_exactly_at_the_flame_limit_is_not_below_it() -> None:
    """Head attack when the head's flame length is *below* ``auto_max_flame_m`` (module doc): at
    exactly the limit, a flank attack; just under it, a head attack."""
    base = TacticConfig(tactic="auto")
    r = 0.4
    lim = 0.0775 * (base.auto_heat_kj_kg * base.auto_fuel_kg_m2 * r) ** 0.46  # Byram, by hand
    cfg = dataclasses.replace(base, auto_max_flame_m=lim)
    assert byram_flame_length_m(r, cfg) == lim  # the boundary itself
    assert auto_choice(np.array([r]), cfg) == "flank"
    assert auto_choice(np.array([r * (1.0 - 1e-9)]), cfg) == "head"


def test_bad_auto_fields_are_named() -> None:
    with pytest.raises(ValueError, match="tactic auto_max_flame_m must be > 0, got 0.0"):
        TacticConfig(tactic="auto", auto_max_flame_m=0.0)


def _groups_by_flood_fill(x: np.ndarray, y: np.ndarray, link_m: float) -> list[int]:
    """Plain reference: flood-fill the graph of cells at most ``link_m`` apart, fires numbered in
    order of their first cell."""
    n, label = len(x), [-1] * len(x)
    fires = 0
    for s in range(n):
        if label[s] >= 0:
            continue
        label[s], todo = fires, [s]
        while todo:
            k = todo.pop()
            for m in range(n):
                if label[m] < 0 and math.hypot(x[k] - x[m], y[k] - y[m]) <= link_m:
                    label[m] = fires
                    todo.append(m)
        fires += 1
    return label


def test_cells_linked_only_through_a_later_cell_are_one_fire() -> None:
    """0 and 1 are 20 m apart, each 11.2 m from cell 2: one fire at a 12 m link, whatever the
    order of the cells; and random fronts against a flood fill."""
    assert fire_groups(front([0, 20, 10], [0, 0, 5], [0.1] * 3), 12.0).tolist() == [0, 0, 0]
    assert fire_groups(front([10, 0, 20], [5, 0, 0], [0.1] * 3), 12.0).tolist() == [0, 0, 0]
    rng = np.random.default_rng(21)
    for _ in range(30):
        n = int(rng.integers(1, 40))
        x, y = rng.uniform(0, 200, n), rng.uniform(0, 200, n)
        got = fire_groups(front(x, y, np.full(n, 0.1)), 25.0).tolist()
        assert got == _groups_by_flood_fill(x, y, 25.0)
