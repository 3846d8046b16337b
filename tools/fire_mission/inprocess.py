"""A mission in one process: the real World and Agents on the lockstep harness, no ROS, no DDS.

``run_inprocess(scenario, uavs=, seed=, overrides=)`` steps
``fire_uav_agent.testing.harness.Harness`` until the world reports the mission complete and
returns the same ``summary.json`` dict as ``scripts/run_mission`` (built by the same
:class:`~fire_mission.summary.LiveSummary` from the world's events and truth). Deterministic for
a scenario and seed, and about 10x faster than the process fleet: the benchmarks of FF Table I
and Figs. 14-15 use it.

    python -m fire_mission.inprocess ff_two_fires --uavs 8 --seed 2 [--set mission.prior_fires=known]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from fire_uav_common.constants import FireStatus, VehicleStatus
from fire_uav_common.scenario import Scenario, load_scenario

from .summary import Event, LiveSummary, table

__all__ = ["run_inprocess", "main"]


def _resolve(scenario: str | Path) -> Path:
    p = Path(scenario)
    if p.suffix in (".yaml", ".yml") or p.is_file():
        return p
    from fire_uav_agent.testing.harness import scenario_path

    return scenario_path(str(scenario))


def run_inprocess(
    scenario: str | Path | Scenario,
    *,
    uavs: int = 0,
    seed: int | None = None,
    overrides: Mapping[str, Any] | None = None,
    max_steps: int | None = None,
) -> dict:
    """Run one mission on the harness; returns its summary dict (``outcome`` complete / time_limit)."""
    from fire_uav_agent.testing.harness import Harness

    sc = (
        scenario if isinstance(scenario, Scenario) else load_scenario(_resolve(scenario), overrides=overrides)
    )
    wall0 = time.monotonic()
    h = Harness(sc, seed, uavs)
    n = h.world.uav_count
    summary = LiveSummary(uav_count=n, raster=sc.fires.model == "raster")
    summary.home_xy = {i: (p[0], p[1]) for i, p in enumerate(sc.uav_start_poses(n))}
    steps = 0
    seen = 0
    while not h.world.complete and (max_steps is None or steps < max_steps):
        r = h.step()
        steps += 1
        for e in h.events[seen:]:
            summary.add(
                Event(
                    e.stamp_ns * 1e-9, int(e.type), e.uav_id, -1, e.fire_id, e.value, e.detail, e.x_m, e.y_m
                )
            )
        seen = len(h.events)
        summary.observe_truth(r.min_separation_m, r.collisions)
        summary.mission_time_s = r.stamp_ns * 1e-9
        summary.fires_total = len(r.fires)
        summary.fires_active = sum(1 for f in r.fires if f.status == FireStatus.ACTIVE)
        summary.vehicles_alive = sum(1 for v in r.vehicles if v.status != VehicleStatus.CRASHED)
        summary.vehicles_landed = sum(1 for v in r.vehicles if v.status == VehicleStatus.LANDED)
        summary.add_truth(  # as the runner does from every /world/truth (burned area, containment)
            summary.mission_time_s, [(float(f.area_m2), f.status == FireStatus.ACTIVE) for f in r.fires]
        )
    for uid, out in enumerate(h.outputs):
        if out is not None:
            st = out.state
            summary.packets[uid] = (st.packets_received, st.packets_lost, st.packets_rejected)
            summary.objective[uid] = int(st.objective)
            summary.alive_view[uid] = list(st.alive_peers)
    outcome = "complete" if summary.complete_success else "time_limit"
    d = summary.as_dict(outcome=outcome, wall_s=time.monotonic() - wall0, steps=steps)
    d["seed"] = h.world.seed
    d["scenario"] = sc.name
    d["runner"] = "inprocess"
    return d


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="fire_mission.inprocess", description=__doc__.split("\n\n")[0])
    p.add_argument("scenario", help="scenario name (under fire_world_sim/scenarios) or YAML path")
    p.add_argument("--uavs", type=int, default=0, help="fleet size (default: the scenario's)")
    p.add_argument("--seed", type=int, default=None)
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE", help="scenario override")
    p.add_argument("--json", type=Path, help="write summary.json here")
    a = p.parse_args(argv)
    import yaml

    ov = {}
    for kv in a.set:
        if "=" not in kv:
            p.error(f"--set {kv!r}: expected FIELD=VALUE")
        k, v = kv.split("=", 1)
        ov[k] = yaml.safe_load(v)
    d = run_inprocess(a.scenario, uavs=a.uavs, seed=a.seed, overrides=ov)
    if a.json:
        a.json.write_text(json.dumps(d, indent=2) + "\n")
    print(table(d), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
