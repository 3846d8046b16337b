"""The world's step cost at N UAVs, run as a script under any checkout's environment.

``python speed_probe.py world --uavs 20 --steps 300`` prints one JSON line: CPU milliseconds per
``World.step`` (``time.process_time``) after a warm-up, and a digest of every vehicle's truth so
that two checkouts' worlds can be compared for the same seed. It imports only the packages'
public API (``World``, ``Command``, ``load_scenario``), so the speed benchmark runs this one file
under the base checkout's environment as well as under HEAD's.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import resource
import time
from pathlib import Path


def world_step(scenario: str, uavs: int, steps: int, warmup: int, seed: int) -> dict:
    from fire_uav_common.scenario import load_scenario
    from fire_world_sim.world import Command, World

    root = Path(os.environ.get("FIRE_UAV_ROOT", "."))
    path = root / "ros2_ws" / "src" / "fire_world_sim" / "scenarios" / f"{scenario}.yaml"
    world = World(load_scenario(path, overrides={"timing.max_duration_s": 1e6}), seed, uavs)
    digest = hashlib.sha256()
    times = []
    for k in range(warmup + steps):
        # climb out, then turn at different rates: every vehicle airborne, none colliding
        cmds = {i: Command(60.0, 5.0 if k < 30 else 0.0, 0.3 * math.sin(0.01 * k + i)) for i in range(uavs)}
        t0 = time.process_time()
        r = world.step(cmds, {})
        if k >= warmup:
            times.append(time.process_time() - t0)
        for v in r.vehicles:
            digest.update(
                repr((v.uav_id, int(v.status), *map(float, (v.x_m, v.y_m, v.z_m, v.yaw_rad)))).encode()
            )
        for b in r.bundles.values():
            digest.update(repr([(g.stamp_ns, float(g.omega_z_radps)) for g in b.gyro]).encode())
            digest.update(repr([(g.stamp_ns, float(g.x_m), float(g.y_m)) for g in b.gps]).encode())
            digest.update(repr([(a.stamp_ns, float(a.range_m)) for a in b.altimeter]).encode())
    times.sort()
    return {
        "scenario": scenario,
        "uavs": uavs,
        "steps": steps,
        "world_ms_per_step": 1e3 * sum(times) / len(times),
        "world_ms_per_step_median": 1e3 * times[len(times) // 2],
        "truth_digest": digest.hexdigest()[:16],
        "max_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("what", choices=["world"])
    p.add_argument("--scenario", default="ff_two_fires")
    p.add_argument("--uavs", type=int, default=20)
    p.add_argument("--steps", type=int, default=300)
    p.add_argument("--warmup", type=int, default=40)
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    print(json.dumps(world_step(a.scenario, a.uavs, a.steps, a.warmup, a.seed)))


if __name__ == "__main__":
    main()
