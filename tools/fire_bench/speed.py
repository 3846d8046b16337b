"""The speed benchmark: this checkout against a base checkout, side by side in one run.

Each measurement runs once under the base checkout's environment and once under this one's,
back to back (base, head, base, head, ... per row), so that both meet the same load of a shared
machine. What is measured is CPU time (user + system of the child process, ``os.wait4``), not
wall time, for the missions in one process; wall-clock steps per second for the DDS fleets
(the lockstep's rate is what users wait for there). The base is any checkout of the project
with its workspace built (``git worktree add ../base <commit> && scripts/bootstrap`` there); the
page names its commit, never its path.

Rows:

- ``inprocess``: ``python -m fire_mission.inprocess SCENARIO --uavs N --seed 1`` (world and
  agents in one process, no DDS): CPU seconds per second of mission, its inverse (times real
  time), and whether the summary is the same as the base's (wall-time fields left out). Those
  include the start-up (imports, numba's kernels, a raster fire's pre-burn), which a 900 s
  mission amortises: the same command at ``timing.max_duration_s`` = :data:`STARTUP_MISSION_S`
  gives the start-up CPU, and "x real time after start-up" is
  ``(mission - STARTUP_MISSION_S) / (CPU - start-up CPU)`` (:func:`after_startup`);
- ``world``: ``fire_bench/speed_probe.py world`` (this checkout's file, run under each
  environment): CPU ms per ``World.step`` at 20 UAVs and a digest of the truth;
- ``dds``: ``python -m fire_mission.runner ff_two_fires --uavs N --no-record --no-report``:
  lockstep steps per wall second once every UAV is airborne (:func:`dds_row`; until session 21
  the rows were the first 15-30 s of mission, inside the takeoff column: at 20 and 30 UAVs only
  the first 8-15 were flying), and the agents' mean RSS [MiB]; also at
  :data:`JSBSIM_DDS_SIZES` UAVs with ``--set uavs.vehicle_model=jsbsim`` (issue [airframe]'s
  figure: 20 JSBSim aircraft at the world's 100 Hz physics, real time is 10 steps/s).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import yaml

HERE = Path(__file__).resolve()
ROOT = HERE.parents[2]

#: in one process: (scenario, UAVs or None for the scenario's, mission seconds or None for all of it)
INPROCESS_CASES: list[tuple[str, int | None, float | None]] = [
    ("ff_two_fires", 5, None),
    ("grass_running", 6, 60.0),
    ("monitor_grass", None, None),
]
#: the issue's targets: times real time in one process, world ms per step at 20, steps/s at 30, RSS
SPEED_TARGETS = {
    "ff_two_fires_x_real_time": 50.0,
    "grass_running_x_real_time": 20.0,
    "world_ms_at_20": 2.0,
    "dds_steps_per_s_at_30": 10.0,
    "agent_rss_mb": 100.0,
}
#: fleet sizes also flown on the ``jsbsim`` backend over DDS (its target: real time at 20)
JSBSIM_DDS_SIZES = [20]
#: [s] after the last takeoff before a DDS row's window opens (the climb to the first layer)
AIRBORNE_MARGIN_S = 5.0
SUMMARY_NOISE = {"wall_time_s", "steps_per_wall_s", "processes", "runner"}  # not the mission
#: [s] of mission the start-up run flies (its own steps are taken out of both sides of the ratio)
STARTUP_MISSION_S = 1.0


def commit_of(root: Path) -> str:
    return subprocess.run(
        ["git", "-C", str(root), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False
    ).stdout.strip()


def _run(root: Path, argv: list[str], timeout_s: float) -> tuple[float, str]:
    """Run ``argv`` under ``root``'s environment (a clean one: its scripts/env.sh only); the
    child's CPU seconds (user + system) and its stdout."""
    env = {k: os.environ[k] for k in ("HOME", "TERM", "LANG") if k in os.environ}
    env["PATH"] = "/usr/local/bin:/usr/bin:/bin"
    cmd = f"cd {_q(root)} && source scripts/env.sh >/dev/null && exec " + " ".join(_q(a) for a in argv)
    with tempfile.TemporaryFile() as out:
        p = subprocess.Popen(["bash", "-c", cmd], stdout=out, stderr=subprocess.DEVNULL, env=env)
        t_end = time.monotonic() + timeout_s
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() > t_end:
                p.kill()
                pid, status, ru = os.wait4(p.pid, 0)
                break
            time.sleep(0.05)
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        text = out.read().decode(errors="replace")
    return ru.ru_utime + ru.ru_stime, text


def _q(s: str | Path) -> str:
    import shlex

    return shlex.quote(str(s))


def _mission_fields(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in SUMMARY_NOISE}


