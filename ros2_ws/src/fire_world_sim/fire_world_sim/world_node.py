"""ROS 2 adapter of :class:`fire_world_sim.world.World`: the clock authority of the fleet.

Publishes ``/clock``, one ``SensorBundle`` per vehicle per control step, ``/world/truth``,
``/world/events``, ``/viz/world``, ``/viz/fire_grid`` and ``/tf`` (``map -> uav_<k>``, truth, at the
viz rate); subscribes ``/uav_<k>/cmd`` and
``/uav_<k>/payload`` (docs/protocol.md). The world itself runs on the steady wall clock;
lockstep waiting is a steady-clock timer reset at each step, never a sleep.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import rclpy
from builtin_interfaces.msg import Time
from fire_uav_common import topics
from fire_uav_common.auth import Authenticator, parse_key
from fire_uav_common.codecs.sensor_bundle import write_sensor_bundle
from fire_uav_common.constants import CellState, EventType, PayloadAction, VehicleStatus
from fire_uav_common.lockstep import OfflineWindow, offline_uavs, parse_schedule
from fire_uav_common.scenario import ScenarioError, load_scenario
from fire_uav_common.stamps import NS_PER_S, stamp_to_ns, to_time_msg
from fire_uav_msgs.msg import (
    FireTruth,
    MissionEvent,
    PayloadRequest,
    VehicleTruth,
    WorldTruth,
)
from geometry_msgs.msg import Point, TransformStamped, TwistStamped
from nav_msgs.msg import OccupancyGrid
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.serialization import deserialize_message
from rclpy.task import Future
from rosgraph_msgs.msg import Clock as ClockMsg
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

from . import viz
from .errors import ConfigError
from .fires.raster import RasterFireModel
from .world import Bundle, Command, Event, StepResult, World

FRAME = "map"
#: [s wall] lockstep: re-send a bundle to an agent whose answer is not in after this long
RESEND_AFTER_WALL_S = 5.0


@dataclass(frozen=True)
class WorldNodeConfig:
    scenario_file: str
    seed: int
    uav_count: int
    mode: str
    real_time_factor: float
    liveness_check_wall_s: float
    startup_timeout_wall_s: float
    offline_schedule: tuple[OfflineWindow, ...]
    max_duration_s: float
    viz_rate_hz: float
    wait_for_subscribers: int
    no_fleet: bool = False


def stamp(ns: int) -> Time:
    """Integer nanoseconds of sim time -> ``builtin_interfaces/Time``."""
    return to_time_msg(ns, Time)


class WorldNode(Node):
    """World simulation node; see the package README for parameters and topics."""

    def __init__(self) -> None:
        super().__init__("world")
        self.cfg = self._read_parameters()
        self.auth = self._read_auth()
        self.rejected: dict[str, int] = {}  # commands / payload requests rejected, per kind
        self._seen_tags: set[bytes] = set()  # tags taken this step: a replayed request is a duplicate
        overrides = (
            {"timing.max_duration_s": self.cfg.max_duration_s} if self.cfg.max_duration_s > 0 else None
        )
        scenario = load_scenario(self.cfg.scenario_file, overrides=overrides)
        seed = scenario.seed if self.cfg.seed < 0 else self.cfg.seed
        n = 0 if self.cfg.no_fleet else self.cfg.uav_count
        self.world = World(scenario, seed, n, no_fleet=self.cfg.no_fleet)
        self.n = self.world.uav_count
        self.get_logger().info(
            f"scenario {scenario.name!r} ({self.cfg.scenario_file}), seed {seed}, {self.n} UAVs, "
            f"fires {scenario.fires.model}, mode {self.cfg.mode}"
        )
        self.done = Future()
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self.pub_clock = topics.publisher(self, topics.CLOCK_SPEC)
        self.pub_truth = topics.publisher(self, topics.WORLD_TRUTH_SPEC)
        self.pub_events = topics.publisher(self, topics.WORLD_EVENTS_SPEC)
        self.pub_viz = topics.publisher(self, topics.VIZ_WORLD_SPEC)
        self.pub_grid = topics.publisher(self, topics.VIZ_FIRE_GRID_SPEC)
        self.pub_tf = topics.publisher(self, topics.TF_SPEC)
        self._marker_book = viz.MarkerBook()
        self.pub_sensors = {}
        for i in range(self.n):
            self.pub_sensors[i] = topics.publisher(self, topics.SENSORS_SPEC, uav_id=i)
            if self.auth is None:  # signed: the command comes from the PayloadRequest (_on_cmd)
                topics.subscription(self, topics.CMD_SPEC, lambda m, i=i: self._on_cmd(i, m), uav_id=i)
            # raw: the tag is checked on the bytes as the agent sent them (auth.check_serialized)
            topics.subscription(
                self, topics.PAYLOAD_SPEC, lambda d, i=i: self._on_payload(i, d), uav_id=i, raw=True
            )
        self._ready: set[int] = set()
        topics.subscription(self, topics.FLEET_EVENTS_SPEC, self._on_fleet_event)
        self._commands: dict[int, Command | None] = {}
        self._payload: dict[int, list[int]] = {}
        self._awaited_ns = 0  # stamp the answers must carry (t_k of the next step)
        self._waiting: set[int] = set()  # agents whose command of this step is not in yet
        self._waiting_payload: set[int] = set()  # ... whose payload request is not in yet
        self._lost: set[int] = set()  # agents whose process is gone (unscheduled, DDS discovery)
        self._told_crashed: set[int] = set()  # agents sent a bundle saying their vehicle crashed
        self._sent: dict[int, bytes] = {}  # this step's bundles (serialised), to re-send (_check_liveness)
        self._sent_step = 0
        self._wait_since_ns = 0  # [steady ns] when this step's wait began
        self._resent_ns = 0  # [steady ns] when bundles were last re-sent
        self._asked_again: dict[int, int] = {}  # uav -> stamp of the step whose bundle it got twice
        self._started = False
        self._finished = False  # the mission is over: answers to its last bundle are not awaited
        self._last_viz_ns = -(10**18)
        self._viz_period_ns = int(NS_PER_S / self.cfg.viz_rate_hz)
        self._start_wall_ns = self._steady.now().nanoseconds
        self.pub_clock.publish(ClockMsg(clock=stamp(0)))
        if self.cfg.mode == "lockstep":
            self._startup_timer = self.create_timer(0.05, self._check_startup, clock=self._steady)
            # not a timeout: a live agent is waited for however slow it is; this only notices an
            # agent whose process is gone (its publishers leave the DDS graph)
            self._liveness_timer = self.create_timer(
                self.cfg.liveness_check_wall_s, self._check_liveness, clock=self._steady
            )
            self._liveness_timer.cancel()
        else:
            period = self.world.control_period_s / self.cfg.real_time_factor
            self._rt_timer = self.create_timer(period, self._on_realtime_tick, clock=self._steady)

    # --- parameters --------------------------------------------------------------------------
    def _read_parameters(self) -> WorldNodeConfig:
        def d(text: str, **kw: object) -> ParameterDescriptor:
            return ParameterDescriptor(description=text, read_only=True, **kw)

        def frange(lo: float, hi: float) -> list[FloatingPointRange]:
            return [FloatingPointRange(from_value=lo, to_value=hi, step=0.0)]

        self.declare_parameter("scenario_file", "", d("scenario YAML (required)"))
        self.declare_parameter(
            "seed",
            -1,
            d(
                "RNG seed; -1 = the scenario's",
                integer_range=[IntegerRange(from_value=-1, to_value=2**31 - 1, step=1)],
            ),
        )
        self.declare_parameter(
            "uav_count",
            0,
            d(
                "vehicles; 0 = the scenario's",
                integer_range=[IntegerRange(from_value=0, to_value=255, step=1)],
            ),
        )
        self.declare_parameter("mode", "lockstep", d("lockstep | realtime"))
        self.declare_parameter("real_time_factor", 1.0, d("realtime mode: sim seconds per wall second (> 0)"))
        self.declare_parameter(
            "liveness_check_wall_s",
            0.5,
            d(
                "[s wall] lockstep: how often to check that the agents waited for still have a process "
                "(DDS graph); never a timeout on a live agent",
                floating_point_range=frange(0.01, 60.0),
            ),
        )
        self.declare_parameter(
            "startup_timeout_wall_s",
            120.0,
            d(
                "[s wall] wait for every agent's ready handshake before step 0",
                floating_point_range=frange(0.0, 3600.0),
            ),
        )
        self.declare_parameter(
            "offline_schedule",
            "",
            d(
                "lockstep fault schedule 'K@T1:T2;K@T1' [s sim]: agent K offline (frozen / killed); see fire_uav_common.lockstep"
            ),
        )
        self.declare_parameter("max_duration_s", 0.0, d("[s sim] mission limit; 0 = the scenario's"))
        self.declare_parameter(
            "wait_for_subscribers",
            0,
            d(
                "[-] before step 0, also wait (up to startup_timeout_wall_s) until /world/truth has this "
                "many subscribers, e.g. the recorder, so a bag starts at step 0",
                integer_range=[IntegerRange(from_value=0, to_value=1000, step=1)],
            ),
        )
        self.declare_parameter(
            "viz_rate_hz",
            2.0,
            d("[Hz sim] /viz/* publication rate", floating_point_range=frange(0.01, 100.0)),
        )
        self.declare_parameter(
            "no_fleet",
            False,
            d("no vehicle at all: the fire burns alone (the suppression baseline, --uavs 0)"),
        )
        g = self.get_parameter
        cfg = WorldNodeConfig(
            scenario_file=g("scenario_file").value,
            seed=int(g("seed").value),
            uav_count=int(g("uav_count").value),
            mode=str(g("mode").value),
            real_time_factor=float(g("real_time_factor").value),
            liveness_check_wall_s=float(g("liveness_check_wall_s").value),
            startup_timeout_wall_s=float(g("startup_timeout_wall_s").value),
            offline_schedule=self._schedule(str(g("offline_schedule").value)),
            max_duration_s=float(g("max_duration_s").value),
            viz_rate_hz=float(g("viz_rate_hz").value),
            no_fleet=bool(g("no_fleet").value),
            wait_for_subscribers=int(g("wait_for_subscribers").value),
        )
        if any(w.uav_id >= 256 for w in cfg.offline_schedule):
            raise ConfigError("parameter offline_schedule: UAV ids are 0..255")
        if not cfg.scenario_file:
            raise ConfigError("parameter scenario_file is required (path to a scenario YAML)")
        if cfg.mode not in ("lockstep", "realtime"):
            raise ConfigError(f"parameter mode must be 'lockstep' or 'realtime', got {cfg.mode!r}")
        if not (math.isfinite(cfg.real_time_factor) and cfg.real_time_factor > 0):
            raise ConfigError(f"parameter real_time_factor must be > 0, got {cfg.real_time_factor}")
        if not (math.isfinite(cfg.max_duration_s) and cfg.max_duration_s >= 0):
            raise ConfigError(f"parameter max_duration_s must be >= 0, got {cfg.max_duration_s}")
        return cfg

    def _read_auth(self) -> Authenticator | None:
        """``auth`` / ``fleet_key`` (docs/security.md); the key is undeclared once read, never logged."""
        self.declare_parameter(
            "auth",
            True,
            ParameterDescriptor(read_only=True, description="verify HMAC-SHA256 tags (docs/security.md)"),
        )
        self.declare_parameter(
            "fleet_key", "", ParameterDescriptor(description="per-mission key, 64 hex digits")
        )
        key = str(self.get_parameter("fleet_key").value)
        self.undeclare_parameter("fleet_key")
        if not bool(self.get_parameter("auth").value):
            self.get_logger().warning("authentication off: commands are taken from /uav_<k>/cmd unverified")
            return None
        if not key:
            raise ConfigError(
                "parameter fleet_key is required when auth is true (the runner writes one per mission)"
            )
        try:
            return Authenticator(parse_key(key))
        except ValueError as e:
            raise ConfigError(f"parameter fleet_key: {e}") from None

    def _reject(self, uid: int, topic: str, reason: str) -> None:
        """Count a rejected command / payload request of kind ``reason`` (throttled warning)."""
        self.rejected[reason] = self.rejected.get(reason, 0) + 1
        self.get_logger().warning(
            f"rejected a message on {topic} for uav {uid}: {reason} (rejections so far: {self.rejected})",
            throttle_duration_sec=2.0,
        )

    def _stamp_problem(self, uid: int, ns: int) -> str | None:
        """Why a command / request for vehicle ``uid`` stamped ``ns`` cannot be taken now, or None."""
        if self.world.vehicles[uid].status == VehicleStatus.CRASHED:
            return "crashed vehicle"
        if self.cfg.mode == "lockstep":
            if not self._started or ns != self._awaited_ns:
                return "stamp out of range"
        elif not 0 <= ns <= self.world.t_ns:
            return "stamp out of range"
        return None

    @staticmethod
    def _schedule(text: str) -> tuple[OfflineWindow, ...]:
        try:
            return parse_schedule(text)
        except ValueError as e:
            raise ConfigError(f"parameter offline_schedule: {e}") from None

    # --- lockstep ----------------------------------------------------------------------------
    def _on_fleet_event(self, msg: MissionEvent) -> None:
        if msg.type == EventType.AGENT_READY and 0 <= msg.uav_id < self.n:
            self._ready.add(int(msg.uav_id))

    def _check_startup(self) -> None:
        """Step 0 starts when every agent said it is ready and the world's own topics are matched."""
        missing = [
            i
            for i in range(self.n)
            if i not in self._ready
            or self.pub_sensors[i].get_subscription_count() == 0
            or self.count_publishers(topics.CMD_SPEC.for_uav(i)) == 0
        ]
        waited_s = (self._steady.now().nanoseconds - self._start_wall_ns) / NS_PER_S
        short = self.pub_truth.get_subscription_count() < self.cfg.wait_for_subscribers
        if (missing or short) and waited_s < self.cfg.startup_timeout_wall_s:
            self.pub_clock.publish(ClockMsg(clock=stamp(0)))
            return
        self._startup_timer.cancel()
        if short:
            self.get_logger().warn(
                f"starting with fewer than {self.cfg.wait_for_subscribers} /world/truth subscribers "
                f"after {waited_s:.1f} s"
            )
        if missing:
            self.get_logger().error(
                f"starting without agents {missing}: no ready handshake after {waited_s:.1f} s "
                "(startup_timeout_wall_s); this run is not reproducible"
            )
            for i in missing:
                self.world.vehicles[i].responsive = False
        else:
            self.get_logger().info(f"all {self.n} agents present after {waited_s:.1f} s; starting")
        self._started = True
        self._advance()

    def _advance(self) -> None:
        """Run one world step with what was received, publish, and wait for the answers."""
        if self.done.done():
            return
        result = self.world.step(self._commands, self._payload)
        self._commands, self._payload = {}, {}
        self._seen_tags.clear()
        self._publish(result)
        if result.complete:
            self._finish(result)
            return
        self._awaited_ns = result.stamp_ns
        if self.cfg.mode == "lockstep":
            self._waiting = set(self.world.awaited_uavs()) - self._offline(result.step) - self._lost
            # every awaited agent sends exactly one PayloadRequest per step (ACTION_NONE if nothing):
            # a request on its own topic may arrive after the command, so it is waited for too
            self._waiting_payload = set(self._waiting)
            if not self._waiting:
                self._advance_soon()
                return
            self._wait_since_ns = self._resent_ns = self._steady.now().nanoseconds
            self._liveness_timer.reset()

    def _offline(self, step: int) -> frozenset[int]:
        """Agents the fault schedule takes offline during ``step`` (no bundle, not waited for)."""
        return offline_uavs(self.cfg.offline_schedule, step, self.world.control_period_s)

    def _advance_soon(self) -> None:
        # nobody to wait for: step on the next executor turn (no recursion, no sleep)
        self._liveness_timer.cancel()
        t = self.create_timer(0.0, lambda: (self.destroy_timer(t), self._advance()), clock=self._steady)

    def _check_liveness(self) -> None:
        """Drop from the wait an agent whose process is gone: its command publisher left the graph.

        Fast DDS removes a participant when its lease expires (10 s with the project's discovery
        profile), so a killed agent not in the schedule holds the fleet up that long, once. This is
        the only wall-clock-dependent path of lockstep, and it runs only for unscheduled deaths.
        """
        self._resend_if_stuck()
        gone = sorted(i for i in self._waiting if self.count_publishers(topics.CMD_SPEC.for_uav(i)) == 0)
        if not gone:
            return
        for i in gone:
            self._lost.add(i)
            self._waiting.discard(i)
            self._waiting_payload.discard(i)
            self.get_logger().error(
                f"step {self.world.step_index}: agent {i}'s process is gone (not in the fault schedule); "
                "no longer waiting for it, so this run is not reproducible"
            )
            self.pub_events.publish(
                MissionEvent(
                    header=self._hdr(self._awaited_ns),
                    type=int(EventType.AGENT_LOST),
                    uav_id=i,
                    peer_id=-1,
                    fire_id=-1,
                    x_m=math.nan,
                    y_m=math.nan,
                    value=0.0,
                    detail="process gone from the DDS graph",
                )
            )
        self._maybe_advance()

    def _resend_if_stuck(self, after_wall_s: float = RESEND_AFTER_WALL_S) -> None:
        """Re-send this step's bundle to every live agent whose answer is not in after ``after_wall_s``.

        A reliable DDS writer should never need this, but two fresh-clone test runs (2026-12-01/02)
        hung in a lockstep wait that never ended (cause not found; 8 repeats on an idle machine did
        not hang): suspected a bundle or an answer lost between matched endpoints. The copy is harmless: an agent that has not run the step yet
        ignores it (it answers only a newer bundle), and one that has answered already sends its
        answer again (agent_node._on_bundle); the world takes one answer per step. It changes no
        step's inputs, so a lockstep run stays reproducible; the warning names who was waited for.
        """
        now = self._steady.now().nanoseconds
        if (now - self._resent_ns) / NS_PER_S < after_wall_s:
            return
        self._resent_ns = now
        late = sorted((self._waiting | self._waiting_payload) & set(self._sent))
        waited_s = (now - self._wait_since_ns) / NS_PER_S
        self.get_logger().warning(
            f"step {self._sent_step}: waiting {waited_s:.0f} s for the answers of agents {late} "
            f"(command: {sorted(self._waiting)}, payload request: {sorted(self._waiting_payload)}); "
            "re-sending their bundles"
        )
        for uid in late:
            self._asked_again[uid] = self._awaited_ns
            self.pub_sensors[uid].publish(self._sent[uid])

    def _second_answer(self, uid: int, ns: int, problem: str) -> bool:
        """True for the spare copy of an answer the world asked for again (not a rejection)."""
        return problem in ("stamp out of range", "duplicate") and self._asked_again.get(uid) == ns

    def _maybe_advance(self) -> None:
        """Step once every awaited agent's command and payload request of this step are in."""
        if not self._waiting and not self._waiting_payload and not self.done.done():
            self._liveness_timer.cancel()
            self._advance()

    def _on_cmd(self, uid: int, msg: TwistStamped) -> None:
        if self._finished:
            return  # the agents answer the mission's last bundle too: nothing waits for that
        # only subscribed unsigned: TwistStamped has no tag, so signed the command comes from the
        # PayloadRequest (_on_payload) and /uav_k/cmd is not subscribed at all
        topic = topics.CMD_SPEC.for_uav(uid)
        problem = self._stamp_problem(uid, stamp_to_ns(msg.header.stamp))
        if problem is not None:
            if self._started and not self._second_answer(uid, stamp_to_ns(msg.header.stamp), problem):
                self._reject(uid, topic, problem)  # before step 0 nothing is awaited yet
            return
        t = msg.twist
        cmd = Command(float(t.linear.x), float(t.linear.z), float(t.angular.z))
        if not cmd.is_finite():
            self._reject(uid, topic, "nan/inf")
        if self.cfg.mode == "realtime":
            self._commands[uid] = cmd if cmd.is_finite() else None
            return
        self._commands[uid] = cmd if cmd.is_finite() else None
        self._waiting.discard(uid)
        self._maybe_advance()

    def _on_payload(self, uid: int, data: bytes) -> None:
        if self._finished:
            return  # an answer to the last bundle (see _on_cmd)
        topic = topics.PAYLOAD_SPEC.for_uav(uid)
        try:
            msg = deserialize_message(data, PayloadRequest)
        except RuntimeError:  # rclpy's RMWError: bytes that are no CDR of a PayloadRequest
            return self._reject(uid, topic, "undecodable")
        ns = stamp_to_ns(msg.header.stamp)
        if msg.uav_id != uid:
            return self._reject(uid, topic, "wrong id")
        if self.auth is not None and not self.auth.check_serialized(data, topic, uid, ns):
            return self._reject(uid, topic, "bad auth")
        if msg.action not in tuple(PayloadAction):
            return self._reject(uid, topic, "unknown action")
        problem = self._stamp_problem(uid, ns)
        if problem is not None:
            if self._started and not self._second_answer(uid, ns, problem):
                self._reject(uid, topic, problem)
            return
        if uid not in self._waiting_payload and self._second_answer(uid, ns, "duplicate"):
            return  # a copy of requests already taken (the agent re-sends all of its step's answer)
        if self.auth is not None:
            tag = bytes(bytearray(msg.auth))
            if tag in self._seen_tags:
                if self._second_answer(uid, ns, "duplicate"):
                    return
                return self._reject(uid, topic, "duplicate")
            self._seen_tags.add(tag)
        if self.auth is not None and uid not in self._commands:  # the signed command (docs/security.md)
            cmd = Command(
                float(msg.cmd_linear_x_mps), float(msg.cmd_linear_z_mps), float(msg.cmd_angular_z_radps)
            )
            if not cmd.is_finite():
                self._reject(uid, topic, "nan/inf")
            self._commands[uid] = cmd if cmd.is_finite() else None
            self._waiting.discard(uid)
        if msg.action != PayloadAction.NONE:
            self._payload.setdefault(uid, []).append(int(msg.action))
        if self.cfg.mode == "lockstep":
            self._waiting_payload.discard(uid)
            self._maybe_advance()

    def _on_realtime_tick(self) -> None:
        if not self._started:
            self._started = True
        self._advance()

    # --- finishing ---------------------------------------------------------------------------
    def _finish(self, result: StepResult) -> None:
        self._finished = True
        self.get_logger().info(
            f"mission complete at t = {result.stamp_ns / NS_PER_S:.1f} s: {result.complete_reason}; "
            f"rejected commands / payload requests: {self.rejected or 'none'}"
        )
        for timer in (getattr(self, "_liveness_timer", None), getattr(self, "_rt_timer", None)):
            if timer is not None:
                timer.cancel()
        # keep spinning ~1 s wall so the last messages are delivered
        self._exit_timer = self.create_timer(1.0, lambda: self.done.set_result(0), clock=self._steady)

    # --- publishing --------------------------------------------------------------------------
    def _publish(self, r: StepResult) -> None:
        self.pub_clock.publish(ClockMsg(clock=stamp(r.stamp_ns)))
        offline = self._offline(r.step) if self.cfg.mode == "lockstep" else frozenset()
        self._sent, self._sent_step = {}, r.step
        for uid, b in sorted(r.bundles.items()):
            if uid not in offline:  # an offline agent's computer reads no sensors
                self._sent[uid] = self._bundle_bytes(b)
                self.pub_sensors[uid].publish(self._sent[uid])
                if b.vehicle_status == VehicleStatus.CRASHED:
                    self._told_crashed.add(uid)
        # An agent whose vehicle fell while it was offline or silent gets one last bundle saying so,
        # the first step it is online again: its final state tells the peers to stop waiting for it.
        for v in r.vehicles:
            if (
                v.status == VehicleStatus.CRASHED
                and v.uav_id not in self._told_crashed
                and v.uav_id not in offline
            ):
                last = Bundle(v.uav_id, r.step, r.stamp_ns, self.world.control_period_s)
                last.water_kg, last.vehicle_status = v.water_kg, int(VehicleStatus.CRASHED)
                self._sent[v.uav_id] = self._bundle_bytes(last)
                self.pub_sensors[v.uav_id].publish(self._sent[v.uav_id])
                self._told_crashed.add(v.uav_id)
        self.pub_truth.publish(self._truth_msg(r))
        for e in r.events:
            self.pub_events.publish(self._event_msg(e))
            if e.type == EventType.CRASH:
                self.get_logger().warn(f"uav {e.uav_id} crashed: {e.detail}")
        if r.stamp_ns - self._last_viz_ns >= self._viz_period_ns or r.complete:
            self._last_viz_ns = r.stamp_ns
            self.pub_viz.publish(self._markers(r))
            self.pub_tf.publish(self._tf_msg(r))
            if isinstance(self.world.fires, RasterFireModel):
                self.pub_grid.publish(self._grid_msg(r.stamp_ns))

    def _bundle_bytes(self, b: Bundle) -> bytes:
        """``b`` as a serialised SensorBundle (``fire_uav_common.codecs.sensor_bundle``), published as it is."""
        return write_sensor_bundle(b, self.world.scenario.sensors.gyro.sigma_radps)

    @staticmethod
    def _hdr(ns: int):
        from std_msgs.msg import Header

        return Header(stamp=stamp(ns), frame_id=FRAME)

    def _truth_msg(self, r: StepResult) -> WorldTruth:
        m = WorldTruth(
            header=self._hdr(r.stamp_ns),
            step=r.step,
            min_separation_m=float(r.min_separation_m),
            collisions=int(r.collisions),
        )
        for v in r.vehicles:
            m.vehicles.append(
                VehicleTruth(
                    uav_id=v.uav_id,
                    status=v.status,
                    x_m=float(v.x_m),
                    y_m=float(v.y_m),
                    z_m=float(v.z_m),
                    yaw_rad=float(v.yaw_rad),
                    v_lin_mps=float(v.v_lin_mps),
                    v_z_mps=float(v.v_z_mps),
                    omega_z_radps=float(v.omega_z_radps),
                    water_kg=float(v.water_kg),
                    commands_clamped=int(v.commands_clamped),
                    commands_missed=int(v.commands_missed),
                )
            )
        for f in r.fires:
            m.fires.append(
                FireTruth(
                    fire_id=int(f.fire_id),
                    status=int(f.status),
                    x_m=float(f.x_m),
                    y_m=float(f.y_m),
                    extent_m=float(f.extent_m),
                    area_m2=float(f.area_m2),
                    drops_received=int(f.drops_received),
                )
            )
        return m

    def _event_msg(self, e: Event) -> MissionEvent:
        return MissionEvent(
            header=self._hdr(e.stamp_ns),
            type=int(e.type),
            uav_id=int(e.uav_id),
            peer_id=-1,
            fire_id=int(e.fire_id),
            x_m=float(e.x_m),
            y_m=float(e.y_m),
            value=float(e.value),
            detail=e.detail,
        )

    def _markers(self, r: StepResult) -> MarkerArray:
        """``/viz/world``: stable ids per UAV, fire and lake, DELETE for what is gone (:mod:`.viz`)."""
        area = self.world.scenario.area
        wanted = viz.world_markers(
            r.vehicles,
            r.fires,
            self.world.scenario.lakes,
            draw_fires=not isinstance(self.world.fires, RasterFireModel),
            legend_xy_m=(area.x_min_m, area.y_max_m),
        )
        hdr = self._hdr(r.stamp_ns)
        kinds = {
            "arrow": Marker.ARROW,
            "cylinder": Marker.CYLINDER,
            "sphere": Marker.SPHERE,
            "text": Marker.TEXT_VIEW_FACING,
        }
        arr = MarkerArray()
        for spec in self._marker_book.frame(wanted):
            mk = Marker(header=hdr, ns=spec.ns, id=spec.id)
            if spec.action == "delete":
                mk.action = Marker.DELETE
                arr.markers.append(mk)
                continue
            mk.type, mk.action, mk.text = kinds[spec.kind], Marker.ADD, spec.text
            mk.pose.position = Point(x=spec.x_m, y=spec.y_m, z=spec.z_m)
            _, _, mk.pose.orientation.z, mk.pose.orientation.w = viz.yaw_quaternion(spec.yaw_rad)
            mk.scale.x, mk.scale.y, mk.scale.z = spec.scale_m
            mk.color.r, mk.color.g, mk.color.b, mk.color.a = spec.rgba
            arr.markers.append(mk)
        return arr

    def _tf_msg(self, r: StepResult) -> TFMessage:
        """``/tf``: ``map -> uav_<k>`` from the truth (the frame of vehicle k's sensor headers)."""
        msg = TFMessage()
        for v in r.vehicles:
            t = TransformStamped()
            t.header = self._hdr(r.stamp_ns)
            t.child_frame_id = f"uav_{v.uav_id}"
            t.transform.translation.x, t.transform.translation.y = float(v.x_m), float(v.y_m)
            t.transform.translation.z = float(v.z_m)
            _, _, t.transform.rotation.z, t.transform.rotation.w = viz.yaw_quaternion(float(v.yaw_rad))
            msg.transforms.append(t)
        return msg

    def _grid_msg(self, ns: int) -> OccupancyGrid:
        fm = self.world.fires
        assert isinstance(fm, RasterFireModel)
        g = OccupancyGrid(header=self._hdr(ns))
        g.info.map_load_time = stamp(ns)
        g.info.resolution = float(fm.cs)
        g.info.width, g.info.height = fm.nx, fm.ny
        g.info.origin.position.x = fm.spec.origin.x_m
        g.info.origin.position.y = fm.spec.origin.y_m
        g.info.origin.orientation.w = 1.0
        state = fm.state_grid()
        import numpy as np

        occ = np.zeros(state.shape, dtype=np.int8)  # unburned 0, wet 20, burnt 60, burning 100
        occ[fm.wet_grid()] = 20
        occ[state == CellState.BURNED] = 60
        occ[state == CellState.BURNING] = 100
        g.data = occ.ravel().tolist()
        return g


