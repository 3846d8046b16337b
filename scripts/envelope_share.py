#!/usr/bin/env python3
"""A mission's figures and the share of its flight beyond a fixed-wing envelope (docs/airframes.md).

Runs the mission in one process (``fire_mission.inprocess``: the real World and Agents, no DDS)
and, from the world's truth at every control step, counts the airborne samples that turn harder
than a bank limit allows (|omega| > g tan(phi_max) / v; Beard & McLain Eq. 9.14). Prints
completion, collisions, closest approach, landing error, fires out, and the share beyond 60 deg
and beyond the airframe's own bank limit (when it has one). Prints, no asserts.

Usage: .venv/bin/python scripts/envelope_share.py [SCENARIO] [--uavs 5] [--seed 1]
       [--set uavs.vehicle_model=coordinated_turn] [--bank-deg 60]
"""

from __future__ import annotations

import argparse
import sys

import yaml
from fire_bench.envelope import envelope_share
from fire_mission.inprocess import run_inprocess
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import ScenarioError, load_scenario


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("scenario", nargs="?", default="ff_two_fires")
    p.add_argument("--uavs", type=int, default=5)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE")
    p.add_argument("--bank-deg", type=float, default=60.0, help="a bank limit to measure against [deg]")
    a = p.parse_args(argv)
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
    banks = [a.bank_deg]
    if sc.uavs.airframe is not None:
        banks.append(sc.uavs.airframe.bank_max_deg)
    for b in banks:
        e = envelope_share(samples, b)
        print(
            f"beyond a {b:g} deg bank: {e.beyond} of {e.airborne} airborne truth samples "
            f"({100 * e.share:.1f} %); hardest needs {e.max_bank_deg:.1f} deg"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