def after_startup(
    mission_s: float | None, cpu_s: float | None, startup_mission_s: float | None, startup_cpu_s: float | None
) -> float | None:
    """Times real time once started: the mission flown after the start-up run's
    (``mission_s - startup_mission_s``) over the CPU spent on it (``cpu_s - startup_cpu_s``);
    None if a figure is missing or the difference is not positive (the run was no longer than
    its start-up: nothing to amortise)."""
    if mission_s is None or cpu_s is None or startup_mission_s is None or startup_cpu_s is None:
        return None
    flown, spent = mission_s - startup_mission_s, cpu_s - startup_cpu_s
    if not (flown > 0 and spent > 0):
        return None
    return round(flown / spent, 1)


def _inprocess_argv(scenario: str, uavs: int | None, duration: float | None, json_path: Path) -> list[str]:
    argv = ["python", "-m", "fire_mission.inprocess", scenario, "--seed", "1", "--json", str(json_path)]
    argv += ["--uavs", str(uavs)] if uavs is not None else []
    if duration is not None:
        argv += ["--set", f"timing.max_duration_s={duration:g}"]
    return argv


def _inprocess_run(root: Path, scenario: str, uavs: int | None, duration: float | None) -> tuple[float, dict]:
    """One in-process mission under ``root``: its CPU seconds and its summary ({} if none)."""
    with tempfile.TemporaryDirectory() as d:
        js = Path(d) / "summary.json"
        cpu, _ = _run(root, _inprocess_argv(scenario, uavs, duration, js), 3600)
        return cpu, json.loads(js.read_text()) if js.is_file() else {}


def inprocess_row(
    roots: dict[str, Path], scenario: str, uavs: int | None, duration: float | None, repeats: int
) -> dict:
    """One scenario in one process under each root, ``repeats`` times alternating (base, head,
    base, head, ...); the least CPU of each root's runs (the load of a shared machine only adds).
    Each repeat also runs the same command for :data:`STARTUP_MISSION_S` of mission (the
    start-up CPU, least of the runs too) for the "x real time after start-up" column."""
    row: dict = {"scenario": scenario, "repeats": repeats}
    summaries = {}
    cpus: dict[str, list[float]] = {tag: [] for tag in roots}
    startup_cpus: dict[str, list[float]] = {tag: [] for tag in roots}
    startup_mission: dict[str, float | None] = {}
    for _ in range(repeats):
        for tag, root in roots.items():
            cpu, summaries[tag] = _inprocess_run(root, scenario, uavs, duration)
            cpus[tag].append(cpu)
            cpu0, s0 = _inprocess_run(root, scenario, uavs, STARTUP_MISSION_S)
            startup_cpus[tag].append(cpu0)
            startup_mission[tag] = s0.get("mission_time_s")
    for tag in roots:
        s = summaries[tag]
        cpu = min(cpus[tag])
        cpu0 = min(startup_cpus[tag])
        row["uavs"] = s.get("uav_count", uavs)
        mt = s.get("mission_time_s")
        row[f"{tag}_cpu_s"] = round(cpu, 2)
        row["mission_time_s"] = mt
        row[f"{tag}_cpu_per_mission_s"] = round(cpu / mt, 4) if mt else None
        row[f"{tag}_x_real_time"] = round(mt / cpu, 1) if mt and cpu else None
        row[f"{tag}_startup_cpu_s"] = round(cpu0, 2)
        row[f"{tag}_x_real_time_after_startup"] = after_startup(mt, cpu, startup_mission[tag], cpu0)
    if "base" in summaries:
        row["summary_same"] = _mission_fields(summaries["base"]) == _mission_fields(summaries["head"])
    return row


def world_row(roots: dict[str, Path], uavs: int, steps: int) -> dict:
    row: dict = {"uavs": uavs, "steps": steps}
    for tag, root in roots.items():
        _, out = _run(
            root,
            [
                "python",
                str(HERE.parent / "speed_probe.py"),
                "world",
                "--uavs",
                str(uavs),
                "--steps",
                str(steps),
            ],
            900,
        )
        lines = [x for x in out.splitlines() if x.startswith("{")]
        r = json.loads(lines[-1]) if lines else {}
        row[f"{tag}_world_ms_per_step"] = round(r["world_ms_per_step"], 3) if r else None
        row[f"{tag}_digest"] = r.get("truth_digest")
    if "base" in roots:
        row["truth_same"] = row.get("base_digest") == row.get("head_digest")
    return row


