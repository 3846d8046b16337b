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


def _run(root: Path, argv: list[str], timeout_s: float, harness: Path | None = None) -> tuple[float, str]:
    """Run ``argv`` under ``root``'s environment (a clean one: its scripts/env.sh only); the
    child's CPU seconds (user + system) and its stdout. ``harness``: a checkout whose ``tools``
    come first on the path (the mission runner that measures, over ``root``'s workspace)."""
    env = {k: os.environ[k] for k in ("HOME", "TERM", "LANG") if k in os.environ}
    env["PATH"] = "/usr/local/bin:/usr/bin:/bin"
    first = f'export PYTHONPATH={_q(harness / "tools")}:"$PYTHONPATH" && ' if harness is not None else ""
    cmd = f"cd {_q(root)} && source scripts/env.sh >/dev/null && {first}exec " + " ".join(_q(a) for a in argv)
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


def _inprocess_run(
    root: Path, scenario: str, uavs: int | None, duration: float | None
) -> tuple[float, dict, float | None]:
    """One in-process mission under ``root``: its CPU seconds, its summary ({} if none) and the
    host's one-core speed while it ran (the median :class:`CpuProbe` sample, None if none)."""
    with tempfile.TemporaryDirectory() as d:
        js = Path(d) / "summary.json"
        with CpuProbe() as probe:
            cpu, _ = _run(root, _inprocess_argv(scenario, uavs, duration, js), 3600)
        return cpu, json.loads(js.read_text()) if js.is_file() else {}, _median(probe.samples_ms)


def inprocess_row(
    roots: dict[str, Path], scenario: str, uavs: int | None, duration: float | None, repeats: int
) -> dict:
    """One scenario in one process under each root, ``repeats`` times alternating (base, head,
    base, head, ...); the least CPU of each root's runs (the load of a shared machine only adds).
    Each repeat also runs the same command for :data:`STARTUP_MISSION_S` of mission (the
    start-up CPU, least of the runs too) for the "x real time after start-up" column. With each
    side's least CPU, the host's one-core speed during that run (``probe_ms``, :class:`CpuProbe`);
    base and head more than :data:`PROBE_TOLERANCE` apart put a note in ``not_comparable``."""
    row: dict = {"scenario": scenario, "repeats": repeats}
    summaries = {}
    cpus: dict[str, list[tuple[float, float | None]]] = {tag: [] for tag in roots}
    startup_cpus: dict[str, list[float]] = {tag: [] for tag in roots}
    startup_mission: dict[str, float | None] = {}
    for _ in range(repeats):
        for tag, root in roots.items():
            cpu, summaries[tag], probe = _inprocess_run(root, scenario, uavs, duration)
            cpus[tag].append((cpu, probe))
            cpu0, s0, _ = _inprocess_run(root, scenario, uavs, STARTUP_MISSION_S)
            startup_cpus[tag].append(cpu0)
            startup_mission[tag] = s0.get("mission_time_s")
    for tag in roots:
        s = summaries[tag]
        cpu, probe = min(cpus[tag], key=lambda c: c[0])
        cpu0 = min(startup_cpus[tag])
        row[f"{tag}_probe_ms"] = None if probe is None else round(probe, 1)
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
    _flag_unlike_hosts(row, scenario)
    return row


def world_row(roots: dict[str, Path], uavs: int, steps: int) -> dict:
    """``World.step`` alone (this checkout's ``speed_probe.py world`` over each side's workspace):
    CPU ms per step and the truth's digest, and the host's one-core speed while it ran
    (``probe_ms``; flagged as for :func:`inprocess_row`)."""
    row: dict = {"uavs": uavs, "steps": steps}
    argv = [
        "python",
        str(HERE.parent / "speed_probe.py"),
        "world",
        "--uavs",
        str(uavs),
        "--steps",
        str(steps),
    ]
    for tag, root in roots.items():
        with CpuProbe() as probe:
            _, out = _run(root, argv, 900)
        lines = [x for x in out.splitlines() if x.startswith("{")]
        r = json.loads(lines[-1]) if lines else {}
        row[f"{tag}_world_ms_per_step"] = round(r["world_ms_per_step"], 3) if r else None
        row[f"{tag}_digest"] = r.get("truth_digest")
        ms = _median(probe.samples_ms)
        row[f"{tag}_probe_ms"] = None if ms is None else round(ms, 1)
    if "base" in roots:
        row["truth_same"] = row.get("base_digest") == row.get("head_digest")
    _flag_unlike_hosts(row, f"world step, {uavs} UAVs")
    return row