def _spin_until_done(node: WorldNode) -> None:
    """``rclpy.spin_until_future_complete(node, node.done)``, except that a message rclpy cannot
    convert to Python is dropped (counted as rejected "undecodable", warned) instead of ending
    the world. It fails inside rclpy's ``take_message``, before any callback of ours; the agents
    have the same guard (``agent_node._spin_through_bad_messages``, issue "hardening"). Seen
    without any fuzzing too: agents now and then drop one near a mission's end, and on
    2026-12-02 the world got one in the 1 s after "mission complete" of a 10-UAV run beside a CPU
    hog and exited 1 (cause not found)."""
    from fire_uav_common.ros_io import make_executor

    executor = make_executor()
    executor.add_node(node)
    try:
        while not node.done.done():
            try:
                executor.spin_until_future_complete(node.done)
            except RuntimeError as err:
                if "Unable to convert" not in str(err):
                    raise
                node.rejected["undecodable"] = node.rejected.get("undecodable", 0) + 1
                node.get_logger().warning(
                    f"dropped a message rclpy could not decode: {err} (rejections so far: {node.rejected})",
                    throttle_duration_sec=5.0,
                )
    finally:
        executor.remove_node(node)
        executor.shutdown()


def main(args: list[str] | None = None) -> int:
    rclpy.init(args=args)
    node = None
    code = 0
    try:
        node = WorldNode()
        _spin_until_done(node)
        code = int(node.done.result() or 0) if node.done.done() else 0
    except (ScenarioError, ConfigError) as e:
        rclpy.logging.get_logger("world").error(str(e))
        code = 2
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return code


if __name__ == "__main__":
    sys.exit(main())