def _dds_summary(root: Path, uavs: int, mission_s: float, vehicle_model: str) -> dict:
    """summary.json of one lockstep DDS run of ff_two_fires (seed 1) for ``mission_s``, with
    ``probe_ms``: the :class:`CpuProbe` samples taken while it ran."""
    with tempfile.TemporaryDirectory() as d:
        argv = ["python", "-m", "fire_mission.runner", "ff_two_fires", "--uavs", str(uavs), "--seed", "1"]
        argv += ["--max-duration", f"{mission_s:g}", "--quiet", "--no-record", "--no-report", "--out", d]
        if vehicle_model != "ff_paper":
            argv += ["--set", f"uavs.vehicle_model={vehicle_model}"]
        with CpuProbe() as probe:
            _run(root, argv, 1800)
        path = Path(d) / "summary.json"
        summary = json.loads(path.read_text()) if path.is_file() else {}
        summary["probe_ms"] = probe.samples_ms
        return summary


#: the probe's loop: CPU ms of this fixed pure-Python loop, one sample a second, printed
_PROBE_CODE = """
import sys, time
while True:
    t0 = time.process_time()
    acc = 0
    for i in range(300_000):
        acc = (acc * 31 + i) & 0xFFFFFFFF
    print(round(1000 * (time.process_time() - t0), 2), flush=True)
    time.sleep(1.0)
"""
#: base and head probes further apart than this share are flagged: the host's one-core speed differed
PROBE_TOLERANCE = 0.15


class CpuProbe:
    """The host's one-core speed while a fleet runs: a child process that runs a fixed pure-Python
    loop (``fire_bench.bench.machine_probe``'s) once a second and reports the loop's *CPU* time.

    Why: on this shared 2-core machine a fixed pure-Python loop (3,000,000 additions, CPU time)
    took 122 to 213 ms from one ten-second sample to the next, idle, no process of ours running
    (session 27); the 30-UAV DDS rate moves by such factors (base and head swapped order between
    two sessions: 12.8 vs 7.9 steps/s one evening, 3.8 vs 11.9 the next, the same two commits).
    CPU time, not wall time, so that the fleet sharing the cores does not count: under a 30-UAV
    fleet that loop took the same CPU as idle (125-143 ms against 122-140 ms). This probe's loop
    is a ~25 ms burst a second, ~2.5 % of one core, the same for base and head. A figure, not a
    correction: no rate is rescaled by it."""

    def __init__(self) -> None:
        self.samples_ms: list[float] = []
        self._p: subprocess.Popen | None = None
        self._out: Any = None

    def __enter__(self) -> CpuProbe:
        self._out = tempfile.TemporaryFile()
        self._p = subprocess.Popen([sys.executable, "-c", _PROBE_CODE], stdout=self._out)
        return self

    def __exit__(self, *exc: object) -> None:
        assert self._p is not None and self._out is not None
        self._p.kill()
        self._p.wait()
        self._out.seek(0)
        for line in self._out.read().decode(errors="replace").split():
            try:
                self.samples_ms.append(float(line))
            except ValueError:
                pass
        self._out.close()


def _median(xs: list[float]) -> float | None:
    xs = sorted(xs)
    n = len(xs)
    if not n:
        return None
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])


def airborne_after_s(uavs: int) -> float:
    """[s] of mission after which every UAV of ff_two_fires is flying: the last takeoff (one per
    ``uavs.takeoff_interval_s``) plus :data:`AIRBORNE_MARGIN_S`. Only airborne vehicles are
    stepped by the world's physics (``Vehicle.substep``), so a window inside the takeoff column
    measures a fleet partly on the ground."""
    scen = yaml.safe_load((ROOT / "ros2_ws/src/fire_world_sim/scenarios/ff_two_fires.yaml").read_text())
    interval = float(scen["uavs"].get("takeoff_interval_s", 2.0))
    return (uavs - 1) * interval + AIRBORNE_MARGIN_S


def _stepping(s: dict) -> tuple[float, float, float | None, float | None] | None:
    """(steps, stepping wall s, world CPU s, agents' mean CPU s) of a summary, over the stepping
    phase (first to last truth message: ``steps_per_wall_s`` and ``cpu_ms_per_step`` are taken
    over it, the start-up left out)."""
    rate, t, dt = s.get("steps_per_wall_s"), s.get("mission_time_s"), s.get("control_period_s", 0.1)
    if not rate or not t:
        return None
    n = t / dt
    procs = s.get("processes", {})
    world = procs.get("world", {}).get("cpu_ms_per_step")
    agents = [
        v["cpu_ms_per_step"] for k, v in procs.items() if k.startswith("agent") and v.get("cpu_ms_per_step")
    ]
    return (
        n,
        n / rate,
        world * n / 1000 if world is not None else None,
        (sum(agents) / len(agents)) * n / 1000 if agents else None,
    )


