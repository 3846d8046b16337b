#!/usr/bin/env python3
"""Landings and go-arounds of a fixed-wing mission, from outside the agents (docs/airframes.md).

Runs one mission in process (``fire_mission.inprocess``) and watches every agent's lined-up final
(``Guide.approach``, ``Guide.on_final``) at every control step, from the agent's own estimate (its
EKF) and from the world's truth. It counts, per UAV:

* passes: the final's threshold crossed (along-track 0, estimate) while established on the final
  and airborne; for each, the estimated and the true cross-track error and the height above ground;
* landings: the world's vehicle status going to LANDED, with the estimated and true distance from
  the threshold at that step;
* go-arounds: established on the final, then not, while still airborne (the UAV flew on past the
  threshold, or out of the capture region) - the circuit it then flies is the time lost.

It reads only attributes the base commit has (``approach``, ``on_final``, ``ekf.s``), so it measures
base and branch alike. Prints one line per UAV and a total; ``--json`` writes the summary dict with
a ``landing_probe`` entry. Prints, no asserts.

Usage: .venv/bin/python scripts/landing_probe.py [SCENARIO] [--uavs 5] [--seed 1]
       [--set uavs.vehicle_model=coordinated_turn] [--json F]
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import fire_uav_agent.testing.harness as harness_mod
from fire_bench.envelope import envelope_share
from fire_mission.cli import OneLineParser, set_overrides
from fire_mission.inprocess import run_inprocess
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario import ScenarioError, load_scenario


class Probe:
    """The per-UAV landing record (module doc), fed with every step's truth and the harness."""

    def __init__(self) -> None:
        self.h: harness_mod.Harness | None = None
        self.prev_along: dict[int, float] = {}
        self.prev_final: dict[int, bool] = {}
        self.prev_status: dict[int, int] = {}
        self.uav: dict[int, dict] = {}
        self.samples: list[tuple[int, float, float]] = []  # (status, v [m/s], omega [rad/s]) of the truth
        self._closest_m = float("inf")
        self.closest: dict = {}  # the closest approach: when, which pair, their objectives

    def rec(self, i: int) -> dict:
        return self.uav.setdefault(i, {"passes": [], "landings": [], "go_arounds": []})

    def step(self, r) -> None:
        h = self.h
        assert h is not None
        t = r.stamp_ns * 1e-9
        self.samples.extend((v.status, v.v_lin_mps, v.omega_z_radps) for v in r.vehicles)
        if r.min_separation_m < self._closest_m:
            self._closest_m = float(r.min_separation_m)
            self.closest = {"m": round(self._closest_m, 2), "t_s": round(t, 1), **self._pair(r)}
        for v in r.vehicles:
            i = v.uav_id
            g = h.agents[i].guide
            ap = g.approach
            if ap is None:
                continue
            s = h.agents[i].ekf.s
            along, cross = ap.frame((float(s[0]), float(s[1])))
            t_along, t_cross = ap.frame((v.x_m, v.y_m))
            airborne = v.status == VehicleStatus.AIRBORNE
            on_final = bool(g.on_final)
            rec = self.rec(i)
            pa = self.prev_along.get(i)
            for mark in (-25.0, -10.0):  # the estimated cross-track error as the final passes these
                if airborne and on_final and pa is not None and pa < mark <= along:
                    rec.setdefault(f"cross_at_{-mark:g}m", []).append(round(cross, 2))
            if airborne and on_final and pa is not None and pa < 0.0 <= along:
                rec["passes"].append(
                    {"t_s": round(t, 1), "cross_est_m": round(cross, 2), "cross_true_m": round(t_cross, 2),
                     "z_est_m": round(float(s[2]), 2)}
                )  # fmt: skip
            if v.status == VehicleStatus.LANDED and self.prev_status.get(i) == VehicleStatus.AIRBORNE:
                rec["landings"].append(
                    {"t_s": round(t, 1), "along_est_m": round(along, 2), "cross_est_m": round(cross, 2),
                     "along_true_m": round(t_along, 2), "cross_true_m": round(t_cross, 2)}
                )  # fmt: skip
            if airborne and self.prev_final.get(i) and not on_final:
                rec["go_arounds"].append(
                    {"t_s": round(t, 1), "along_est_m": round(along, 2), "cross_est_m": round(cross, 2)}
                )
            self.prev_along[i] = along
            self.prev_final[i] = on_final
            self.prev_status[i] = v.status

    def _pair(self, r) -> dict:
        """The pair (not crashed) nearest each other at this step, and their objectives."""
        h = self.h
        assert h is not None
        up = [v for v in r.vehicles if v.status != VehicleStatus.CRASHED]
        best: tuple[float, int, int] = (float("inf"), -1, -1)
        for i, a in enumerate(up):
            for b in up[i + 1 :]:
                d = math.dist((a.x_m, a.y_m, a.z_m), (b.x_m, b.y_m, b.z_m))
                if d < best[0]:
                    best = (d, a.uav_id, b.uav_id)
        objs = {}
        for j in best[1:]:
            out = h.outputs[j] if j >= 0 else None
            objs[str(j)] = int(out.state.objective) if out is not None else -1
        return {"pair": list(best[1:]), "objectives": objs}

    def report(self) -> dict:
        out = {}
        for i in sorted(self.uav):
            u = self.uav[i]
            out[str(i)] = {
                **u,
                "n_landings": len(u["landings"]),
                "n_go_arounds": len(u["go_arounds"]),
            }
        return out


