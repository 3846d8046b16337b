#!/usr/bin/env python3
"""How fast the ``jsbsim`` backend steps: N aircraft of a preset in one process (docs/airframes.md).

Launches N instances of :class:`fire_world_sim.vehicles.JsbsimModel` (each its own
``jsbsim.FGFDMExec``), flies them for a number of simulated seconds at the world's physics step
with the autopilot (turns, climbs, speed changes), and prints the substeps per CPU second in total,
the CPU share that real time at that physics rate would need (N x rate / steps per CPU second),
and, for comparison, the bare JSBSim ``run()`` without autopilot and property traffic. Prints,
no asserts.

Usage: .venv/bin/python scripts/jsbsim_steps.py [--uavs 20] [--seconds 10] [--rate-hz 100]
       [--airframe small_uav]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from fire_uav_common.scenario import AIRFRAMES
from fire_world_sim.vehicles import Command, FlightState, JsbsimModel


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="jsbsim_steps.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--uavs", type=int, default=20)
    p.add_argument("--seconds", type=float, default=10.0, help="simulated seconds per aircraft")
    p.add_argument("--rate-hz", type=float, default=100.0, help="physics rate (the world's 100 Hz)")
    p.add_argument("--airframe", default="small_uav", choices=sorted(AIRFRAMES))
    a = p.parse_args(argv)
    if a.uavs < 1 or a.seconds <= 0 or a.rate_hz <= 0:
        p.error("--uavs, --seconds and --rate-hz must be > 0")
    af = AIRFRAMES[a.airframe]
    dt = 1.0 / a.rate_hz
    n_steps = round(a.seconds * a.rate_hz)
    v0 = max(af.v_min_mps, af.jsbsim.v_floor_mps) + 2.0
    models = [JsbsimModel(af) for _ in range(a.uavs)]
    states = [
        m.launch(
            FlightState(30.0 * i, 0.0, 100.0, 0.0, water_kg=af.water_capacity_kg), Command(v0, 0.0, 0.0), dt
        )
        for i, m in enumerate(models)
    ]
    rng = np.random.default_rng(0)
    cmds = [
        Command(v0 + float(rng.uniform(0, 5)), float(rng.uniform(-1, 1)), float(rng.uniform(-0.4, 0.4)))
        for _ in models
    ]
    t0 = time.process_time()
    for k in range(n_steps):
        if k % round(a.rate_hz) == 0:  # a new command every second
            cmds = [Command(c.v_lin_mps, -c.v_z_mps, -c.omega_z_radps) for c in cmds]
        for i, m in enumerate(models):
            (states[i],) = m.step([states[i]], [cmds[i]], dt, [rng])
    cpu = time.process_time() - t0
    total = n_steps * a.uavs
    rate = total / cpu
    print(f"{a.uavs} x {af.jsbsim.aircraft} ({a.airframe}), {a.seconds:g} s simulated at {a.rate_hz:g} Hz")
    print(f"with autopilot: {total} substeps in {cpu:.2f} CPU s = {rate:,.0f} substeps per CPU second")
    print(f"real time at {a.rate_hz:g} Hz needs {a.uavs * a.rate_hz / rate:.1%} of one core for the vehicles")
    t0 = time.process_time()
    for _ in range(n_steps):
        for m in models:
            assert m.fdm is not None
            m.fdm.run()
    cpu_bare = time.process_time() - t0
    print(f"bare JSBSim run(): {total / cpu_bare:,.0f} steps per CPU second")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