def dds_row(roots: dict[str, Path], uavs: int, duration: float, vehicle_model: str = "ff_paper") -> dict:
    """Lockstep steps per wall second of ``uavs`` agents over DDS on ``vehicle_model`` (the world's
    vehicle backend, ``uavs.vehicle_model``; ``jsbsim`` steps one JSBSim aircraft and its autopilot
    per UAV at the world's 100 Hz physics), over ``duration`` s of mission once the whole fleet is
    airborne (:func:`airborne_after_s`): two runs, to ``t_air`` and to ``t_air + duration``, the
    same mission up to ``t_air`` (lockstep, one seed), and the rate of the steps between them. Also
    the world's and an agent's CPU ms per step over that window, the agents' mean RSS at the
    end of the longer run, and the host's one-core speed over both runs (``probe_ms``, the
    median :class:`CpuProbe` sample); base and head probes more than :data:`PROBE_TOLERANCE`
    apart put a note in ``not_comparable``."""
    t_air = airborne_after_s(uavs)
    row: dict = {
        "uavs": uavs,
        "vehicle_model": vehicle_model,
        "mission_time_s": duration,
        "airborne_from_s": t_air,
    }
    for tag, root in roots.items():
        s0 = _dds_summary(root, uavs, t_air, vehicle_model)
        short = _stepping(s0)
        s = _dds_summary(root, uavs, t_air + duration, vehicle_model)
        full = _stepping(s)
        probe = _median(s0.get("probe_ms", []) + s.get("probe_ms", []))
        row[f"{tag}_probe_ms"] = None if probe is None else round(probe, 1)
        procs = s.get("processes", {})
        rss = [v.get("rss_mb") for k, v in procs.items() if k.startswith("agent") and v.get("rss_mb")]
        row[f"{tag}_agent_rss_mb"] = round(sum(rss) / len(rss), 1) if rss else None
        for key in ("steps_per_s", "world_cpu_ms_per_step", "agent_cpu_ms_per_step"):
            row[f"{tag}_{key}"] = None
        if short is None or full is None:
            continue
        steps = full[0] - short[0]
        if full[1] <= short[1] or steps <= 0:
            _not_a_measure(
                row, f"{tag} steps/s", f"{full[1] - short[1]:.3f} s of wall time for {steps:g} steps"
            )
            continue
        row[f"{tag}_steps_per_s"] = round(steps / (full[1] - short[1]), 2)
        for i, key in ((2, "world"), (3, "agent")):
            a, b = short[i], full[i]
            if a is None or b is None:
                continue
            if b <= a:
                _not_a_measure(row, f"{tag} {key} CPU ms/step", f"{1000 * (b - a) / steps:.3f}")
                continue
            row[f"{tag}_{key}_cpu_ms_per_step"] = round(1000 * (b - a) / steps, 3)
    pb, ph = row.get("base_probe_ms"), row.get("head_probe_ms")
    if pb and ph and abs(pb - ph) > PROBE_TOLERANCE * min(pb, ph):
        note = (
            f"the host's one-core speed differed between base and head (CpuProbe: {pb:g} / {ph:g} ms "
            f"of CPU for the same loop, {100 * (max(pb, ph) / min(pb, ph) - 1):.0f} %): steps/s and CPU "
            "per step not comparable side by side"
        )
        row.setdefault("not_comparable", []).append(note)
        print(f"bench: warning: {uavs} UAVs {vehicle_model}: {note}", file=sys.stderr)
    return row


def _not_a_measure(row: dict, figure: str, value: str) -> None:
    """A difference of the two runs that is not positive is not a measure of the window (the
    longer run spent no more than the shorter: the machine's load changed between them). The
    figure stays empty, and the row says which and what the difference was, so that the page
    shows it instead of printing a negative rate or CPU time."""
    note = f"{figure}: difference of the two runs {value}, not positive (load changed between them?): not a measure"
    row.setdefault("not_measured", []).append(note)
    print(f"bench: warning: {row['uavs']} UAVs {row['vehicle_model']}: {note}", file=sys.stderr)


def bench_speed(base: Path | None, quick: bool, dds_sizes: list[int] | None = None) -> dict:
    """The speed rows, base and head side by side (head only without ``base``)."""
    roots = {"base": base, "head": ROOT} if base is not None else {"head": ROOT}
    out: dict = {
        "head_commit": commit_of(ROOT),
        "base_commit": commit_of(base) if base is not None else None,
        "targets": SPEED_TARGETS,
        "probe_tolerance": PROBE_TOLERANCE,
    }
    out["inprocess"] = [inprocess_row(roots, s, n, d, 2 if quick else 3) for s, n, d in INPROCESS_CASES]
    out["world"] = [world_row(roots, 20, 100 if quick else 300)]
    sizes = dds_sizes if dds_sizes is not None else ([5, 20] if quick else [5, 20, 30])
    out["dds"] = [dds_row(roots, n, 15.0 if quick else 30.0) for n in sizes]
    # issue [airframe]: 20 UAVs on JSBSim at the world's 100 Hz physics keep real time over DDS
    out["dds"] += [dds_row(roots, n, 15.0 if quick else 30.0, "jsbsim") for n in JSBSIM_DDS_SIZES]
    return out
