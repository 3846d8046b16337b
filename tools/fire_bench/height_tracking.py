"""Height tracking over a raster fire: |true height above terrain - the UAV's layer| in level flight.

usage: python -m fire_bench.height_tracking [SCENARIO] [--uavs N] [--seed S] [--tactic T]
       [--duration S] [--json OUT]

In process (``fire_uav_agent.testing.harness``), ``monitors_per_fire`` 0 as in the suppression
benchmark. A sample is one UAV at one control step that is AIRBORNE, SUPPRESS, has a front
picture (so it flies its raster layer, ``TacticConfig.layer_height_m``), is more than
``--lake-margin`` from every lake (the refill dip leaves the layer) and has been SUPPRESS for at
least ``--settle`` s (the climb or descent to the layer after a refill is not level flight).
The error is the world's truth (vehicle z minus the terrain under it) minus the layer height.
This is the tracking error e of ``tactics.raster_layers`` (docs/suppression.md "Collisions").
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from pathlib import Path

import numpy as np


def measure(
    scenario: str,
    uavs: int = 6,
    seed: int = 1,
    tactic: str = "head",
    duration_s: float = 200.0,
    lake_margin_m: float = 150.0,
    settle_s: float = 5.0,
) -> dict:
    from fire_uav_agent.testing.harness import Harness, scenario_path
    from fire_uav_common.constants import Objective, VehicleStatus
    from fire_uav_common.scenario import load_scenario

    sc = load_scenario(scenario_path(scenario))
    sc = dataclasses.replace(
        sc,
        mission=dataclasses.replace(sc.mission, tactic=tactic, monitors_per_fire=0),
        timing=dataclasses.replace(sc.timing, max_duration_s=duration_s),
    )
    h = Harness(sc, seed=seed, uav_count=uavs)
    T = sc.timing.control_period_s
    since: dict[int, float] = {}  # uav -> time it became SUPPRESS
    err: dict[int, list[float]] = {i: [] for i in range(h.world.uav_count)}
    while not h.world.complete:
        r = h.step()
        t = h.step_index * T
        for v in r.vehicles:
            a, out = h.agents[v.uav_id], h.outputs[v.uav_id]
            if out is None or v.status != VehicleStatus.AIRBORNE or out.state.objective != Objective.SUPPRESS:
                since.pop(v.uav_id, None)
                continue
            since.setdefault(v.uav_id, t)
            if a.front is None or t - since[v.uav_id] < settle_s:
                continue
            if any(
                math.hypot(v.x_m - k.x_m, v.y_m - k.y_m) < k.diameter_m / 2 + lake_margin_m for k in sc.lakes
            ):
                continue
            agl = v.z_m - float(sc.terrain.elevation(v.x_m, v.y_m))
            err[v.uav_id].append(agl - a.tactic.layer_height_m(v.uav_id))

    def stats(e: list[float]) -> dict:
        x = np.abs(np.asarray(e))
        if x.size == 0:
            return {"samples": 0}
        return {
            "samples": int(x.size),
            "mean_m": round(float(np.mean(e)), 3),
            "p50_abs_m": round(float(np.percentile(x, 50)), 3),
            "p99_abs_m": round(float(np.percentile(x, 99)), 3),
            "max_abs_m": round(float(x.max()), 3),
        }

    t0 = h.agents[0].tactic
    return {
        "scenario": scenario,
        "uavs": uavs,
        "seed": seed,
        "tactic": tactic,
        "duration_s": duration_s,
        "layers_m": sorted({t0.layer_height_m(i) for i in range(uavs)}),
        "all": stats([x for e in err.values() for x in e]),
        "per_uav": {i: {"layer_m": t0.layer_height_m(i), **stats(e)} for i, e in err.items()},
    }


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(
        prog="python -m fire_bench.height_tracking", description=__doc__.split("\n")[0]
    )
    p.add_argument("scenario", nargs="?", default="grass_brush_hill")
    p.add_argument("--uavs", type=int, default=6)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--tactic", default="head")
    p.add_argument("--duration", type=float, default=200.0, help="mission time [s]")
    p.add_argument("--lake-margin", type=float, default=150.0, help="[m] beyond the lake's shore")
    p.add_argument("--settle", type=float, default=5.0, help="[s] SUPPRESS for this long first")
    p.add_argument("--json", type=Path, default=None)
    a = p.parse_args(argv)
    if a.uavs < 1:
        raise SystemExit(f"--uavs must be >= 1, got {a.uavs}")
    if not a.duration > 0:
        raise SystemExit(f"--duration must be > 0, got {a.duration}")
    r = measure(a.scenario, a.uavs, a.seed, a.tactic, a.duration, a.lake_margin, a.settle)
    text = json.dumps(r, indent=2)
    if a.json is not None:
        a.json.write_text(text + "\n")
    print(text, file=sys.stdout)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