def _dds_argv(uavs: int, mission_s: float, vehicle_model: str, out: str) -> list[str]:
    """The mission runner's command line of one DDS row's run (ff_two_fires, seed 1)."""
    argv = ["python", "-m", "fire_mission.runner", "ff_two_fires", "--uavs", str(uavs), "--seed", "1"]
    argv += ["--max-duration", f"{mission_s:g}", "--quiet", "--no-record", "--no-report", "--out", out]
    return argv + (["--set", f"uavs.vehicle_model={vehicle_model}"] if vehicle_model != "ff_paper" else [])


def _dds_summary(
    root: Path, uavs: int, mission_s: float, vehicle_model: str, harness: Path | None = None
) -> dict:
    """summary.json of one lockstep DDS run of ff_two_fires (seed 1) for ``mission_s``, with
    ``probe_ms``: the :class:`CpuProbe` samples taken while it ran, as (monotonic s, ms) pairs.
    ``harness``: whose mission runner flies it (:func:`_run`)."""
    with tempfile.TemporaryDirectory() as d:
        with CpuProbe() as probe:
            _run(root, _dds_argv(uavs, mission_s, vehicle_model, d), 1800, harness)
        path = Path(d) / "summary.json"
        summary = json.loads(path.read_text()) if path.is_file() else {}
        stepping = Path(d) / "stepping.json"  # the runner's within-run series (since session 27)
        if stepping.is_file():
            summary.update(json.loads(stepping.read_text()))
        summary["probe_ms"] = probe.stamped
        return summary


