"""Edges of the lake sequence's rule (fire_uav_agent.lake_sequence), found by mutation testing.

Truth: the module doc's rule written out over plain vectors (on the lake: low and within the
radius of the lake's centre; waiting: refilling within the radius, not on it), on seeded random
UAVs around a lake that is not at the origin, in both axes; and the config's documented bounds.
"""

from __future__ import annotations

import numpy as np
import pytest
from fire_uav_agent.lake_sequence import LakeSequenceConfig, LakeUser, hold_rank, lake_holder, on_lake

CFG = LakeSequenceConfig(radius_m=500.0, clear_radius_m=160.0, low_agl_m=19.5)


def _on_lake_reference(u: LakeUser, lake: np.ndarray) -> bool:
    d = float(np.linalg.norm(np.array([u.x_m, u.y_m]) - lake))
    return d < (CFG.radius_m if u.refilling else CFG.clear_radius_m) and u.agl_m < CFG.low_agl_m


def test_on_lake_measures_the_distance_to_the_centre_in_both_axes():
    rng = np.random.default_rng(7)
    for _ in range(300):
        lake = rng.uniform(-2000.0, 2000.0, size=2)
        off = rng.uniform(-700.0, 700.0, size=2)
        u = LakeUser(
            int(rng.integers(0, 9)), *(lake + off), float(rng.uniform(0.0, 40.0)), bool(rng.random() < 0.5)
        )
        assert on_lake(u, (float(lake[0]), float(lake[1])), CFG) == _on_lake_reference(u, lake)


def test_the_holder_and_the_ranks_follow_the_distance_in_both_axes():
    # the lake at (1000, -300); 1 low right above its centre, 0 waiting 400 m north of it
    lake = (1000.0, -300.0)
    users = [LakeUser(1, 1000.0, -300.0, 7.5, True), LakeUser(0, 1000.0, 100.0, 23.0, True)]
    assert lake_holder(users, lake, CFG) == 1
    assert hold_rank(0, users, lake, CFG) == 0
    # 0 now 600 m north: outside the radius, not waiting; 2 waits 300 m west and takes rung 0
    users = [LakeUser(1, 1000.0, -300.0, 7.5, True), LakeUser(0, 1000.0, 300.0, 23.0, True)]
    users.append(LakeUser(2, 700.0, -300.0, 23.0, True))
    assert hold_rank(2, users, lake, CFG) == 0
    # a climbing UAV low 400 m south, beyond the 160 m clear radius, no longer holds the lake
    assert lake_holder([LakeUser(3, 1000.0, -700.0, 10.0, False)], lake, CFG) is None


def test_low_means_strictly_below_low_agl():
    # the module doc: "below low_agl_m" (a UAV exactly at the height is not yet low)
    at = LakeUser(3, 50.0, 0.0, CFG.low_agl_m, True)
    assert not on_lake(at, (0.0, 0.0), CFG)
    assert lake_holder([at, LakeUser(0, 300.0, 0.0, 23.0, True)], (0.0, 0.0), CFG) == 0


@pytest.mark.parametrize("v", [1e-3, 0.5, 1.0])
def test_any_positive_finite_config_value_is_accepted(v):
    # "> 0 and finite": small values too (a config in km or a scaled test geometry)
    cfg = LakeSequenceConfig(radius_m=v, clear_radius_m=v, low_agl_m=v)
    assert (cfg.radius_m, cfg.clear_radius_m, cfg.low_agl_m) == (v, v, v)
