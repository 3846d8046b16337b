"""The mission runner: world, recorder and N agents as separate processes, supervised.

usage: scripts/run_mission [SCENARIO] [options]   (scripts/run_mission --help)

Everything is started in one process group on a private ROS_DOMAIN_ID; the runner itself is a
small rclpy node that follows ``/clock``, ``/world/truth`` and the events to show progress,
inject faults at given mission times, and decide when the mission is over. It ends every
process it started (SIGINT, then SIGKILL) on completion (once the world has exited by itself,
its last messages acknowledged by every reader: ``_let_the_world_end``), timeout, error or
Ctrl-C, the agents first (each exits once its own last messages are acknowledged) and the
recorder last, prints a summary table and writes ``summary.json`` beside the bag and the report.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import re
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from fire_uav_common.constants import EventType, FireStatus, VehicleStatus
from fire_uav_common.final_acks import FINAL_ACK_CAP_WALL_S
from fire_uav_common.scenario import LinkOutage
from fire_uav_common.stamps import stamp_to_s

from fire_mission.cli import OneLineParser, mission_exit_status
from fire_mission.errors import MissionError
from fire_mission.procs import ProcessGroup, claim_domain, ros_run_argv
from fire_mission.procstat import sample as proc_sample
from fire_mission.summary import LiveEvent, LiveSummary, table

if TYPE_CHECKING:
    from fire_uav_common.scenario import Scenario

ROOT = Path(__file__).resolve().parents[2]  # the checkout: tools/<package>/<module>.py
_HELD_DOMAINS = contextlib.ExitStack()  # the ROS domains this runner claimed (released at exit)


# --- fault specifications ----------------------------------------------------------------
@dataclass(frozen=True)
class Kill:
    uav: int
    t_s: float


@dataclass(frozen=True)
class Freeze:
    uav: int
    start_s: float
    end_s: float


def _parse_kill(text: str) -> Kill:
    m = re.fullmatch(r"(\d+)@([0-9.]+)", text)
    if not m:
        raise argparse.ArgumentTypeError(f"--kill expects K@T (uav id @ mission seconds), got '{text}'")
    return Kill(int(m[1]), float(m[2]))


def _parse_freeze(text: str) -> Freeze:
    m = re.fullmatch(r"(\d+)@([0-9.]+):([0-9.]+)", text)
    if not m or float(m[3]) <= float(m[2]):
        raise argparse.ArgumentTypeError(
            f"--freeze expects K@T1:T2 with T2 > T1 (mission seconds), got '{text}'"
        )
    return Freeze(int(m[1]), float(m[2]), float(m[3]))


@dataclass(frozen=True)
class Stall:
    uav: int
    t_s: float
    wall_ms: float


def _parse_stall(text: str) -> Stall:
    m = re.fullmatch(r"(\d+)@([0-9.]+):([0-9.]+)", text)
    if not m or float(m[3]) <= 0:
        raise argparse.ArgumentTypeError(
            f"--stall expects K@T:MS (uav @ mission seconds : wall milliseconds > 0), got '{text}'"
        )
    return Stall(int(m[1]), float(m[2]), float(m[3]))


def offline_windows(args: argparse.Namespace) -> tuple:
    """The lockstep offline schedule of ``--kill`` and ``--freeze`` (fire_uav_common.lockstep)."""
    from fire_uav_common.lockstep import OfflineWindow

    ws = [OfflineWindow(k.uav, k.t_s) for k in args.kill]
    ws += [OfflineWindow(f.uav, f.start_s, f.end_s) for f in args.freeze]
    return tuple(sorted(ws, key=lambda w: (w.start_s, w.uav_id, w.end_s)))


def signal_plan(args: argparse.Namespace, period_s: float) -> list[tuple[float, int, str, int, int, float]]:
    """When the supervisor delivers each fault's signal: (clock [s], order, text, uav, signal, the
    fault's own mission time as given [s]).

    The world and the agents take agent K out of the lockstep waits from the first step of its
    window (step S1), whatever the signal does; the signal comes when ``/clock`` shows that the
    world has finished step S1 + 1, so every message K sent before its window has been consumed
    by its peers. A frozen agent is continued when the clock shows step S2 (its window's end)
    has started, and the world is waiting for it again. So the moment the signal lands changes
    nothing the fleet sees (docs/protocol.md "Lockstep").
    """
    from fire_uav_common.lockstep import first_step_at

    plan = []
    for k in args.kill:
        s1 = first_step_at(k.t_s, period_s)
        plan.append(
            (
                (s1 + 2) * period_s,
                0,
                f"kill uav {k.uav} at {k.t_s:g} s (offline from step {s1})",
                k.uav,
                signal.SIGKILL,
                k.t_s,
            )
        )
    for f in args.freeze:
        s1, s2 = first_step_at(f.start_s, period_s), first_step_at(f.end_s, period_s)
        t_stop = (s1 + 2) * period_s
        plan.append(
            (
                t_stop,
                0,
                f"freeze uav {f.uav} at {f.start_s:g} s (offline steps {s1}-{s2 - 1})",
                f.uav,
                signal.SIGSTOP,
                f.start_s,
            )
        )
        plan.append(
            (
                max(t_stop, (s2 + 1) * period_s),
                1,
                f"resume uav {f.uav} at {f.end_s:g} s",
                f.uav,
                signal.SIGCONT,
                f.end_s,
            )
        )
    return sorted(plan, key=lambda p: (p[0], p[1], p[3]))


#: the supervisor's signals and the fault each stands for (``summary.json`` ``faults``)
_SIGNAL_KIND = {signal.SIGKILL: "kill", signal.SIGSTOP: "freeze", signal.SIGCONT: "resume"}


def _parse_outage(text: str) -> LinkOutage:
    m = re.fullmatch(r"(\d+)>(\d+)@([0-9.]+):([0-9.]+)", text)
    if not m or float(m[4]) <= float(m[3]):
        raise argparse.ArgumentTypeError(
            f"--outage expects A>B@T1:T2 (link from A to B, T2 > T1), got '{text}'"
        )
    return LinkOutage(int(m[1]), int(m[2]), float(m[3]), float(m[4]))


def applied_outages(
    args: argparse.Namespace, scenario: Scenario, uav_count: int
) -> list[tuple[int, int, float, float]]:
    """The link outages the agents apply: ``--outage`` when given (it replaces the scenario's,
    see ``write_params``), else the scenario's ``comms.outages``; none without a fleet."""
    if uav_count < 2:
        return []
    if args.outage:
        return [(o.from_id, o.to_id, o.start_s, o.end_s) for o in args.outage]
    return [(o.from_id, o.to_id, o.start_s, o.end_s) for o in scenario.comms.outages]


def _probability(text: str) -> float:
    try:
        p = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--loss expects a probability in [0, 1], got '{text}'") from None
    if not 0.0 <= p <= 1.0:
        raise argparse.ArgumentTypeError(f"--loss expects a probability in [0, 1], got {p}")
    return p


#: the --help examples, each cheap enough to paste and watch (tests/test_examples.py runs them)
EXAMPLES = [
    ("scripts/run_mission", "the default mission (FF two fires, 5 UAVs) + report"),
    ("scripts/run_mission tiny_test --uavs 3 --kill 2@10 --loss 0.2", "UAV 2 crashes mid-mission, 20 % loss"),
    (
        "scripts/run_mission tiny_test --freeze 1@5:6.5 --outage '0>1@3:9'",
        "quote A>B: the shell reads > itself",
    ),
    ("scripts/run_mission grass_running --uavs 0 --max-duration 60", "the fire alone (suppression baseline)"),
]


def shipped_scenarios() -> dict[str, str]:
    """Scenario name -> the first sentence of its description, for every shipped scenario."""
    import yaml

    out = {}
    for path in sorted((ROOT / "ros2_ws/src/fire_world_sim/scenarios").glob("*.yaml")):
        try:
            text = str(yaml.safe_load(path.read_text()).get("description", ""))
        except (OSError, yaml.YAMLError, AttributeError):
            text = ""
        text = " ".join(text.split())
        out[path.stem] = text if len(text) <= 70 else text[:67].rsplit(" ", 1)[0] + " ..."
    return out


def _epilog() -> str:
    w = max(len(c) for c, _ in EXAMPLES)
    lines = ["examples (runs land in runs/<scenario>-<time>-s<seed>/, the last one also in runs/latest):"]
    lines += [f"  {c.ljust(w)}  # {why}" for c, why in EXAMPLES]
    scenarios = shipped_scenarios()
    if scenarios:
        n = max(len(k) for k in scenarios)
        lines += ["", "scenarios (shipped in fire_world_sim/scenarios; or give a YAML path):"]
        lines += [f"  {k.ljust(n)}  {v}" for k, v in scenarios.items()]
    return "\n".join(lines)


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog="run_mission",
        description="Run a fleet mission: world + recorder + N agent processes, with fault injection. "
        "Exit status: 0 complete (a run with --uavs 0 also at its time limit), 1 not complete, "
        "2 a usage or configuration error.",
        epilog=_epilog(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "scenario",
        nargs="?",
        default="ff_two_fires",
        help="scenario name (shipped in fire_world_sim/scenarios) or path to a YAML file",
    )
    p.add_argument(
        "--uavs", type=int, default=None, help="fleet size (default: the scenario's; 0: the fire burns alone)"
    )
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="FIELD=VALUE",
        help="override a scenario field, e.g. --set mission.prior_fires=known; the run's scenario is "
        "written to OUT/scenario.yaml; repeatable",
    )
    p.add_argument(
        "--seed", type=int, default=None, help="seed for every random stream (default: the scenario's)"
    )
    p.add_argument("--mode", choices=["lockstep", "realtime"], default="lockstep")
    p.add_argument("--rtf", type=float, default=1.0, help="real-time factor in realtime mode (> 0)")
    p.add_argument(
        "--loss", type=_probability, default=None, help="packet loss probability per directed link"
    )
    for flag, parse, metavar, text in (  # the scheduled faults: each repeatable
        ("--kill", _parse_kill, "K@T", "SIGKILL agent K at mission time T [s]"),
        ("--freeze", _parse_freeze, "K@T1:T2", "SIGSTOP agent K at T1 and SIGCONT it at T2 [s]"),
        (
            "--stall",
            _parse_stall,
            "K@T:MS",
            "stop agent K for MS wall milliseconds at mission time T, as a slow machine would "
            "(lockstep waits for it: nothing but wall time may change)",
        ),
        (
            "--outage",
            _parse_outage,
            "'A>B@T1:T2'",
            "drop every message on the link A -> B between T1 and T2 [s] (quote it: the shell reads >)",
        ),
    ):
        p.add_argument(
            flag, type=parse, action="append", default=[], metavar=metavar, help=f"{text}; repeatable"
        )
    p.add_argument(
        "--check-determinism",
        action="store_true",
        help="run the mission twice (OUT/run1, OUT/run2) and compare the summaries and the "
        "/world/truth messages of the two bags; exit 0 only if they are identical",
    )
    p.add_argument(
        "--max-duration",
        type=float,
        default=None,
        help="stop the mission after this many seconds (default: the scenario's time limit); "
        "a mission stopped here exits 0, one that runs out of the scenario's own limit exits 1",
    )
    p.add_argument(
        "--wall-timeout", type=float, default=1800.0, help="wall-clock limit for the whole run [s]"
    )
    p.add_argument(
        "--out", type=Path, default=None, help="output directory (default: runs/<scenario>-<time>)"
    )
    p.add_argument("--no-record", action="store_true", help="do not start the recorder")
    p.add_argument(
        "--no-auth",
        action="store_true",
        help="turn off HMAC authentication of fleet and command topics (on by default; docs/security.md)",
    )
    p.add_argument("--no-report", action="store_true", help="do not write the report after the run")
    p.add_argument(
        "--wall-epoch",
        action="store_true",
        help="stamp the bag from the wall-clock epoch of the recorder's start (the recorder's "
        "stamp_wall_epoch), so Foxglove's timeline shows the real date; header stamps stay sim time",
    )
    p.add_argument(
        "--foxglove",
        action="store_true",
        help="also start the Foxglove bridge (live view: WebSocket server on 127.0.0.1:PORT)",
    )
    p.add_argument(
        "--foxglove-port", type=int, default=8765, metavar="PORT", help="the bridge's port (default 8765)"
    )
    p.add_argument(
        "--agent-arg",
        action="append",
        default=[],
        metavar="NAME:=VALUE",
        help="extra ROS parameter for every agent; repeatable",
    )
    p.add_argument(
        "--agent-netns",
        type=_parse_netns,
        default=[],
        metavar="NS[,NS...]",
        help="start agent K in Linux network namespace NS[K mod len] (`ip netns exec`, root): a fleet "
        "spread over several hosts; the runner, world and recorder stay in the runner's own namespace "
        "(docs/deployment.md)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def _parse_netns(text: str) -> list[str]:
    names = [n for n in text.split(",") if n]
    bad = [n for n in names if not re.fullmatch(r"[A-Za-z0-9_.-]{1,64}", n)]
    if not names or bad:
        raise argparse.ArgumentTypeError(
            f"--agent-netns expects comma-separated namespace names ([A-Za-z0-9_.-]), got '{text}'"
        )
    return names


# --- scenario & parameters ---------------------------------------------------------------
def resolve_scenario(name: str) -> Path:
    """A path as given, or ``<share>/fire_world_sim/scenarios/<name>.yaml`` (source tree fallback)."""
    p = Path(name)
    if p.suffix in (".yaml", ".yml") or p.exists():
        if not p.is_file():
            raise MissionError(f"scenario file not found: {p}")
        return p.resolve()
    candidates = [
        Path(prefix) / "share/fire_world_sim/scenarios" / f"{name}.yaml"
        for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)
        if prefix
    ]
    candidates.append(ROOT / "ros2_ws/src/fire_world_sim/scenarios" / f"{name}.yaml")
    for c in candidates:
        if c.is_file():
            return c.resolve()
    shipped = sorted(q.stem for q in (ROOT / "ros2_ws/src/fire_world_sim/scenarios").glob("*.yaml"))
    raise MissionError(f"unknown scenario '{name}'; shipped: {', '.join(shipped) or 'none'}; or give a path")


