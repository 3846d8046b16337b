"""Perimeter-monitor role assignment and the MONITOR planner wrapper (PM in the agent)."""

import itertools
from types import SimpleNamespace

import numpy as np
import pytest
from fire_perimeter_monitor.synthetic_fire import linear_ros, star_fire
from fire_uav_agent.mission import Objective
from fire_uav_agent.monitor_role import MonitorPlanner, MonitorPlannerConfig, RoleConfig, assign_monitors
from fire_uav_agent.peer_link import FireEntry

S, P, M, G = int(Objective.SUPPRESS), int(Objective.SEARCH), int(Objective.MONITOR), int(Objective.GROUNDED)
FIRES = [(7, 100.0, 100.0), (3, 500.0, 500.0)]
UAVS = {0: (110.0, 100.0, S, -1), 1: (480.0, 500.0, P, -1), 2: (0.0, 0.0, S, -1), 3: (90.0, 90.0, G, -1)}


def test_deterministic_whatever_the_order():
    ref = assign_monitors(FIRES, UAVS, RoleConfig(1))
    assert ref == {3: (1,), 7: (0,)}  # grounded uav 3 is not eligible
    for perm in itertools.permutations(UAVS.items()):
        assert assign_monitors(reversed(FIRES), dict(perm), RoleConfig(1)) == ref


def test_respects_monitors_per_fire_and_one_fire_per_uav():
    two = assign_monitors(FIRES, UAVS, RoleConfig(2))
    assert two[3] == (1, 0) and two[7] == (2,)  # fire 3 first (lower id) takes the two nearest
    assert assign_monitors(FIRES, UAVS, RoleConfig(0)) == {}
    with pytest.raises(ValueError, match="monitors_per_fire"):
        RoleConfig(-1)


def test_hysteresis_keeps_the_incumbent_and_crash_reassigns():
    uavs = {0: (200.0, 100.0, M, 7), 2: (120.0, 100.0, S, -1)}  # 2 is nearer, but 0 monitors fire 7
    assert assign_monitors(FIRES[:1], uavs, RoleConfig(1, hysteresis_m=150.0)) == {7: (0,)}
    assert assign_monitors(FIRES[:1], uavs, RoleConfig(1, hysteresis_m=0.0)) == {7: (2,)}
    del uavs[0]  # uav 0 crashed: no longer alive in anyone's view
    assert assign_monitors(FIRES[:1], uavs, RoleConfig(1)) == {7: (2,)}


def test_planner_follows_the_perimeter_and_reports_a_front():
    fire = star_fire((80, 80), 5.0, (40, 40), linear_ros(0.2, 2.0, 0.0))
    entry = FireEntry(0, True, *fire.ignition_xy_m, 30.0)
    plan = MonitorPlanner(1, MonitorPlannerConfig(speed_mps=50.0, lookahead_cells=3, ros_baseline_s=5.0))
    cell = fire.boundary_cell_at_angle(0.3, 40.0)
    x, y = (float(v) for v in fire.grid.center(*cell))
    t = 40.0
    for _ in range(400):
        cells = fire.observe(x, y, 20.0, t)
        view = SimpleNamespace(
            target_fire_id=0,
            fires=(entry,),
            cells=cells,
            cell_size_m=5.0,
            s=np.array([x, y, 30.0, 0.0]),
            t_s=t,
        )
        tgt = plan.plan(view)
        assert tgt is not None and tgt.waypoint_xy is not None
        nx, ny = plan.active.next_waypoint()
        assert np.hypot(tgt.waypoint_xy[0] - x, tgt.waypoint_xy[1] - y) < 40.0  # a few cells ahead
        t += np.hypot(nx - x, ny - y) / 50.0 + 1e-3
        x, y = nx, ny
    assert plan.active.initial_lap_done
    fx, fy, ros = plan.front(0)
    # fastest spread is west (r_max at 180 deg): the front lies west of the ignition point
    assert fx < fire.ignition_xy_m[0] and ros > 0
    assert plan.plan(SimpleNamespace(target_fire_id=9, fires=(entry,))) is None  # unknown fire
