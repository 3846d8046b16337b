"""A mission in one process: the real World and Agents on the lockstep harness, no ROS, no DDS.

``run_inprocess(scenario, uavs=, seed=, overrides=)`` steps
``fire_uav_agent.testing.harness.Harness`` until the world reports the mission complete and
returns the same ``summary.json`` dict as ``scripts/run_mission`` (built by the same
:class:`~fire_mission.summary.LiveSummary` from the world's events and truth). Deterministic for
a scenario and seed, and about 10x faster than the process fleet: the benchmarks of FF Table I
and Figs. 14-15 use it.

    python -m fire_mission.inprocess ff_two_fires --uavs 8 --seed 2 [--set mission.prior_fires=known]
    python -m fire_mission.inprocess grass_running --max-duration 120 --json summary.json

``--uavs 0`` flies no fleet: the fire burns alone (``World(no_fleet=True)``), as with
``scripts/run_mission SCENARIO --uavs 0``; without ``--uavs`` the scenario's fleet flies.
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from fire_uav_common.constants import FireStatus, VehicleStatus
from fire_uav_common.scenario import Scenario, load_scenario
from fire_uav_common.scenario.ground import geo_summary

from .cli import OneLineParser, mission_exit_status, set_overrides
from .errors import MissionError
from .summary import LiveEvent, LiveSummary, table

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
    uavs: int | None = None,
    seed: int | None = None,
    overrides: Mapping[str, Any] | None = None,
    max_steps: int | None = None,
    on_step: Callable[[Any], None] | None = None,
) -> dict:
    """Run one mission on the harness; returns its summary dict (``outcome`` complete / time_limit).

    ``uavs`` None: the scenario's fleet; 0: no fleet, the fire burns alone (the world with
    ``no_fleet``, as the process runner starts it for ``--uavs 0``). ``on_step`` is called with
    every step's ``fire_world_sim.world.StepResult`` (the truth at the control rate)."""
    from fire_uav_agent.testing.harness import Harness
    from fire_world_sim.world import World

    if uavs is not None and uavs < 0:
        raise MissionError(f"uavs must be >= 0 (0: the fire alone), got {uavs}")
    sc = (
        scenario if isinstance(scenario, Scenario) else load_scenario(_resolve(scenario), overrides=overrides)
    )
    wall0 = time.monotonic()
    h: Harness | None = None
    world: World
    if uavs == 0:
        world = World(sc, seed, no_fleet=True)
    else:
        h = Harness(sc, seed, uavs or 0)  # the harness reads 0 as the scenario's fleet
        world = h.world
    n = world.uav_count
    summary = LiveSummary(uav_count=n, raster=sc.fires.model == "raster")
    summary.home_xy = {i: (p[0], p[1]) for i, p in enumerate(sc.uav_start_poses(n))}
    if n >= 2:  # the agents apply the scenario's link outages themselves
        summary.outages = [(o.from_id, o.to_id, o.start_s, o.end_s) for o in sc.comms.outages]
    steps = 0
    seen = 0
    events: list = []
    while not world.complete and (max_steps is None or steps < max_steps):
        if h is not None:
            r = h.step()
            events = h.events
        else:
            r = world.step({})
            events += r.events
        steps += 1
        if on_step is not None:
            on_step(r)
        for e in events[seen:]:
            summary.add(
                LiveEvent(
                    e.stamp_ns * 1e-9, int(e.type), e.uav_id, -1, e.fire_id, e.value, e.detail, e.x_m, e.y_m
                )
            )
        seen = len(events)
        summary.observe_truth(r.min_separation_m, r.collisions)
        summary.mission_time_s = r.stamp_ns * 1e-9
        summary.fires_total = len(r.fires)
        summary.fires_active = sum(1 for f in r.fires if f.status == FireStatus.ACTIVE)
        summary.vehicles_alive = sum(1 for v in r.vehicles if v.status != VehicleStatus.CRASHED)
        summary.vehicles_landed = sum(1 for v in r.vehicles if v.status == VehicleStatus.LANDED)
        summary.add_truth(  # as the runner does from every /world/truth (burned area, containment)
            summary.mission_time_s, [(float(f.area_m2), f.status == FireStatus.ACTIVE) for f in r.fires]
        )
    for uid, out in enumerate(h.outputs if h is not None else []):
        if out is not None:
            st = out.state
            summary.packets[uid] = (st.packets_received, st.packets_lost, st.packets_rejected)
            summary.objective[uid] = int(st.objective)
            summary.alive_view[uid] = list(st.alive_peers)
    fire_type = world.fires.fire_type_grid()
    if fire_type is not None:  # as the runner reads the world's last /world/fire_type
        summary.add_fire_types(fire_type)
    outcome = "complete" if summary.complete_success else "time_limit"
    d = summary.as_dict(outcome=outcome, wall_s=time.monotonic() - wall0, steps=steps)
    d["seed"] = world.seed
    d["scenario"] = sc.name
    d["runner"] = "inprocess"
    geo = geo_summary(sc, uavs)
    if geo is not None:  # a scenario on a landscape: positions in degrees too
        d["geo"] = geo
    if sc.notes:  # e.g. water bodies of a landscape too small to refill from
        d["scenario_notes"] = list(sc.notes)
    return d


def main(argv: list[str] | None = None) -> int:
    p = OneLineParser(prog="fire_mission.inprocess", description=__doc__.split("\n\n")[0])
    p.add_argument("scenario", help="scenario name (under fire_world_sim/scenarios) or YAML path")
    p.add_argument(
        "--uavs", type=int, default=None, help="fleet size (default: the scenario's; 0: the fire burns alone)"
    )
    p.add_argument("--seed", type=int, default=None)
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE", help="scenario override")
    p.add_argument(
        "--max-duration",
        type=float,
        default=None,
        help="stop the mission after this many seconds (default: the scenario's time limit); "
        "as with scripts/run_mission, a mission stopped here exits 0, one that runs out of the "
        "scenario's own limit exits 1",
    )
    p.add_argument("--json", type=Path, help="write summary.json here")
    a = p.parse_args(argv)
    if a.uavs is not None and a.uavs < 0:
        p.error(f"--uavs must be >= 0 (0: the fire alone), got {a.uavs}")
    if a.max_duration is not None and not a.max_duration > 0:
        p.error(f"--max-duration must be > 0 s, got {a.max_duration}")
    ov = set_overrides(p, a.set)
    if a.max_duration is not None:
        ov["timing.max_duration_s"] = a.max_duration
    from fire_uav_common.scenario import ScenarioError
    from fire_world_sim.errors import ConfigError

    try:
        d = run_inprocess(a.scenario, uavs=a.uavs, seed=a.seed, overrides=ov)
    except (FileNotFoundError, ScenarioError, ConfigError) as e:  # the scenario or fleet asked for
        p.error(str(e))
    if a.json:
        a.json.write_text(json.dumps(d, indent=2) + "\n")
    print(table(d), file=sys.stderr)
    return mission_exit_status(str(d["outcome"]), int(d["uav_count"]), a.max_duration)


if __name__ == "__main__":
    sys.exit(main())
