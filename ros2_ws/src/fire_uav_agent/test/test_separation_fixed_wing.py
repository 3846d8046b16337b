"""Separation between fixed-wings that turn as their airframe can (docs/airframes.md): two aircraft
of the world's coordinated-turn model, each avoiding the other with the agent's
:class:`~fire_uav_agent.separation.PeerAvoidance`, measured on the flown truth."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.separation import PeerAvoidance, SeparationConfig
from fire_uav_common.codecs.uav_state import PeerState
from fire_uav_common.constants import Objective
from fire_uav_common.scenario import AIRFRAMES
from fire_world_sim.vehicles.base import Command, FlightState
from fire_world_sim.vehicles.coordinated_turn import CoordinatedTurnModel

J3CUB = AIRFRAMES["j3cub"]


def _fly_head_on(offset_m: float, seconds: float = 30.0) -> tuple[float, list[list[float]]]:
    """Two J3Cubs at the same height flying at each other (UAV 1 ``offset_m`` to the side of UAV 0's
    track), each wanting to fly straight on through the other's start point; every 0.1 s each
    commands the agent's avoidance from the other's state one step old. Returns the closest 3-D
    approach of the truth [m] and each UAV's commanded turn rates."""
    af = J3CUB
    v = af.v_min_mps
    w_max = af.turn_rate_max_radps(v)
    model = CoordinatedTurnModel(af, 0.0)
    rngs = [np.random.default_rng(0), np.random.default_rng(1)]
    st = [
        model.launch(FlightState(0.0, 0.0, 8.0, 0.0), Command(v, 0.0, 0.0)),
        model.launch(FlightState(400.0, offset_m, 8.0, math.pi), Command(v, 0.0, 0.0)),
    ]
    goal = [(1000.0, 0.0), (-600.0, offset_m)]
    avoid = [
        PeerAvoidance(i, 0.1, SeparationConfig(), v, af.v_max_mps, w_max, lambda s: af.turn_rate_max_radps(s))
        for i in (0, 1)
    ]
    prev = [
        PeerState(i, 0, 0, s.x_m, s.y_m, s.z_m, s.yaw_rad, int(Objective.REFILL)) for i, s in enumerate(st)
    ]
    closest = math.inf
    oms: list[list[float]] = [[], []]
    for k in range(1, int(seconds * 10)):
        cmds = []
        for i in (0, 1):
            s = st[i]
            pose = np.array([s.x_m, s.y_m, s.z_m, s.yaw_rad])
            want = math.atan2(goal[i][1] - s.y_m, goal[i][0] - s.x_m)
            om0 = float(np.clip(2.0 * math.remainder(want - s.yaw_rad, math.tau), -w_max, w_max))
            _, _, om = avoid[i].command(pose, (v, 0.0, om0), goal[i], {1 - i: prev[1 - i]}, k - 1)
            oms[i].append(om)
            cmds.append(Command(v, 0.0, om))
        prev = [
            PeerState(i, k, k, s.x_m, s.y_m, s.z_m, s.yaw_rad, int(Objective.REFILL))
            for i, s in enumerate(st)
        ]
        for _ in range(10):
            st = model.step(st, cmds, 0.01, rngs)
            closest = min(
                closest, math.dist((st[0].x_m, st[0].y_m, st[0].z_m), (st[1].x_m, st[1].y_m, st[1].z_m))
            )
    return closest, oms


@pytest.mark.parametrize("offset_m", [0.0, 3.0, 8.0])
def test_two_j3cubs_head_on_keep_10_m_apart(offset_m: float) -> None:
    """Head-on (or nearly) at the same height, the J3Cub turning at most 0.37 rad/s on a 59 m radius:
    the pair passes at least 10 m apart (the issue's must-show). A guard of the committed turn
    below: it passes on the old code too, where this clean geometry never left the pair without a
    clear heading."""
    closest, _ = _fly_head_on(offset_m)
    assert closest >= 10.0


def test_a_fixed_wing_near_head_on_keeps_one_turn_direction() -> None:
    """A J3Cub 60 m from a peer closing head-on at the same height, no heading clear: as the peer's
    position wavers 0.2 m either side of the line from one step to the next (its estimate does),
    the avoider keeps turning to one side instead of following the larger closest approach from
    left to right and back every 0.1 s step (a fixed-wing then flies straight on: 8.9 m over FF's
    lake, ff_two_fires on jsbsim, seed 1)."""
    from fire_uav_agent.separation import Avoider

    v = J3CUB.v_min_mps
    w = J3CUB.turn_rate_max_radps(v)
    av = Avoider(SeparationConfig())
    sides = []
    for k in range(12):
        peer = np.array([[60.0 - 2 * v * 0.1 * k, 0.2 if k % 2 else -0.2, 8.0, -v, 0.0]])
        head, changed, _ = av.step((0.0, 0.0, 8.0), v, 0.0, peer, None, w, 0.0)
        assert changed
        sides.append(math.copysign(1.0, math.remainder(head, math.tau)))
    assert len(set(sides)) == 1