#: the probe's loop: CPU ms of this fixed pure-Python loop, one sample a second, printed
_PROBE_CODE = """
import sys, time
while True:
    t0 = time.process_time()
    acc = 0
    for i in range(300_000):
        acc = (acc * 31 + i) & 0xFFFFFFFF
    print(round(time.monotonic(), 3), round(1000 * (time.process_time() - t0), 2), flush=True)
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
        self.stamped: list[tuple[float, float]] = []  # (monotonic s at the sample's end, ms)
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
        for line in self._out.read().decode(errors="replace").splitlines():
            try:
                stamp, ms = map(float, line.split())
            except ValueError:
                continue
            self.stamped.append((stamp, ms))
            self.samples_ms.append(ms)
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


def _span(rows: list, n0: int, n1: int) -> tuple[list, list] | None:
    """The first and last of ``rows`` ([monotonic s, steps, ...]) with steps in [n0, n1], if two
    such rows differ in both steps and wall time."""
    inside = [r for r in rows if n0 <= r[1] <= n1]
    if len(inside) < 2 or inside[-1][1] <= inside[0][1] or inside[-1][0] <= inside[0][0]:
        return None
    return inside[0], inside[-1]


def _window(s: dict, n0: int, n1: int) -> dict | None:
    """Steps n0 to n1 of one run (the runner's ``stepping.json``): the rate from the truth
    messages' wall times (``truth_walls``, one per step), the CPU per step from the process
    samples (``stepping_series``, ~0.25 s apart) whose steps fall in the window, and the wall
    span (for the probe). None if the run has fewer than two truth messages in the window."""
    walls = s.get("truth_walls") or [r[:2] for r in s.get("stepping_series", [])]
    span = _span(walls, n0, n1)
    if span is None:
        return None
    (w0, k0), (w1, k1) = span[0][:2], span[1][:2]
    out: dict = {"steps_per_s": (k1 - k0) / (w1 - w0), "wall": (w0, w1), "world": None, "agent": None}
    cpu = _span(s.get("stepping_series", []), n0, n1)
    if cpu is not None:
        first, last = cpu
        for i, key in ((2, "world"), (3, "agent")):
            if first[i] is not None and last[i] is not None:
                out[key] = (last[i] - first[i], last[1] - first[1])  # (CPU s, steps)
    return out


def dds_row(roots: dict[str, Path], uavs: int, duration: float, vehicle_model: str = "ff_paper") -> dict:
    """Lockstep steps per wall second of ``uavs`` agents over DDS on ``vehicle_model`` (the world's
    vehicle backend, ``uavs.vehicle_model``; ``jsbsim`` steps one JSBSim aircraft and its autopilot
    per UAV at the world's 100 Hz physics), over ``duration`` s of mission once the whole fleet is
    airborne (:func:`airborne_after_s`), measured within one run to ``t_air + duration``: the
    runner's ``stepping.json`` (the wall time of every truth message; the processes' CPU about
    four times a wall second) between the window's first and last step (:func:`_window`). The
    run is flown by this
    checkout's mission runner over each side's workspace (the world and agents measured are the
    side's own; the runner measures), as the world row runs this checkout's probe.

    Until session 27 the window was the difference of two runs, to ``t_air`` and to ``t_air +
    duration``: at 30 UAVs a 15 s window is a fifth of the longer run, so the two runs'
    ordinary difference in overall rate (10-17 steps/s within one run, session 27) came out
    several times larger in the window: the same commits gave 3.8 to 16.9 steps/s, base or head
    first. That way is gone: this checkout's runner always writes ``stepping.json``, so a run
    without it failed (or ran past its time limit), and the row says so in ``not_measured``
    with the command that reproduces it, instead of flying a second run to stand in for it.

    Also the world's and an agent's CPU ms per step over the window, the agents' mean RSS at the
    end, and the host's one-core speed in the window (``probe_ms``: the median :class:`CpuProbe`
    sample); base and head probes more than :data:`PROBE_TOLERANCE` apart put a note in
    ``not_comparable``."""
    t_air = airborne_after_s(uavs)
    row: dict = {
        "uavs": uavs,
        "vehicle_model": vehicle_model,
        "mission_time_s": duration,
        "airborne_from_s": t_air,
    }
    for tag, root in roots.items():
        s = _dds_summary(root, uavs, t_air + duration, vehicle_model, harness=ROOT)
        procs = s.get("processes", {})
        rss = [v.get("rss_mb") for k, v in procs.items() if k.startswith("agent") and v.get("rss_mb")]
        row[f"{tag}_agent_rss_mb"] = round(sum(rss) / len(rss), 1) if rss else None
        for key in ("steps_per_s", "world_cpu_ms_per_step", "agent_cpu_ms_per_step", "probe_ms"):
            row[f"{tag}_{key}"] = None
        dt = s.get("control_period_s", 0.1)
        if "truth_walls" not in s and "stepping_series" not in s:
            cmd = " ".join(_dds_argv(uavs, t_air + duration, vehicle_model, "DIR")[1:])
            why = (
                "the run wrote no stepping.json: it failed or ran past its time limit "
                f"(`python {cmd}` in {root} shows why)"
            )
            _not_a_measure(row, f"{tag} steps/s", why)
            continue
        w = _window(s, round(t_air / dt), round((t_air + duration) / dt))
        if w is None:
            _not_a_measure(row, f"{tag} steps/s", "fewer than two truth messages of the run in the window")
            continue
        w0, w1 = w["wall"]
        probe = _median([ms for t, ms in s.get("probe_ms", []) if w0 <= t <= w1])
        rate = w["steps_per_s"]
        cpus = {key: w[key] for key in ("world", "agent")}
        row[f"{tag}_probe_ms"] = None if probe is None else round(probe, 1)
        row[f"{tag}_steps_per_s"] = round(rate, 2)
        for key, c in cpus.items():
            if c is None:
                continue
            if c[0] <= 0 or c[1] <= 0:
                why = f"{1000 * c[0]:.3f} ms of CPU over {c[1]:g} steps, not positive"
                _not_a_measure(row, f"{tag} {key} CPU ms/step", why)
                continue
            row[f"{tag}_{key}_cpu_ms_per_step"] = round(1000 * c[0] / c[1], 3)
    _flag_unlike_hosts(row, f"{uavs} UAVs {vehicle_model}")
    return row


def _flag_unlike_hosts(row: dict, what: str) -> None:
    """Base and head measured while the host's one-core speed differed by more than
    :data:`PROBE_TOLERANCE` (``base_probe_ms`` / ``head_probe_ms``): a note in the row's
    ``not_comparable`` and a warning on stderr naming ``what``. Nothing is rescaled."""
    pb, ph = row.get("base_probe_ms"), row.get("head_probe_ms")
    if pb and ph and abs(pb - ph) > PROBE_TOLERANCE * min(pb, ph):
        note = (
            f"the host's one-core speed differed between base and head (CpuProbe: {pb:g} / {ph:g} ms "
            f"of CPU for the same loop, {100 * (max(pb, ph) / min(pb, ph) - 1):.0f} %): its figures "
            "are not comparable side by side"
        )
        row.setdefault("not_comparable", []).append(note)
        print(f"bench: warning: {what}: {note}", file=sys.stderr)


def _not_a_measure(row: dict, figure: str, why: str) -> None:
    """A window figure that is not a measure (a run that failed; a window without two samples;
    CPU over the window that is not positive): the figure stays empty, and the row says which
    and why, so that the page shows it instead of printing a zero or negative rate or CPU time."""
    note = f"{figure}: {why}: not a measure"
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
