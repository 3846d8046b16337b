#!/usr/bin/env python3
"""Cost of one world control step (pure World, no ROS), the raster's share, and its direction errors.

Usage: .venv/bin/python scripts/bench_world.py [--steps N] [--warmup-s S] [--no-directions]

1. World step: analytic and 200x200 raster scenarios, 5 and 14 UAVs; the raster fire is first
   grown for --warmup-s of sim time so that the front is large. ``raster ms/step`` is the part
   spent in ``RasterFireModel.step`` (propagation batched every 0.5 s, so 1 step in 5 pays it);
   ``update p95`` is the 95th percentile of the steps that ran a propagation update.
2. Direction errors: fuel model 1 at 6 %, flat, 5 m cells, midflame wind every 5 deg from 0 to
   45 deg at 2 and 4 m/s, burnt until the head is ~250 m downwind; head = farthest burnt cell
   centre along the wind / (Rothermel head rate * t); direction = bearing of the farthest burnt
   cell from the ignition minus the wind direction. Also the no-wind area / circle area.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

import numpy as np  # noqa: E402
from fire_uav_common.scenario import Ignition, Raster, Wind, load_scenario  # noqa: E402
from fire_uav_common.terrain import Terrain  # noqa: E402
from fire_world_sim.fires import RasterFireModel  # noqa: E402
from fire_world_sim.fires.fuel_models import fuel_model  # noqa: E402
from fire_world_sim.fires.rothermel import head_spread, spread_params  # noqa: E402
from fire_world_sim.world import Command, World  # noqa: E402

SCEN = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios"


def commands(n: int, k: int) -> dict[int, Command]:
    return {i: Command(60.0, 5.0 if k < 30 else 0.0, 0.3 * math.sin(0.01 * k + i)) for i in range(n)}


class _Timed:
    """Wraps a fire model's step to time it."""

    def __init__(self, model) -> None:
        self.model = model
        self.times: list[float] = []
        self.update_times: list[float] = []

    def step(self, t_s: float, dt_s: float):
        before = getattr(self.model, "_t_updated", None)
        t0 = time.perf_counter()
        out = self.model.step(t_s, dt_s)
        dt = time.perf_counter() - t0
        self.times.append(dt)
        if before is not None and self.model._t_updated != before:
            self.update_times.append(dt)
        return out

    def __getattr__(self, name: str):
        return getattr(self.model, name)


def bench(name: str, n: int, steps: int, warmup_s: float) -> tuple[float, float, float, float, int]:
    world = World(load_scenario(SCEN / f"{name}.yaml", overrides={"timing.max_duration_s": 1e6}), 0, n)
    k = 0
    for _ in range(round(warmup_s / world.control_period_s)):
        world.step(commands(n, k))
        k += 1
    timed = _Timed(world.fires)
    world.fires = timed
    times = []
    for _ in range(steps):
        t0 = time.perf_counter()
        r = world.step(commands(n, k))
        times.append(time.perf_counter() - t0)
        k += 1
    times.sort()
    area = sum(f.area_m2 for f in r.fires)
    fire_ms = 1000 * sum(timed.times) / len(timed.times)
    upd = sorted(timed.update_times)
    upd_p95 = 1000 * upd[int(0.95 * (len(upd) - 1))] if upd else 0.0
    return 1000 * sum(times) / len(times), 1000 * times[int(0.95 * len(times))], fire_ms, upd_p95, int(area)


def spread_run(speed_mps: float, deg: float, n: int = 200, cs: float = 5.0) -> tuple[float, float]:
    """(head / Rothermel head, direction of fastest spread - wind [deg]) for fuel model 1, 6 %."""
    x0 = y0 = 0.25 * n * cs + 3.8  # off the cell centre
    th = math.radians(deg)
    rh = head_spread(spread_params(fuel_model(1), 0.06), speed_mps, th, 0.0, 0.0)[0]
    seconds = round(250.0 / rh / 0.5) * 0.5
    spec = Raster(
        cell_size_m=cs, nx=n, ny=n, wind=(Wind(0.0, speed_mps, deg),), ignitions=(Ignition(x0, y0, 0.0),)
    )
    m = RasterFireModel(spec, Terrain())
    t = 0.0
    while t < seconds - 1e-9:
        m.step(t, 0.5)
        t += 0.5
    ys, xs = np.nonzero(m.state_grid() != 0)
    px, py = m.xc[xs] - x0, m.yc[ys] - y0
    along = px * math.cos(th) + py * math.sin(th)
    far = np.argmax(np.hypot(px, py))
    err = (math.degrees(math.atan2(py[far], px[far])) - deg + 180.0) % 360.0 - 180.0
    return float(along.max() / (rh * seconds)), err


def circle_ratio(seconds: float = 400.0, factor: float = 10.0, n: int = 100, cs: float = 5.0) -> float:
    x0 = y0 = n * cs / 2 + 1.1
    spec = Raster(
        cell_size_m=cs,
        nx=n,
        ny=n,
        wind=(Wind(0.0, 0.0, 0.0),),
        ignitions=(Ignition(x0, y0, 0.0),),
        spread_factor=factor,
    )
    m = RasterFireModel(spec, Terrain())
    t = 0.0
    while t < seconds - 1e-9:
        m.step(t, 0.5)
        t += 0.5
    r = spread_params(fuel_model(1), 0.06).r0_mps * factor * seconds
    return float((m.state_grid() != 0).sum() * cs * cs / (math.pi * r * r))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--warmup-s", type=float, default=120.0)
    ap.add_argument("--no-directions", action="store_true")
    a = ap.parse_args()
    print(
        f"{'scenario':<18}{'uavs':>5}{'mean ms/step':>14}{'p95 ms':>9}"
        f"{'raster ms/step':>16}{'update p95 ms':>15}{'fire area m2':>14}"
    )
    for name in ("ff_two_fires", "grass_wind", "grass_running", "grass_brush_hill"):
        for n in (5, 14):
            mean, p95, fire_ms, upd, area = bench(name, n, a.steps, a.warmup_s)
            print(f"{name:<18}{n:>5}{mean:>14.2f}{p95:>9.2f}{fire_ms:>16.3f}{upd:>15.2f}{area:>14}")
    if a.no_directions:
        return
    print()
    print("raster spread vs Rothermel, fuel model 1 at 6 %, flat, 5 m cells, head ~250 m downwind")
    print(f"{'wind deg':>9}{'2 m/s head':>12}{'dir err':>9}{'4 m/s head':>12}{'dir err':>9}")
    worst_head, worst_dir = 0.0, 0.0
    for deg in range(0, 50, 5):
        cells = []
        for speed in (2.0, 4.0):
            h, d = spread_run(speed, float(deg))
            worst_head = max(worst_head, abs(h - 1.0))
            worst_dir = max(worst_dir, abs(d))
            cells += [f"{h:>12.3f}", f"{d:>9.1f}"]
        print(f"{deg:>9}" + "".join(cells))
    print(f"worst head error {100 * worst_head:.1f} %, worst direction error {worst_dir:.1f} deg")
    print(f"no wind: burnt area / circle area = {circle_ratio():.3f} (400 s, spread_factor 10)")


if __name__ == "__main__":
    main()
