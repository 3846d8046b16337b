"""Where an agent's time goes: cProfile of the agent step alone and of a whole agent process.

``harness``: the real World and Agents in one process (no DDS), ``--steps`` steps of
``--uavs`` UAVs; profiles only the agents' ``Agent.step`` calls and prints the share of each
stage (_estimate/_link/_fuse/_decide/_guide/_compose_output) and the top functions.

``process``: a real mission (``fire_mission.runner``, ``--max-duration`` s of mission time)
with every agent under cProfile (``FIRE_UAV_PROFILE_DIR``, see ``agent_node.main``); prints
agent 0's profile: the executor (rclpy wait set, take, message conversion) against the step.

    python -m fire_bench.profile harness --uavs 10 --steps 300
    python -m fire_bench.profile process --uavs 10 --max-duration 15
"""

from __future__ import annotations

import argparse
import cProfile
import io
import os
import pstats
import subprocess
import sys
import tempfile
import time
from pathlib import Path

STAGES = ("_estimate", "_link", "_fuse", "_decide", "_guide", "_compose_output")


def _stage_table(stats: pstats.Stats, total_s: float, steps: int) -> str:
    rows = []
    for (file, _line, name), (_cc, _nc, _tt, ct, _callers) in stats.stats.items():  # type: ignore[attr-defined]
        if name in STAGES and file.endswith("agent_core.py"):
            rows.append((name, ct))
    rows.sort(key=lambda r: STAGES.index(r[0]))
    out = ["| stage | ms per agent step | share |", "|---|---|---|"]
    for name, ct in rows:
        out.append(f"| {name} | {1000 * ct / steps:.3f} | {ct / total_s:.0%} |")
    return "\n".join(out)


def _top(stats: pstats.Stats, key: str, n: int) -> str:
    buf = io.StringIO()
    stats.stream = buf  # type: ignore[attr-defined]
    stats.sort_stats(key).print_stats(n)
    lines = [ln for ln in buf.getvalue().splitlines() if ln.strip()]
    start = next((i for i, ln in enumerate(lines) if ln.lstrip().startswith("ncalls")), 0)
    return "\n".join(lines[start:])


def profile_harness(uavs: int, steps: int, scenario: str, top: int) -> str:
    from fire_uav_agent.testing import harness as hm

    h = hm.Harness.from_file(hm.scenario_path(scenario), seed=1, uav_count=uavs)
    prof = cProfile.Profile(time.process_time)  # CPU time: the machine is shared
    real_step = hm.Agent.step

    def profiled(self, *a, **kw):
        return prof.runcall(real_step, self, *a, **kw)

    hm.Agent.step = profiled  # type: ignore[method-assign]
    try:
        t0 = time.process_time()
        h.run(steps)
        cpu = time.process_time() - t0
    finally:
        hm.Agent.step = real_step  # type: ignore[method-assign]
    st = pstats.Stats(prof)
    agent_steps = steps * uavs
    total = st.total_tt  # type: ignore[attr-defined]
    return "\n".join(
        [
            f"harness: {scenario}, {uavs} UAVs, {steps} steps; process CPU {cpu:.1f} s, "
            f"in Agent.step {total:.1f} s = {1000 * total / agent_steps:.2f} ms per agent step "
            "(CPU; cProfile overhead included)",
            "",
            _stage_table(st, total, agent_steps),
            "",
            _top(st, "tottime", top),
        ]
    )


def profile_process(uavs: int, max_duration_s: float, scenario: str, top: int) -> str:
    with tempfile.TemporaryDirectory(prefix="fire-profile-") as d:
        env = dict(os.environ, FIRE_UAV_PROFILE_DIR=d)
        env.pop("ROS_DOMAIN_ID", None)
        cmd = [sys.executable, "-m", "fire_mission.runner", scenario, "--uavs", str(uavs), "--seed", "1"]
        cmd += ["--max-duration", str(max_duration_s), "--out", f"{d}/run", "--quiet", "--no-record"]
        cmd += ["--no-report"]
        subprocess.run(cmd, env=env, capture_output=True, text=True, check=False, timeout=1800)
        path = Path(d) / "agent_0.prof"
        if not path.is_file():
            return f"process: no profile written ({path.name} missing); is the workspace sourced?"
        st = pstats.Stats(str(path))
        total = st.total_tt  # type: ignore[attr-defined]
        return "\n".join(
            [
                f"process: {scenario}, {uavs} UAVs, {max_duration_s:g} s of mission time; agent 0 "
                f"spent {total:.1f} s of main-thread CPU in spin (cProfile over time.thread_time; its overhead included)",
                "",
                _top(st, "tottime", top),
                "",
                _top(st, "cumulative", top),
            ]
        )


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="fire_bench.profile", description=__doc__.split("\n\n")[0])
    p.add_argument("what", choices=["harness", "process"])
    p.add_argument("--uavs", type=int, default=10)
    p.add_argument("--steps", type=int, default=300, help="harness: steps")
    p.add_argument("--max-duration", type=float, default=15.0, help="process: mission seconds")
    p.add_argument("--scenario", default="ff_two_fires")
    p.add_argument("--top", type=int, default=25)
    a = p.parse_args(argv)
    if a.uavs < 1 or a.steps < 1:
        p.error(f"--uavs and --steps must be >= 1, got {a.uavs} and {a.steps}")
    if a.what == "harness":
        print(profile_harness(a.uavs, a.steps, a.scenario, a.top))
    else:
        print(profile_process(a.uavs, a.max_duration, a.scenario, a.top))
    return 0


if __name__ == "__main__":
    sys.exit(main())
