#!/usr/bin/env python3
"""The envelope a preset's JSBSim aircraft flies under the world's autopilot, beside the preset's own.

Steps one ``jsbsim`` vehicle at fixed commands (``fire_world_sim.vehicles.jsbsim_envelope``: no
agent, calm air, 100 Hz) at the full and the empty tank and prints what it flies: the lowest trim
and level speeds, the top speed held level, and at the autopilot's slowest speed the climb
and descent rates, the bank and turn rate of the hardest level turn, the roll rate, the
acceleration and the response times; then the preset's figures for the same fields. The
``j3cub`` preset's figures come from this script. With ``--excess-power`` it measures instead the
energy limit at full throttle (``full_throttle_climb``: the steepest climb held and P_s) over the
preset's ``jsbsim.excess_power`` grid (``tanker``: ``PC7_EXCESS_POWER``), beside the preset's
values. Prints, no asserts.

Usage: .venv/bin/python scripts/jsbsim_envelope.py [--airframe j3cub] [--v-slow 22] [--excess-power]
"""

from __future__ import annotations

import argparse
import dataclasses
import math

from fire_uav_common.scenario import AIRFRAMES
from fire_uav_common.scenario.airframes import G_MPS2
from fire_world_sim.vehicles.jsbsim_envelope import full_throttle_climb, measure_envelope


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="jsbsim_envelope.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--airframe", default="j3cub", choices=sorted(AIRFRAMES))
    p.add_argument("--v-slow", type=float, default=None, help="fly climb, descent, turn at this [m/s]")
    p.add_argument("--excess-power", action="store_true", help="measure the energy limit's table")
    a = p.parse_args(argv)
    if a.v_slow is not None and not a.v_slow > 0:
        p.error(f"--v-slow must be > 0, got {a.v_slow}")
    af = AIRFRAMES[a.airframe]
    if a.excess_power:
        ep = af.jsbsim.excess_power
        if ep is None:
            p.error(f"preset {a.airframe} has no jsbsim.excess_power grid")
        print(
            f"preset {a.airframe}, JSBSim aircraft {af.jsbsim.aircraft}: climb held / P_s at full throttle [m/s]"
        )
        for i, water in enumerate(ep.water_kg):
            for j, v in enumerate(ep.speeds_mps):
                climb, ps = full_throttle_climb(af, v, water)
                print(
                    f"  water {water:6.0f} kg  v {v:5.1f} m/s  measured {climb:6.2f} / {ps:6.2f}"
                    f"  preset {ep.climb_mps[i][j]:6.2f} / {ep.power_mps[i][j]:6.2f}"
                )
        return 0
    print(
        f"preset {a.airframe}, JSBSim aircraft {af.jsbsim.aircraft}, autopilot floor {af.jsbsim.v_floor_mps:g} m/s"
    )
    for water in (af.water_capacity_kg, 0.0):
        m = measure_envelope(af, water, a.v_slow)
        print(f"measured, {water:g} kg of water:")
        for f in dataclasses.fields(m):
            v = getattr(m, f.name)
            print(f"  {f.name:22s} {v:8.3f}")
    print("preset:")
    print(
        f"  {'v_min_mps':22s} {af.v_min_mps:8.3f}  (1 g stall {af.v_stall_mps:g} x {af.min_speed_factor:.3f})"
    )
    for name in ("v_max_mps", "climb_max_mps", "descent_max_mps", "bank_max_deg", "roll_rate_max_degps"):
        print(f"  {name:22s} {getattr(af, name):8.3f}")
    print(
        f"  {'turn_rate_max_radps':22s} {af.turn_rate_max_radps(af.v_min_mps):8.3f}  (g tan(bank_max) / v_min)"
    )
    for name in ("accel_max_mps2", "tau_airspeed_s", "tau_gamma_s", "tau_bank_s"):
        print(f"  {name:22s} {getattr(af, name):8.3f}")
    print(f"  turn radius at v_min: {af.v_min_mps**2 / (G_MPS2 * math.tan(af.bank_max_rad)):.1f} m")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
