"""The fleet's one-pass physics (FF Eq. 4 on arrays) against the per-vehicle backend, to the bit."""

from __future__ import annotations

import math

from fire_world_sim.vehicle import Status
from fire_world_sim.world import Command, World

from .conftest import make_scenario


def _run(fast: bool, steps: int) -> list:
    # hills (a terrain floor that varies), 12 UAVs turning at different rates, two of them sent
    # into each other so that collisions crash vehicles in the middle of a step
    sc = make_scenario(
        terrain={"hills": [{"x_m": 500.0, "y_m": 500.0, "height_m": 120.0, "sigma_m": 180.0}]},
        uavs={"count": 12},
        timing={"max_duration_s": 1e6},
    )
    w = World(sc, seed=3, uav_count=12)
    w._fleet_fast = fast
    out = []
    for k in range(steps):
        cmds = {
            i: Command(40.0 + i, 4.0 if k < 40 else -1.0, 0.4 * math.sin(0.05 * k + i)) for i in range(12)
        }
        cmds[11] = None if k >= 60 else cmds[11]  # one agent silent: missed commands, then a crash
        r = w.step(cmds)
        out.append(
            (
                [(v.status, v.x_m, v.y_m, v.z_m, v.yaw_rad, v.water_kg) for v in r.vehicles],
                {i: (b.gyro, b.altimeter, b.gps, b.fires) for i, b in r.bundles.items()},
                r.events,
                r.min_separation_m,
                r.collisions,
            )
        )
    return out


def test_fleet_pass_is_the_per_vehicle_flight_to_the_bit() -> None:
    fast, slow = _run(True, 130), _run(False, 130)
    assert fast == slow
    assert any(s == Status.CRASHED for s, *_ in fast[-1][0])  # a vehicle left the fleet mid-run
