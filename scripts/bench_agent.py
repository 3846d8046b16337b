#!/usr/bin/env python3
"""Agent benchmarks without ROS: EKF error after convergence vs FF V-A, CPU time per control step.

Runs the pure Agent fleet in fire_uav_agent.minisim (FF Fig. 3 layout: lake (50, 50), fires
(300, 400) sigma 50 and (450, 50) sigma 20, UAVs at x = 50, y = 250 + 30 i). Prints, no asserts.
Usage: .venv/bin/python scripts/bench_agent.py [--duration 120]
"""

import argparse
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

import numpy as np  # noqa: E402
from fire_uav_agent.agent_core import AgentConfig  # noqa: E402
from fire_uav_agent.minisim import MiniWorld, SimFire  # noqa: E402
from fire_uav_common.terrain import Lake  # noqa: E402


def fleet(n: int) -> list[AgentConfig]:
    return [
        AgentConfig(uav_id=i, uav_count=n, lakes=(Lake(50.0, 50.0, 90.0),),
                    start_pose=(50.0, 250.0 + 30.0 * i, 0.0, -1.5707963), takeoff_interval_s=2.0)
        for i in range(n)
    ]  # fmt: skip


def fires() -> list[SimFire]:
    return [SimFire(300.0, 400.0, 50.0, -0.5, -0.2), SimFire(450.0, 50.0, 20.0, -0.25, 0.1)]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=120.0, help="sim seconds per run")
    a = ap.parse_args()
    for n in (5, 14):
        w = MiniWorld(fleet(n), fires(), seed=1)
        cpu = []
        steps = int(a.duration / w.T)
        for _ in range(steps):
            t0 = time.process_time()
            w.step()
            cpu.append((time.process_time() - t0) / n)
        e = np.array(w.errors)
        conv = e[e[:, 5] > a.duration / 3]  # "after one third of the simulation" (FF V-A a)
        ax = np.abs(conv[:, :4])
        print(f"\n== {n} UAVs, {a.duration:.0f} s sim, {len(conv)} airborne agent-steps after t > T/3")
        for name, col, ref in (
            ("|x| [m]", 0, 1.0),
            ("|y| [m]", 1, 1.0),
            ("|z| [m]", 2, 0.25),
            ("|yaw| [rad]", 3, 0.03),
        ):
            p50, p90, p99 = np.percentile(ax[:, col], [50, 90, 99])
            frac = float(np.mean(ax[:, col] <= ref))
            print(
                f"  {name:12s} p50 {p50:.3f}  p90 {p90:.3f}  p99 {p99:.3f}   within FF bound {ref}: {frac:.1%}"
            )
        c = np.array(cpu) * 1e3
        print(
            f"  CPU per agent step (incl. its share of the mini world) [ms]: mean {c.mean():.2f}  "
            f"p50 {np.median(c):.2f}  p99 {np.percentile(c, 99):.2f}"
        )
        print(f"  drops {w.drops}, fires out {[f.out for f in w.fires]}")
        # pure agent step only
        agent = w.agents[0]
        from fire_uav_agent.agent_core import Bundle
        from fire_uav_agent.estimation import Samples

        t0 = time.process_time()
        reps = 200
        for r in range(reps):
            b = Bundle(w.step_k + 1 + r, (w.step_k + 2 + r) * w.T, Samples(), np.zeros((0, 4)), 2000.0, 1)
            agent.step(b, [])
        print(
            f"  pure Agent.step (no samples, {n - 1} known peers): {(time.process_time() - t0) / reps * 1e3:.2f} ms"
        )


if __name__ == "__main__":
    main()
