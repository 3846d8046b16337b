#!/usr/bin/env python3
"""Agent benchmarks without ROS: EKF error after convergence vs FF V-A, CPU time per agent step.

Runs the in-process harness (``fire_uav_agent.testing.harness``: the real World and the real
Agents, no DDS) on ``ff_two_fires`` (FF Fig. 3 layout: lake (50, 50), fires (300, 400) sigma 50
and (450, 50) sigma 20, UAVs at x = 50, y = 250 + 30 i) with 5 and 14 UAVs. The estimate error is
each airborne agent's published state minus the world's truth at the same stamp. Prints, no asserts.
Usage: .venv/bin/python scripts/bench_agent.py [--duration 120]
"""

import argparse
import time

import numpy as np
from fire_uav_agent.agent_types import Bundle
from fire_uav_agent.estimation import Samples
from fire_uav_agent.testing.harness import Harness, scenario_path
from fire_uav_common.angles import wrap_angle
from fire_uav_common.constants import EventType, FireStatus, VehicleStatus
from fire_uav_common.stamps import ns_to_s

FF_BOUNDS = (("|x| [m]", 1.0), ("|y| [m]", 1.0), ("|z| [m]", 0.25), ("|yaw| [rad]", 0.03))  # FF V-A a


def timed_agents(h: Harness, cpu_s: list[float]) -> None:
    """Wrap every agent's ``step`` so its process time [s] is appended to ``cpu_s``."""
    for agent in h.agents:
        step = agent.step

        def timed(bundle, inbox, _step=step):  # type: ignore[no-untyped-def]
            t0 = time.process_time()
            out = _step(bundle, inbox)
            cpu_s.append(time.process_time() - t0)
            return out

        agent.step = timed  # type: ignore[method-assign]


def run(n: int, duration_s: float) -> None:
    h = Harness.from_file(scenario_path("ff_two_fires"), seed=1, uav_count=n)
    T = h.scenario.timing.control_period_s
    agent_cpu: list[float] = []
    round_cpu: list[float] = []
    timed_agents(h, agent_cpu)
    errors = []  # (x, y, z, yaw, t_s) per airborne agent-step
    for _ in range(int(round(duration_s / T))):
        t0 = time.process_time()
        r = h.step()
        round_cpu.append(time.process_time() - t0)
        t_s = ns_to_s(r.stamp_ns)
        for v in r.vehicles:
            out = h.outputs[v.uav_id]
            if out is None or v.status != VehicleStatus.AIRBORNE:
                continue
            if abs(out.state.stamp_s - t_s) > 1e-9:
                raise RuntimeError(f"uav {v.uav_id}: estimate at {out.state.stamp_s} s, truth at {t_s} s")
            x, y, z, yaw = (float(c) for c in out.state.s)
            errors.append((x - v.x_m, y - v.y_m, z - v.z_m, wrap_angle(yaw - v.yaw_rad), t_s))
        if h.world.complete:
            break
    e = np.array(errors).reshape(-1, 5)
    conv = e[e[:, 4] > duration_s / 3]  # "after one third of the simulation" (FF V-A a)
    ax = np.abs(conv[:, :4])
    print(f"\n== {n} UAVs, {duration_s:.0f} s sim, {len(conv)} airborne agent-steps after t > T/3")
    for col, (name, ref) in enumerate(FF_BOUNDS):
        if len(ax) == 0:
            print(f"  {name:12s} no airborne agent-steps")
            continue
        p50, p90, p99 = np.percentile(ax[:, col], [50, 90, 99])
        frac = float(np.mean(ax[:, col] <= ref))
        print(f"  {name:12s} p50 {p50:.3f}  p90 {p90:.3f}  p99 {p99:.3f}   within FF bound {ref}: {frac:.1%}")
    c = np.array(agent_cpu) * 1e3
    w = np.array(round_cpu) * 1e3
    print(
        f"  CPU per Agent.step [ms]: mean {c.mean():.2f}  p50 {np.median(c):.2f}  p99 {np.percentile(c, 99):.2f}"
        f"   (whole lockstep round, world + {n} agents: mean {w.mean():.2f})"
    )
    drops = sum(1 for ev in h.events if ev.type == EventType.DROP)
    fires = h.result.fires if h.result is not None else []
    print(f"  drops {drops}, fires out {[f.status == FireStatus.EXTINGUISHED for f in fires]}")
    # the pure Agent.step: no samples, the fleet's peers known from the run
    agent = h.agents[0]
    k = h.step_index
    reps = 200
    t0 = time.process_time()
    for r_ in range(reps):
        b = Bundle(
            k + r_, (k + 1 + r_) * T, Samples(), np.zeros((0, 4)), 2000.0, int(VehicleStatus.AIRBORNE), T
        )
        agent.step(b, [])
    dt = (time.process_time() - t0) / reps
    print(f"  pure Agent.step (no samples, {n - 1} known peers): {dt * 1e3:.2f} ms")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=120.0, help="sim seconds per run")
    a = ap.parse_args()
    if not a.duration > 0:
        ap.error(f"--duration must be > 0, got {a.duration}")
    for n in (5, 14):
        run(n, a.duration)


if __name__ == "__main__":
    main()
