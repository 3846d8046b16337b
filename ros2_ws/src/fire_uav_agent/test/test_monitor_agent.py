"""The Agent's PM hooks without ROS: role from the fleet view, fronts into fire estimates."""

import numpy as np
from fire_uav_agent.agent_core import Agent, AgentConfig, PlannerView
from fire_uav_agent.coverage import make_grid
from fire_uav_agent.mission import Objective
from fire_uav_agent.peer_link import FireEntry
from fire_uav_common.scenario import MissionSettings


def _view(uid, own_xy, peers):
    grid = make_grid(0, 600, 0, 600, 20.0)
    return PlannerView(
        0.0, uid, np.array([*own_xy, 30.0, 0.0]), grid, np.ones(grid.points.shape[0], bool),
        {j: xy for j, (xy, _) in peers.items()}, (FireEntry(5, True, 300.0, 300.0, 30.0),),
        peer_roles={j: r for j, (_, r) in peers.items()}, own_published_xy=own_xy,
        own_objective=int(Objective.SUPPRESS),
    )  # fmt: skip


def test_every_agent_agrees_on_the_monitor():
    pos = {0: (100.0, 100.0), 1: (290.0, 300.0), 2: (500.0, 500.0)}
    chosen = set()
    for uid in pos:
        a = Agent(AgentConfig(uav_id=uid, uav_count=3, mission=MissionSettings(monitors_per_fire=1)))
        peers = {j: (xy, (int(Objective.SUPPRESS), -1)) for j, xy in pos.items() if j != uid}
        fid = a.assign_monitor(_view(uid, pos[uid], peers))
        chosen |= {uid} if fid == 5 else set()
        assert a.roles == {5: (1,)}
    assert chosen == {1}


def test_front_feeds_the_fire_estimate_and_the_aim():
    a = Agent(AgentConfig(uav_id=0, uav_count=2, mission=MissionSettings(monitors_per_fire=1)))
    a._fronts = {5: (350.0, 340.0, 1.2)}
    e = FireEntry(5, True, 300.0, 300.0, 30.0)
    (out,) = a._with_fronts((e,))
    assert (out.front_x_m, out.front_y_m, out.max_spread_rate_mps) == (350.0, 340.0, 1.2)
    (aim,) = a._aim((e,))
    assert (aim.x_m, aim.y_m) == (350.0, 340.0)