def main(argv: list[str] | None = None) -> int:
    p = OneLineParser(prog="landing_probe.py", description=__doc__.split("\n\n")[0])
    p.add_argument("scenario", nargs="?", default="ff_two_fires")
    p.add_argument("--uavs", type=int, default=5)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE")
    p.add_argument("--json", type=Path, help="write the mission's summary dict (with landing_probe) here")
    a = p.parse_args(argv)
    overrides = set_overrides(p, a.set)
    try:
        sc = load_scenario(scenario_path(a.scenario), overrides=overrides)
    except (FileNotFoundError, ScenarioError) as e:
        p.error(str(e))
    probe = Probe()
    base = harness_mod.Harness

    class Kept(base):  # type: ignore[misc, valid-type]
        def __post_init__(self) -> None:
            super().__post_init__()
            probe.h = self

    harness_mod.Harness = Kept  # type: ignore[misc]
    try:
        s = run_inprocess(sc, uavs=a.uavs, seed=a.seed, on_step=probe.step)
    finally:
        harness_mod.Harness = base  # type: ignore[misc]
    rep = probe.report()
    land = s["landing_error_m"]
    print(f"scenario {sc.name}, model {sc.uavs.vehicle_model}, uavs {a.uavs}, seed {a.seed}")
    print(f"outcome {s['outcome']} at {s['mission_time_s']:.1f} s; collisions {s['collisions']}, "
          f"closest {s['min_separation_m']} m; fires out {s['fires_total'] - s['fires_active_at_end']}"
          f"/{s['fires_total']}; landing error max {max(land.values(), default=float('nan')):.2f} m")  # fmt: skip
    n_land = n_ga = 0
    for i, u in rep.items():
        n_land += u["n_landings"]
        n_ga += u["n_go_arounds"]
        passes = ", ".join(f"{p_['cross_est_m']:+.1f}/{p_['cross_true_m']:+.1f}" for p_ in u["passes"])
        print(f"  uav {i}: landings {u['n_landings']}, go-arounds {u['n_go_arounds']}; "
              f"threshold passes cross est/true [m]: {passes or '-'}")  # fmt: skip
    print(f"landings {n_land}, go-arounds {n_ga}; closest approach {probe.closest}")
    bank = {}
    if sc.uavs.airframe is not None:
        e = envelope_share(probe.samples, sc.uavs.airframe.bank_max_deg)
        bank = {"limit_deg": sc.uavs.airframe.bank_max_deg, "beyond": e.beyond, "airborne": e.airborne,
                "hardest_deg": round(e.max_bank_deg, 1)}  # fmt: skip
        print(f"beyond the {bank['limit_deg']:g} deg bank limit: {e.beyond} of {e.airborne} airborne truth "
              f"samples; hardest needs {e.max_bank_deg:.1f} deg")  # fmt: skip
    if a.json:
        s["landing_probe"] = rep
        s["landing_probe_bank"] = bank
        s["landing_probe_closest"] = probe.closest
        a.json.write_text(json.dumps(s, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
