#!/usr/bin/env python3
"""Cost of one world control step (pure World, no ROS): analytic and 200x200 raster, 5 and 14 UAVs.

Usage: .venv/bin/python scripts/bench_world.py [--steps N] [--warmup-s S]
The raster fire is first grown for --warmup-s of sim time so that the front is large.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

from fire_uav_common.scenario import load_scenario  # noqa: E402
from fire_world_sim.world import Command, World  # noqa: E402

SCEN = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios"


def commands(n: int, k: int) -> dict[int, Command]:
    return {i: Command(60.0, 5.0 if k < 30 else 0.0, 0.3 * math.sin(0.01 * k + i)) for i in range(n)}


def bench(name: str, n: int, steps: int, warmup_s: float) -> tuple[float, float, int]:
    world = World(load_scenario(SCEN / f"{name}.yaml", overrides={"timing.max_duration_s": 1e6}), 0, n)
    k = 0
    for _ in range(round(warmup_s / world.control_period_s)):
        world.step(commands(n, k))
        k += 1
    times = []
    for _ in range(steps):
        t0 = time.perf_counter()
        r = world.step(commands(n, k))
        times.append(time.perf_counter() - t0)
        k += 1
    times.sort()
    burning = sum(f.area_m2 for f in r.fires)
    return 1000 * sum(times) / len(times), 1000 * times[int(0.95 * len(times))], int(burning)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--warmup-s", type=float, default=120.0)
    a = ap.parse_args()
    print(f"{'scenario':<16}{'uavs':>5}{'mean ms/step':>14}{'p95 ms':>9}{'fire area m2':>14}")
    for name in ("ff_two_fires", "grass_wind"):
        for n in (5, 14):
            mean, p95, area = bench(name, n, a.steps, a.warmup_s)
            print(f"{name:<16}{n:>5}{mean:>14.2f}{p95:>9.2f}{area:>14}")


if __name__ == "__main__":
    main()
