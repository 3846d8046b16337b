#!/usr/bin/env python3
"""A mission's figures and the share of its flight beyond a fixed-wing envelope (docs/airframes.md).

Runs the mission in one process (``fire_mission.inprocess``: the real World and Agents, no DDS)
and, from the world's truth at every control step, counts the airborne samples that turn harder
than a bank limit allows (|omega| > g tan(phi_max) / v; Beard & McLain Eq. 9.14). Prints
completion, collisions, closest approach, landing error, fires out, and the share beyond 60 deg
and beyond the airframe's own bank limit (when it has one). Also, over the airborne samples: the
error between the commanded turn rate (as the world clamps it) and the flown one, and the agents'
EKF consistency, the normalised estimation error squared NEES = e^T P^-1 e of s = (x, y, z, yaw)
against the truth (mean 4 for a consistent filter; Bar-Shalom, Li & Kirubarajan, *Estimation with
Applications to Tracking and Navigation*, 2001, sec. 5.4), and the largest horizontal estimation
error. On a raster fire also the tactic, the burned area at the end, the time to containment and
the refills (``mission.tactic`` chooses the tactic: ``--set mission.tactic=flank``). ``--json``
writes the mission's summary dict. Prints, no asserts.

With ``--bag RUN/bag`` it reads the samples from a recorded mission's ``/world/truth`` instead
(the bank figures only; its scenario from the bag for the airframe's own limit).

Usage: .venv/bin/python scripts/envelope_share.py [SCENARIO] [--uavs 5] [--seed 1]
       [--set uavs.vehicle_model=coordinated_turn] [--bank-deg 60] [--json summary.json]
       .venv/bin/python scripts/envelope_share.py --bag runs/latest/bag [--bank-deg 60]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import fire_uav_agent.testing.harness as harness_mod
import fire_uav_recording as bag_io
import numpy as np
import yaml
from fire_bench.envelope import envelope_share
from fire_mission.cli import OneLineParser, set_overrides
from fire_mission.inprocess import run_inprocess
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.constants import VehicleStatus
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
    p.add_argument("--json", type=Path, help="write the mission's summary dict here")
    a = p.parse_args(argv)
    if a.bag:
        return from_bag(p, a.bag, a.bank_deg)
    overrides = set_overrides(p, a.set)
    try:
        sc = load_scenario(scenario_path(a.scenario), overrides=overrides)
    except (FileNotFoundError, ScenarioError) as e:
        p.error(str(e))
    samples: list[tuple[int, float, float]] = []
    kept: list[harness_mod.Harness] = []
    est = EstimateStats()

    def on_step(r) -> None:
        samples.extend((v.status, v.v_lin_mps, v.omega_z_radps) for v in r.vehicles)
        est.add(r, kept[0])

    with keep_harness(kept):
        s = run_inprocess(sc, uavs=a.uavs, seed=a.seed, on_step=on_step)
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
    if sc.fires.model == "raster":
        print(raster_line(s, sc.mission.tactic))
    print_shares(samples, a.bank_deg, sc.uavs.airframe)
    est.print()
    if a.json:
        a.json.write_text(json.dumps(s, indent=2) + "\n")
    return 0


def raster_line(s: dict, tactic: str) -> str:
    """The raster fire's figures of a summary dict: tactic, burned area at the end, containment, refills."""
    area = s.get("burned_area_m2")
    burned = "n/a" if area is None else f"{area / 1e4:.2f} ha"
    t = s.get("contained_at_s")
    contained = "not contained" if t is None else f"contained at {t:.1f} s"
    return (
        f"raster fire, tactic {tactic}: burned area {burned} at {s['mission_time_s']:.1f} s, {contained}, "
        f"refills {s['refills']}"
    )


@contextmanager
def keep_harness(kept: list) -> Iterator[None]:
    """The in-process runner's harness, appended to ``kept`` when it is made (its agents' EKFs)."""
    base = harness_mod.Harness

    class Kept(base):  # type: ignore[misc, valid-type]
        def __post_init__(self) -> None:
            super().__post_init__()
            kept.append(self)

    harness_mod.Harness = Kept  # type: ignore[misc]
    try:
        yield
    finally:
        harness_mod.Harness = base  # type: ignore[misc]


class EstimateStats:
    """Turn-rate error and EKF consistency over the airborne truth samples (module doc)."""

    def __init__(self) -> None:
        self.turn_err: list[float] = []
        self.nees: list[float] = []
        self.pos_err = 0.0

    def add(self, r, h: harness_mod.Harness) -> None:
        for v in r.vehicles:
            if v.status != VehicleStatus.AIRBORNE:
                continue
            self.turn_err.append(abs(h.world.vehicles[v.uav_id].omega_z_radps - v.omega_z_radps))
            ekf = h.agents[v.uav_id].ekf
            e = np.array([v.x_m, v.y_m, v.z_m, v.yaw_rad]) - ekf.s
            e[3] = math.remainder(float(e[3]), math.tau)
            self.nees.append(float(e @ np.linalg.solve(ekf.P, e)))
            self.pos_err = max(self.pos_err, math.hypot(e[0], e[1]))

    def print(self) -> None:
        if not self.nees:
            return
        te = np.array(self.turn_err)
        ne = np.array(self.nees)
        print(
            f"commanded - flown turn rate: rms {math.sqrt(float(np.mean(te**2))):.3f} rad/s, "
            f"max {te.max():.3f} rad/s over {te.size} airborne samples"
        )
        print(
            f"EKF NEES (x, y, z, yaw): mean {ne.mean():.2f} (4 if consistent), "
            f"{100 * float(np.mean(ne > 9.49)):.1f} % above the 95 % chi2(4) bound 9.49; "
            f"largest horizontal error {self.pos_err:.2f} m"
        )


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