def parse_sets(items: list[str]) -> dict[str, object]:
    """``--set a.b=VALUE`` items -> {"a.b": value}; values are read as YAML (numbers, true, names)."""
    import yaml

    out: dict[str, object] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key or not re.fullmatch(r"[A-Za-z_][\w]*(\.[A-Za-z_][\w]*)*", key):
            raise MissionError(
                f"--set expects FIELD.PATH=VALUE (e.g. mission.prior_fires=known), got '{item}'"
            )
        out[key] = yaml.safe_load(value)
    return out


def write_scenario(src: Path, overrides: dict[str, object], dst: Path) -> Path:
    """The scenario with ``overrides`` applied, written to ``dst`` (every process then reads it)."""
    import yaml

    raw = yaml.safe_load(src.read_text(encoding="utf-8"))
    # the copy lives in the run folder: its relative file paths (landscape, wind grid) still
    # name the files beside the original
    if isinstance(raw, dict) and raw.get("paths_relative_to") is None:
        raw["paths_relative_to"] = str(src.resolve().parent)
    for dotted, value in overrides.items():
        node = raw
        *parents, leaf = dotted.split(".")
        for part in parents:
            node = node.setdefault(part, {})
        node[leaf] = value
    dst.write_text(
        f"# {src} with --set {' '.join(f'{k}={v}' for k, v in overrides.items())}\n"
        + yaml.safe_dump(raw, sort_keys=False)
    )
    return dst.resolve()


