"""Two UAVs flown by a world airframe model, each behind the agent's last stage
(``separation.PeerAvoidance.command``), each seeing the other's published state every control step:
the closest 3-D approach of the truth. Used by the separation tests that check the avoider
against the world's own ``coordinated_turn`` model (test_separation_detect.py,
test_separation_vertical_resolution.py)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from fire_uav_common.codecs.uav_state import PeerState
from fire_uav_common.constants import Objective
from fire_world_sim.vehicles.base import Command, FlightState

from ..separation import PeerAvoidance

__all__ = ["closest_approach_flown"]


def closest_approach_flown(
    model: Any,
    states: list[FlightState],
    targets: Sequence[tuple[float, float]],
    wanted: Callable[[int, FlightState], tuple[float, float, float]],
    avoiders: Sequence[PeerAvoidance],
    omega_max_radps: float,
    steps: int,
    objective: Objective,
    period_s: float = 0.1,
    substeps: int = 10,
) -> float:
    """Fly UAVs 0 and 1 for ``steps`` control steps of ``period_s`` (the world's physics:
    ``substeps`` per step) from ``states`` (already launched by ``model``), each steering at its
    ``targets[i]`` with the command ``wanted(i, state)`` (v, v_z, omega) filtered by its avoider
    and its turn rate clipped to ``omega_max_radps``; the closest 3-D distance [m] of the two
    over every physics substep. Each publishes a :class:`PeerState` of ``objective`` with its
    target as its goal."""
    rngs = [np.random.default_rng(0), np.random.default_rng(1)]
    dmin = math.inf
    for k in range(steps):
        pub = [
            PeerState(i, k, k, s.x_m, s.y_m, s.z_m, s.yaw_rad, int(objective), -1, 0.0, *targets[i])
            for i, s in enumerate(states)
        ]
        cmds = []
        for i, s in enumerate(states):
            own = np.array([s.x_m, s.y_m, s.z_m, s.yaw_rad])
            v_c, vz_c, om = avoiders[i].command(own, wanted(i, s), targets[i], {1 - i: pub[1 - i]}, k)
            cmds.append(Command(v_c, vz_c, max(-omega_max_radps, min(omega_max_radps, om))))
        for _ in range(substeps):
            states = model.step(states, cmds, period_s / substeps, rngs)
            a, b = states
            dmin = min(dmin, math.dist((a.x_m, a.y_m, a.z_m), (b.x_m, b.y_m, b.z_m)))
    return dmin
