#!/usr/bin/env python3
"""A mission's figures and the share of its flight beyond a fixed-wing envelope (docs/airframes.md).

Runs the mission in one process (``fire_mission.inprocess``: the real World and Agents, no DDS)
and, from the world's truth at every control step, counts the airborne samples that turn harder
than a bank limit allows (|omega| > g tan(phi_max) / v; Beard & McLain Eq. 9.14). Prints
completion, collisions, closest approach, landing error, fires out, and the share beyond 60 deg
and beyond the airframe's own bank limit (when it has one). Prints, no asserts.

With ``--bag RUN/bag`` it reads the samples from a recorded mission's ``/world/truth`` instead
(the bank figures only; its scenario from the bag for the airframe's own limit).

Usage: .venv/bin/python scripts/envelope_share.py [SCENARIO] [--uavs 5] [--seed 1]
       [--set uavs.vehicle_model=coordinated_turn] [--bank-deg 60]
       .venv/bin/python scripts/envelope_share.py --bag runs/latest/bag [--bank-deg 60]
"""

from __future__ import annotations

import argparse
import sys

import fire_uav_recording as bag_io
import yaml
from fire_bench.envelope import envelope_share
from fire_mission.cli import OneLineParser
from fire_mission.inprocess import run_inprocess
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import Airframe, ScenarioError, load_scenario, scenario_from_dict
from fire_uav_common.topics import WORLD_TRUTH


def main(argv: list[str] | None = None) -> int:
    p = OneLineParser(prog="envelope_share.py", description=__doc__.split("\n\n")[0])
    p.add_argument("scenario", nargs="?", default="ff_two_fires")
    p.add_argument("--uavs", type=int, default=5)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE")
    p.add_argument("--bank-deg", type=float, default=60.0, help="a bank limit to measure against [deg]")
    p.add_argument("--bag", help="read /world/truth of this recorded mission instead of running one")
    a = p.parse_args(argv)
    if a.bag:
        return from_bag(p, a.bag, a.bank_deg)
    overrides = {}
    for kv in a.set:
        if "=" not in kv:
            p.error(f"--set {kv!r}: expected FIELD=VALUE")
        k, v = kv.split("=", 1)
        overrides[k] = yaml.safe_load(v)
    try:
        sc = load_scenario(scenario_path(a.scenario), overrides=overrides)
    except (FileNotFoundError, ScenarioError) as e:
        p.error(str(e))
    samples: list[tuple[int, float, float]] = []
    s = run_inprocess(
        sc,
        uavs=a.uavs,
        seed=a.seed,
        on_step=lambda r: samples.extend((v.status, v.v_lin_mps, v.omega_z_radps) for v in r.vehicles),
    )
    fires_out = s["fires_total"] - s["fires_active_at_end"]
    land = s["landing_error_m"]
    print(f"scenario {sc.name}, model {sc.uavs.vehicle_model}, uavs {a.uavs}, seed {a.seed}")
    print(f"outcome {s['outcome']} at {s['mission_time_s']:.1f} s: {s['detail']}")
    print(f"fires out {fires_out}/{s['fires_total']}, drops {s['drops_total']}, hit rate {s['hit_rate']}")
    print(
        f"collisions {s['collisions']}, closest approach {s['min_separation_m']} m, crashes {len(s['crashes'])}"
    )
    print(
        f"landed {len(s['landed'])}/{a.uavs}, landing error max {max(land.values(), default=float('nan')):.2f} m"
    )
    print_shares(samples, a.bank_deg, sc.uavs.airframe)
    return 0


def print_shares(samples: list[tuple[int, float, float]], bank_deg: float, airframe: Airframe | None) -> None:
    banks = [bank_deg] + ([airframe.bank_max_deg] if airframe is not None else [])
    for b in banks:
        e = envelope_share(samples, b)
        print(
            f"beyond a {b:g} deg bank: {e.beyond} of {e.airborne} airborne truth samples "
            f"({100 * e.share:.1f} %); hardest needs {e.max_bank_deg:.1f} deg"
        )


def from_bag(p: argparse.ArgumentParser, path: str, bank_deg: float) -> int:
    samples: list[tuple[int, float, float]] = []
    try:
        with bag_io.open_bag(path, salvage=True) as bag:
            text = dict(bag.custom_data).get(bag_io.KEY_SCENARIO_YAML, "")
            for _topic, _t, msg in bag.messages([WORLD_TRUTH]):
                samples.extend(
                    (int(v.status), float(v.v_lin_mps), float(v.omega_z_radps)) for v in msg.vehicles
                )
    except bag_io.BagError as e:
        p.error(str(e))
    airframe = None
    if text:
        try:
            airframe = scenario_from_dict(yaml.safe_load(text), file=f"{path} (scenario)").uavs.airframe
        except ScenarioError as e:
            p.error(str(e))
    print(f"bag {path}: {len(samples)} vehicle truth samples")
    print_shares(samples, bank_deg, airframe)
    return 0


if __name__ == "__main__":
    sys.exit(main())