def _yaml_params(node: str, params: dict) -> str:
    import yaml

    clean = {k: v for k, v in params.items() if not (isinstance(v, list) and not v)}
    return yaml.safe_dump({node: {"ros__parameters": clean}}, sort_keys=True)


def _write_private(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` readable by this user only (mode 0600, also when it existed)."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    os.fchmod(fd, 0o600)
    with os.fdopen(fd, "w") as f:
        f.write(text)


def write_params(
    out: Path,
    args: argparse.Namespace,
    scenario_path: Path,
    uav_count: int,
    seed: int,
    max_duration_s: float | None,
) -> dict[str, Path]:
    pdir = out / "params"
    pdir.mkdir(parents=True, exist_ok=True)
    files = {}
    from fire_uav_common.auth import new_key_hex

    # one fresh key per mission, only in the world's and agents' params files (0600): never in a
    # log, the bag, the summary or a command line (docs/security.md)
    auth = {"auth": not getattr(args, "no_auth", False)}
    if auth["auth"]:
        auth["fleet_key"] = new_key_hex()
    world = {
        "scenario_file": str(scenario_path),
        "seed": seed,
        "uav_count": uav_count,
        "no_fleet": uav_count == 0,
        "mode": args.mode,
        "real_time_factor": float(args.rtf),
    }
    if max_duration_s is not None:
        world["max_duration_s"] = float(max_duration_s)
    # the supervisor subscribes to /world/truth; with a recorder, wait for it too (bag from step 0)
    world["wait_for_subscribers"] = 1 if args.no_record else 2
    from fire_uav_common.lockstep import format_schedule

    schedule = format_schedule(offline_windows(args))
    # known-fires mode: the dispatch briefing (noisy estimates drawn next to the truth, seeded)
    from fire_uav_common.scenario import load_scenario
    from fire_world_sim.dispatch import prior_fire_estimates

    briefing = prior_fire_estimates(load_scenario(scenario_path), seed)
    world["offline_schedule"] = schedule
    files["world"] = pdir / "world.yaml"
    _write_private(files["world"], _yaml_params("/**", {**world, **auth}))
    files["recorder"] = pdir / "recorder.yaml"
    files["recorder"].write_text(
        _yaml_params(
            "/**",
            {
                "output": str(out / "bag"),
                "scenario_file": str(scenario_path),
                "seed": seed,
                "uav_count": uav_count,
                "stamp_wall_epoch": bool(args.wall_epoch),
            },
        )
    )
    for k in range(uav_count):
        agent = {
            "uav_id": k,
            "uav_count": uav_count,
            "seed": seed,
            "scenario_file": str(scenario_path),
            "mode": args.mode,
            "outage_from": [o.from_id for o in args.outage],
            "outage_to": [o.to_id for o in args.outage],
            "outage_start_s": [o.start_s for o in args.outage],
            "outage_end_s": [o.end_s for o in args.outage],
            "offline_schedule": schedule,
        }
        if briefing:
            agent["prior_fires"] = [float(v) for f in briefing for v in f]
        if args.loss is not None:
            agent["loss_probability"] = float(args.loss)
        files[f"agent_{k}"] = pdir / f"agent_{k}.yaml"
        _write_private(files[f"agent_{k}"], _yaml_params("/**", {**agent, **auth}))
    return files


# --- the supervisor node -------------------------------------------------------------------
class Supervisor:
    """Follows the mission over ROS and applies the fault schedule. Owns no algorithm."""

    def __init__(
        self,
        procs: ProcessGroup,
        summary: LiveSummary,
        args: argparse.Namespace,
        uav_count: int,
        control_period_s: float,
    ) -> None:
        import rclpy
        from fire_uav_common import topics

        self.procs, self.summary, self.args = procs, summary, args
        self.uav_count = uav_count
        self.control_period_s = control_period_s
        self.node = rclpy.create_node("mission_supervisor")
        # one executor for the run (ros_io.make_executor: the lean one unless FIRE_UAV_EXECUTOR=rclpy);
        # rclpy.spin_once(node) built a wait set per call and took one message per call
        from fire_uav_common.ros_io import make_executor

        self.executor = make_executor()
        self.executor.add_node(self.node)
        self.t_s = 0.0
        self.steps = 0
        self.done = False
        self.last_truth_wall = time.monotonic()
        self.first_truth_wall: float | None = None
        self.first_step = 0
        self.cpu_at_first_step: dict[str, float] = {}
        self.steps_at_sample: dict[str, int] = {}  # sup.steps when each process's CPU was last sampled
        # once stepping: (monotonic wall s, steps, world CPU s, agents' mean CPU s) at each sample,
        # so that a window of the mission is measured within this run (fire_bench.speed.dds_row)
        self.stepping_series: list[tuple[float, int, float | None, float | None]] = []
        self.truth_walls: list[tuple[float, int]] = []  # (monotonic wall s, steps) at each truth message
        self.pending = signal_plan(args, control_period_s)  # (clock, order, text, uav, signal, t_s)
        # the water on board where each fault's window starts (truth of that step: deterministic)
        self.water_watch = sorted(
            [(k.t_s, f"kill uav {k.uav} at {k.t_s:g} s", k.uav) for k in args.kill]
            + [(f.start_s, f"freeze uav {f.uav} at {f.start_s:g} s", f.uav) for f in args.freeze]
        )
        self.stalls = sorted((s.t_s, s.uav, s.wall_ms) for s in args.stall)
        self.resume_at: list[tuple[float, str]] = []  # (monotonic wall time, process) of stalls
        topics.subscription(self.node, topics.CLOCK_SPEC, self._on_clock)
        topics.subscription(self.node, topics.WORLD_TRUTH_SPEC, self._on_truth)
        topics.subscription(self.node, topics.WORLD_EVENTS_SPEC, self._on_event)
        topics.subscription(self.node, topics.WORLD_FIRE_TYPE_SPEC, self._on_fire_type)
        topics.subscription(self.node, topics.FLEET_EVENTS_SPEC, self._on_event)
        topics.subscription(self.node, topics.FLEET_STATE_SPEC, self._on_state, drain=True)

    def _on_clock(self, msg) -> None:
        self.t_s = stamp_to_s(msg.clock)
        self.summary.mission_time_s = self.t_s
        while self.pending and self.pending[0][0] <= self.t_s + 1e-9:
            _, _, what, uav, sig, fault_t = self.pending.pop(0)
            name = f"agent_{uav}"
            kind = _SIGNAL_KIND[sig]
            if name in self.procs.children and self.procs.children[name].alive():
                self.procs.signal(name, sig)
                self.summary.faults.append(what)
                self.summary.fault_records.append(
                    {"kind": kind, "uav_id": uav, "t_s": fault_t, "applied": True}
                )
                self.node.get_logger().warn(
                    f"fault injected: {what} (signal at mission time {self.t_s:.2f} s)"
                )
            else:
                self.summary.faults.append(f"{what}: not applied, agent not running")
                self.summary.fault_records.append(
                    {"kind": kind, "uav_id": uav, "t_s": fault_t, "applied": False}
                )
        while self.stalls and self.stalls[0][0] <= self.t_s + 1e-9:
            t, uav, ms = self.stalls.pop(0)
            name = f"agent_{uav}"
            if name in self.procs.children and self.procs.children[name].alive():
                self.procs.signal(name, signal.SIGSTOP)
                self.resume_at.append((time.monotonic() + ms / 1000.0, name))
                self.summary.faults.append(f"stall uav {uav} at {t:g} s for {ms:g} ms wall")
                self.summary.fault_records.append(
                    {"kind": "stall", "uav_id": uav, "t_s": t, "applied": True, "wall_ms": ms}
                )

    def resume_stalled(self) -> None:
        """SIGCONT the agents whose stall has lasted its wall time (called from the supervise loop)."""
        now = time.monotonic()
        for due, name in [r for r in self.resume_at if r[0] <= now]:
            self.resume_at.remove((due, name))
            if self.procs.children[name].alive():
                self.procs.signal(name, signal.SIGCONT)

    def _on_truth(self, msg) -> None:
        self.steps = max(self.steps, msg.step + 1)
        self.last_truth_wall = time.monotonic()
        self.truth_walls.append((round(self.last_truth_wall, 4), self.steps))
        if self.first_truth_wall is None:
            # the stepping phase starts here: rates and CPU per step leave start-up out
            self.first_truth_wall, self.first_step = self.last_truth_wall, msg.step
            for name, child in self.procs.children.items():
                st = proc_sample(child.pid)
                if st is not None:
                    self.cpu_at_first_step[name] = st.cpu_s
        self.summary.fires_total = len(msg.fires)
        self.summary.fires_active = sum(1 for f in msg.fires if f.status == FireStatus.ACTIVE)
        self.summary.vehicles_alive = sum(1 for v in msg.vehicles if v.status != VehicleStatus.CRASHED)
        self.summary.vehicles_landed = sum(1 for v in msg.vehicles if v.status == VehicleStatus.LANDED)
        for v in msg.vehicles:
            self.summary.water_kg[v.uav_id] = float(v.water_kg)
        self.summary.add_truth(
            stamp_to_s(msg.header.stamp),
            [(float(f.area_m2), f.status == FireStatus.ACTIVE) for f in msg.fires],
        )
        t = stamp_to_s(msg.header.stamp)
        while self.water_watch and self.water_watch[0][0] <= t + 1e-9:
            _, what, uav = self.water_watch.pop(0)
            if uav in self.summary.water_kg:
                self.summary.water_at_fault[what] = self.summary.water_kg[uav]
        self.summary.observe_truth(float(msg.min_separation_m), int(msg.collisions))

    def _on_fire_type(self, msg) -> None:
        import numpy as np

        self.summary.add_fire_types(np.asarray(msg.data, dtype=np.int8))

    def _on_event(self, msg) -> None:
        t = stamp_to_s(msg.header.stamp)
        self.summary.add(
            LiveEvent(
                t, msg.type, msg.uav_id, msg.peer_id, msg.fire_id, msg.value, msg.detail, msg.x_m, msg.y_m
            )
        )
        if msg.type == EventType.MISSION_COMPLETE:
            self.done = True

    def _on_state(self, msg) -> None:
        self.summary.add_state(
            int(msg.uav_id),
            stamp_to_s(msg.header.stamp),
            (msg.packets_received, msg.packets_lost, msg.packets_rejected),
            list(msg.alive_peers),
            int(msg.objective),
        )


class MissionProgress:
    """One status line: a bar on a terminal (\\r), a plain line every 10 s otherwise."""

    def __init__(self, max_duration_s: float, quiet: bool) -> None:
        self.max_s = max_duration_s
        self.quiet = quiet
        self.tty = sys.stderr.isatty()
        self.last_plain = 0.0

    def show(self, t_s: float, s: LiveSummary, uav_count: int, alive: int) -> None:
        if self.quiet:
            return
        frac = min(1.0, t_s / self.max_s) if self.max_s > 0 else 0.0
        bar = "#" * int(frac * 30)
        fires = "?" if s.fires_active is None else f"{s.fires_active}/{s.fires_total}"
        vehicles = "?" if s.vehicles_alive is None else f"{s.vehicles_alive}/{uav_count}"
        line = (
            f"[{bar:<30}] t={t_s:7.1f} s  fires left {fires}  UAVs flying-or-landed {vehicles} "
            f"(landed {s.vehicles_landed})  agents running {alive}/{uav_count}  drops {len(s.drops())}"
        )
        if self.tty:
            sys.stderr.write("\r" + line[:160])
            sys.stderr.flush()
        elif time.monotonic() - self.last_plain > 10:
            self.last_plain = time.monotonic()
            sys.stderr.write(line + "\n")

    def close(self) -> None:
        if self.tty and not self.quiet:
            sys.stderr.write("\n")


def run(args: argparse.Namespace) -> int:
    from fire_uav_common.scenario import ScenarioError, check_fleet_size, load_scenario
    from fire_uav_common.scenario.ground import geo_summary

    scenario_path = resolve_scenario(args.scenario)
    overrides = parse_sets(args.set)
    try:
        scenario = load_scenario(scenario_path, overrides=overrides)
    except ScenarioError as e:
        raise MissionError(str(e)) from None
    uav_count = args.uavs if args.uavs is not None else scenario.uavs.count
    if uav_count < 0:
        raise MissionError(
            f"--uavs must be >= 0 (0: the fire alone, the suppression baseline), got {uav_count}"
        )
    if uav_count > 0:
        try:
            check_fleet_size(scenario, uav_count)
        except ScenarioError as e:
            raise MissionError(f"{e} (--uavs {uav_count})") from None
    for k in [*(x.uav for x in args.kill), *(x.uav for x in args.freeze), *(x.uav for x in args.stall)]:
        if not 0 <= k < uav_count:
            raise MissionError(f"fault names uav {k}, but the fleet is uavs 0..{uav_count - 1}")
    for o in args.outage:
        if not (0 <= o.from_id < uav_count and 0 <= o.to_id < uav_count) or o.from_id == o.to_id:
            raise MissionError(
                f"--outage {o.from_id}>{o.to_id}: both ends must be distinct uavs in 0..{uav_count - 1}"
            )
    if not 0 <= args.foxglove_port <= 65535:
        raise MissionError(f"--foxglove-port must be in 0..65535, got {args.foxglove_port}")
    if args.rtf <= 0 or not math.isfinite(args.rtf):
        raise MissionError(f"--rtf must be a positive number, got {args.rtf}")
    seed = args.seed if args.seed is not None else scenario.seed
    max_s = args.max_duration if args.max_duration is not None else scenario.timing.max_duration_s
    out = args.out or ROOT / "runs" / f"{scenario.name}-{time.strftime('%Y%m%d-%H%M%S')}-s{seed}"
    out = out.resolve()
    if (out / "bag").exists():
        raise MissionError(
            f"{out / 'bag'} already exists: choose another --out (recordings are never overwritten)"
        )
    out.mkdir(parents=True, exist_ok=True)
    _point_latest_at(out)
    if overrides:
        scenario_path = write_scenario(scenario_path, overrides, out / "scenario.yaml")
    params = write_params(out, args, scenario_path, uav_count, seed, args.max_duration)

    if "FIRE_UAV_DOMAIN_ID" in os.environ:  # claimed by the caller (a sweep, a test)
        domain = int(os.environ["FIRE_UAV_DOMAIN_ID"])
    else:  # held until this process ends: no other fleet on the host gets it meanwhile
        domain = _HELD_DOMAINS.enter_context(claim_domain())
    os.environ["ROS_DOMAIN_ID"] = str(domain)
    # PYTHONHASHSEED: no set or dict of strings may change its order between two runs
    env = dict(os.environ, PYTHONUNBUFFERED="1", PYTHONHASHSEED="0", ROS_LOG_DIR=str(out / "ros_log"))
    summary = LiveSummary(uav_count=uav_count, raster=scenario.fires.model == "raster")
    summary.home_xy = {i: (p[0], p[1]) for i, p in enumerate(scenario.uav_start_poses(uav_count))}
    summary.outages = applied_outages(args, scenario, uav_count)
    print(
        f"[run_mission] scenario {scenario.name} ({scenario_path}), {uav_count} UAVs, seed {seed}, "
        f"mode {args.mode}, ROS_DOMAIN_ID {domain}, output {out}",
        file=sys.stderr,
    )

    import rclpy

    rclpy.init()
    wall0 = time.monotonic()
    outcome = "aborted"
    agents = [f"agent_{k}" for k in range(uav_count)]
    sup = None
    progress = MissionProgress(max_s, args.quiet)
    with ProcessGroup(out / "logs", env, grace_s=8.0) as procs:
        try:
            sup = Supervisor(procs, summary, args, uav_count, scenario.timing.control_period_s)
            if not args.no_record:
                procs.start(
                    "recorder",
                    ros_run_argv(
                        "fire_uav_recording", "recorder", ["--params-file", str(params["recorder"])]
                    ),
                )
                _wait_for_node(sup, "recorder", procs, wall0 + args.wall_timeout, args.quiet)
            if not args.no_record or args.foxglove:
                # /fleet/perimeter drawn as markers on /viz/perimeter: recorded in every bag, live in Foxglove
                procs.start(
                    "perimeter_viewer", ros_run_argv("fire_perimeter_monitor", "perimeter_viewer", [])
                )
                _wait_for_node(sup, "perimeter_viewer", procs, wall0 + args.wall_timeout, args.quiet)
            if args.foxglove:
                procs.start(
                    "foxglove_bridge",
                    ros_run_argv(
                        "fire_uav_recording",
                        "foxglove_bridge",
                        # the scenario: on a landscape the bridge also serves the Map panel's view
                        [
                            "-p",
                            f"port:={args.foxglove_port}",
                            "-p",
                            f"scenario_file:={scenario_path}",
                            "-p",
                            f"uav_count:={uav_count}",
                        ],  # fmt: skip
                    ),
                )
                _wait_for_node(sup, "foxglove_bridge", procs, wall0 + args.wall_timeout, args.quiet)
                print(f"[run_mission] Foxglove: ws://127.0.0.1:{args.foxglove_port}", file=sys.stderr)
            for k in range(uav_count):
                ns = args.agent_netns
                procs.start(
                    f"agent_{k}",
                    (["ip", "netns", "exec", ns[k % len(ns)]] if ns else [])
                    + ros_run_argv(
                        "fire_uav_agent",
                        "uav_agent",
                        [
                            "-r",
                            f"__ns:=/uav_{k}",
                            "-p",
                            f"uav_id:={k}",
                            "--params-file",
                            str(params[f"agent_{k}"]),
                            *sum((["-p", a] for a in args.agent_arg), []),
                        ],
                    ),
                )
            procs.start(
                "world", ros_run_argv("fire_world_sim", "world_node", ["--params-file", str(params["world"])])
            )
            outcome = _supervise(sup, procs, summary, progress, args, uav_count, wall0)
        except KeyboardInterrupt:
            outcome = "interrupted"
            print("\n[run_mission] Ctrl-C: ending every process", file=sys.stderr)
        finally:
            progress.close()
            if outcome in ("complete", "time_limit"):
                _let_the_world_end(procs)
            codes = _stop_in_order(procs, agents)
            if sup is not None:
                # drain what is still in flight (final states, events)
                end = time.monotonic() + 0.5
                while time.monotonic() < end:
                    sup.executor.spin_once(timeout_sec=0.05)
                sup.executor.shutdown()
                sup.node.destroy_node()
            rclpy.try_shutdown()
    summary.settle_states()
    result = summary.as_dict(outcome=outcome, wall_s=time.monotonic() - wall0, steps=sup.steps if sup else 0)
    if sup is not None and sup.first_truth_wall is not None and sup.last_truth_wall > sup.first_truth_wall:
        stepped = sup.steps - 1 - sup.first_step
        result["steps_per_wall_s"] = round(stepped / (sup.last_truth_wall - sup.first_truth_wall), 2)
        result["steps_per_wall_s_note"] = "over the stepping phase (first to last truth message)"
        for name, p in result["processes"].items():
            # from the first step to the process's last CPU sample, over the steps between them
            sampled = sup.steps_at_sample.get(name, sup.steps) - 1 - sup.first_step
            if name in sup.cpu_at_first_step and sampled > 0:
                cpu_s = summary.proc_stats[name].cpu_s
                p["cpu_ms_per_step"] = round(1000 * (cpu_s - sup.cpu_at_first_step[name]) / sampled, 3)
    result.update(
        {
            "scenario": scenario.name,
            "scenario_file": str(scenario_path),
            "seed": seed,
            "mode": args.mode,
            "domain_id": domain,
            "bag": None if args.no_record else str(out / "bag"),
            "exit_codes": codes,
            "pids": {n: c.pid for n, c in procs.children.items()},
            "control_period_s": scenario.timing.control_period_s,
        }
    )
    geo = geo_summary(scenario, uav_count)
    if geo is not None:  # a scenario on a landscape: positions in degrees too
        result["geo"] = geo
    if scenario.notes:  # e.g. water bodies of a landscape too small to refill from
        result["scenario_notes"] = list(scenario.notes)
    (out / "summary.json").write_text(json.dumps(result, indent=2) + "\n")
    if sup is not None and sup.truth_walls:
        # the stepping's wall time within the run (fire_bench.speed.dds_row: a window of the mission
        # measured in one run): [monotonic wall s, steps, world CPU s, agents' mean CPU s (None unless
        # all were sampled)] ~0.25 s apart, and [monotonic wall s, steps] at every truth message
        stepping = {
            "stepping_series": [list(r) for r in sup.stepping_series],
            "truth_walls": [list(r) for r in sup.truth_walls],
        }
        (out / "stepping.json").write_text(json.dumps(stepping) + "\n")
    print("\nMission summary\n" + table(result) + f"\n\n  written: {out / 'summary.json'}", file=sys.stderr)
    if not args.no_record and not args.no_report:
        rep = subprocess.run(
            [str(ROOT / "scripts/report"), str(out / "bag"), "-o", str(out / "report")], env=env, check=False
        )
        if rep.returncode == 0:
            print(f"  report:  {out / 'report' / 'index.html'}", file=sys.stderr)
        else:
            print(
                f"  report failed (exit {rep.returncode}); the bag is kept at {out / 'bag'}", file=sys.stderr
            )
    return mission_exit_status(outcome, uav_count, args.max_duration)


def _point_latest_at(out: Path) -> None:
    """``runs/latest`` -> the run folder just made, when it is one of ``runs/`` (the README's
    replay and report examples name it); other ``--out`` places leave it alone."""
    runs = (ROOT / "runs").resolve()
    if out.parent != runs:
        return
    tmp = runs / f".latest-{os.getpid()}"
    with contextlib.suppress(FileNotFoundError):
        tmp.unlink()
    tmp.symlink_to(out.name)
    os.replace(tmp, runs / "latest")  # atomic: a concurrent run's link is replaced, never half-made


#: [s wall] the longest the runner lets a finished world take to exit by itself: its own cap on
#: waiting for acknowledgements (fire_world_sim.world_node.FINAL_ACK_CAP_WALL_S, 20 s) and a margin
WORLD_EXIT_WALL_S = 30.0


#: [s wall] the agents' grace at the end (``ProcessGroup.stop``): SIGINT, then SIGTERM (to an agent,
#: a second signal: it stops waiting for acknowledgements) after their own cap on that wait
#: (``fire_uav_common.final_acks.FINAL_ACK_CAP_WALL_S``, 20 s) and a margin, SIGKILL as long after
AGENT_STOP_GRACE_WALL_S = 2 * (FINAL_ACK_CAP_WALL_S + 5.0)


def _stop_in_order(
    procs: ProcessGroup, agents: list[str], agent_grace_s: float = AGENT_STOP_GRACE_WALL_S
) -> dict[str, int | None]:
    """End every process, publishers first, so that the recorder (and a Foxglove bridge) take
    their last messages; their exit codes.

    The agents first, each of which, signalled, exits once every reader has acknowledged its
    messages (at most FINAL_ACK_CAP_WALL_S; fire_uav_common.final_acks): ``agent_grace_s`` lets
    them; then the world (gone already after a complete mission, ``_let_the_world_end``) and the
    perimeter viewer (it publishes the recorded /viz/perimeter from the agents' /fleet/perimeter);
    then the rest, the recorder among them (tests/system/test_agent_last_messages.py)."""
    codes = procs.stop([a for a in agents if a in procs.children], grace_s=agent_grace_s)
    codes.update(procs.stop_all(first=["world", "perimeter_viewer"]))
    return codes


def _let_the_world_end(procs: ProcessGroup, timeout_s: float = WORLD_EXIT_WALL_S) -> None:
    """After MISSION_COMPLETE, wait for the world to exit by itself before anything is stopped.

    The world exits once every matched reader (the recorder's among them) has acknowledged its
    messages. Signalled at once, as the runner did, it exited a few milliseconds after its final
    publish: a final /world/truth that had not reached the recorder yet (a datagram or shared-memory
    slot lost on a busy machine, repaired only on the writer's next heartbeat, 3 s in Fast DDS) was
    lost with it, and the recorder, stopped next, could not take it (tests/system/
    test_recorder_final_truth.py; the likely cause of a bag one truth short, "599 vs 600 truth
    messages" in test_determinism)."""
    world = procs.children.get("world")
    if world is None:
        return
    try:
        world.popen.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        print(
            f"[run_mission] the world did not exit within {timeout_s:g} s of the mission's end: stopping it",
            file=sys.stderr,
        )


def _wait_for_node(
    sup: Supervisor,
    name: str,
    procs: ProcessGroup,
    deadline_s: float,
    quiet: bool,
    report_every_s: float = 10.0,
) -> None:
    """Wait until node ``name`` is on the ROS graph (the recorder before step 0: the bag from the
    first message). As long as its process runs it may take its time: on a loaded machine a
    Python node's imports alone took over 20 s, the fixed wait this replaced, and a mission then
    failed that would have run. So the wait ends only when the node appears (return), its process
    exits (MissionError with its log's tail) or the run's ``--wall-timeout`` (``deadline_s``, on
    ``time.monotonic``) passes; a line every ``report_every_s`` says what the runner waits for."""
    t0 = time.monotonic()
    next_report = t0 + report_every_s
    while True:
        if name in sup.node.get_node_names():
            return
        if not procs.children[name].alive():
            raise MissionError(f"{name} exited at start:\n{procs.tail(name)}")
        now = time.monotonic()
        if now >= deadline_s:
            raise MissionError(
                f"{name} did not appear on the ROS graph within {now - t0:.0f} s (the run's --wall-timeout):\n"
                f"{procs.tail(name)}"
            )
        if now >= next_report:
            next_report = now + report_every_s
            if not quiet:
                print(
                    f"[run_mission] waiting for {name} to join the ROS graph: {now - t0:.0f} s "
                    "(its process is running)",
                    file=sys.stderr,
                )
        sup.executor.spin_once(timeout_sec=0.1)


def _fail_on_agent_error_before_start(procs: ProcessGroup, uav_count: int) -> None:
    """An agent that exited with an error before step 0: the lockstep world would wait for its
    AGENT_READY for ever (a fault plan kills by signal, a negative return code, and only later)."""
    for k in range(uav_count):
        child = procs.children[f"agent_{k}"]
        code = child.popen.poll()
        if code is not None and code > 0:
            raise MissionError(f"agent_{k} exited (code {code}) before step 0:\n{procs.tail(child.name)}")


def stepping_row(
    now: float, steps: int, cpu_s: dict[str, float], uav_count: int
) -> tuple[float, int, float | None, float | None]:
    """One row of ``stepping.json``'s ``stepping_series``: (monotonic s, steps, the world's CPU s,
    the agents' mean CPU s) from the processes' CPU seconds sampled now (``cpu_s``, by process
    name: ``world``, ``agent_K``). The agents' mean only when every agent of the fleet was
    sampled (a mean over the survivors would jump when one dies, and read as a change in CPU per
    step); None with no agents (a 0-UAV run) or any missing; the world's None if not sampled."""
    agents = [v for k, v in cpu_s.items() if k.startswith("agent_")]
    mean = sum(agents) / len(agents) if agents and len(agents) == uav_count else None
    return (round(now, 3), steps, cpu_s.get("world"), None if mean is None else round(mean, 3))


def _supervise(
    sup: Supervisor,
    procs: ProcessGroup,
    summary: LiveSummary,
    progress: MissionProgress,
    args: argparse.Namespace,
    uav_count: int,
    wall0: float,
) -> str:

    def sample_all() -> None:
        now, cpu = time.monotonic(), {}
        for name, child in procs.children.items():
            st = proc_sample(child.pid)
            if st is not None:
                summary.proc_stats[name] = st
                sup.steps_at_sample[name] = sup.steps
                cpu[name] = st.cpu_s
        if sup.first_truth_wall is not None and not sup.done:
            sup.stepping_series.append(stepping_row(now, sup.steps, cpu, uav_count))

    last_sample = 0.0
    while True:
        sup.executor.spin_once(timeout_sec=0.02 if sup.resume_at else 0.1)
        sup.resume_stalled()
        if time.monotonic() - last_sample > (0.25 if sup.first_truth_wall is not None else 1.0):
            last_sample = time.monotonic()
            sample_all()
        alive_agents = sum(1 for k in range(uav_count) if procs.children[f"agent_{k}"].alive())
        if sup.steps == 0 and alive_agents < uav_count:
            _fail_on_agent_error_before_start(procs, uav_count)
        progress.show(sup.t_s, summary, uav_count, alive_agents)
        if sup.done:
            sample_all()  # the CPU at the last step (a fast mission can end between samples)
            return "complete" if summary.complete_success else "time_limit"
        world = procs.children["world"]
        if not world.alive():
            # let late events arrive, then judge
            end = time.monotonic() + 1.0
            while time.monotonic() < end and not sup.done:
                sup.executor.spin_once(timeout_sec=0.05)
            if sup.done:
                continue
            raise MissionError(
                f"the world exited (code {world.popen.returncode}) before the mission ended:\n"
                f"{procs.tail('world')}"
            )
        if "recorder" in procs.children and not procs.children["recorder"].alive():
            raise MissionError(f"the recorder exited during the mission:\n{procs.tail('recorder')}")
        if time.monotonic() - wall0 > args.wall_timeout:
            return "wall_timeout"


def _terminate(signum: int, frame: object) -> None:
    raise KeyboardInterrupt  # SIGTERM ends the run like Ctrl-C: every child is stopped, the summary written


def main(argv: list[str] | None = None) -> int:
    signal.signal(signal.SIGTERM, _terminate)
    args = build_parser().parse_args(argv)
    try:
        if args.check_determinism:
            from fire_mission.determinism import check_twice

            return check_twice(args, run)
        return run(args)
    except MissionError as e:
        print(f"run_mission: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
