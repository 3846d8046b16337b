"""The runner's ``stepping.json`` series row (``runner.stepping_row``): what the speed benchmark's
DDS window reads its CPU per step from (``fire_bench.speed._window``).

Session 27's fresh-clone CI found ``run_mission grass_running --uavs 0`` dividing by zero in the
row's agents' mean; only a system test (test_examples) reached it. These are the fast cases."""

import math

from fire_mission.runner import stepping_row


def test_a_full_fleet_row_carries_the_world_and_the_agents_mean():
    row = stepping_row(1234.56789, 420, {"world": 5.5, "agent_0": 1.0, "agent_1": 2.0, "agent_2": 4.5}, 3)
    assert row == (1234.568, 420, 5.5, 2.5)


def test_no_agents_gives_no_mean_not_a_division_by_zero():
    assert stepping_row(10.0, 7, {"world": 0.25}, 0) == (10.0, 7, 0.25, None)


def test_a_fleet_with_an_agent_unsampled_gives_no_mean():
    """A mean over the survivors would jump when one dies (3 agents at 1, 2, 6 s: mean 3; without
    the third, 1.5) and read as a change in CPU per step; the row leaves it out instead."""
    row = stepping_row(10.0, 7, {"world": 0.25, "agent_0": 1.0, "agent_1": 2.0}, 3)
    assert row[3] is None and row[2] == 0.25


def test_a_world_not_sampled_is_none_and_other_processes_do_not_count():
    row = stepping_row(10.0, 7, {"agent_0": 1.0, "agent_1": 3.0, "recorder": 50.0, "foxglove": 9.0}, 2)
    assert row[2] is None and math.isclose(row[3], 2.0)
