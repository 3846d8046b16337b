"""ROS 2 adapter of :class:`fire_world_sim.world.World`: the clock authority of the fleet.

Publishes ``/clock``, one ``SensorBundle`` per vehicle per control step, ``/world/truth``,
``/world/events``, ``/viz/world``, ``/viz/fire_grid`` and ``/tf`` (``map -> uav_<k>``, truth, at the
viz rate); subscribes ``/uav_<k>/cmd`` and
``/uav_<k>/payload`` (docs/protocol.md). The world itself runs on the steady wall clock;
lockstep waiting is a steady-clock timer reset at each step, never a sleep.

The node is the thin part: parameters come from one table into a frozen config
(:mod:`.world_config`), which answers a step waits for and which are taken is decided by the
pure :class:`~.step_answers.AnswerGate`, and the messages are built by :mod:`.ros_messages`.
"""

from __future__ import annotations

import os
import sys

import rclpy
from fire_uav_common import topics
from fire_uav_common.auth import Authenticator
from fire_uav_common.cdr import CdrError
from fire_uav_common.codecs.payload_request import WirePayloadRequest, read_payload_request
from fire_uav_common.codecs.sensor_bundle import write_sensor_bundle
from fire_uav_common.constants import EventType, PayloadAction, VehicleStatus
from fire_uav_common.final_acks import FINAL_ACK_CAP_WALL_S, FINAL_ACK_POLL_WALL_S, FinalAckWait
from fire_uav_common.lockstep import offline_uavs
from fire_uav_common.ros_io import unacked_topics
from fire_uav_common.scenario import ScenarioError, load_scenario
from fire_uav_common.stamps import NS_PER_S, stamp_to_ns
from fire_uav_msgs.msg import MissionEvent, PayloadRequest
from geometry_msgs.msg import TwistStamped
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.serialization import deserialize_message
from rclpy.task import Future
from rosgraph_msgs.msg import Clock as ClockMsg
from visualization_msgs.msg import MarkerArray

from . import ros_messages as msgs
from . import viz
from .errors import ConfigError
from .ros_messages import FRAME, stamp  # noqa: F401  (the SensorBundle writer's tests take them from here)
from .step_answers import AnswerGate
from .world import Command, SensorBundleRecord, StepResult, World
from .world_config import (
    PARAMETERS,
    ParameterSpec,
    WorldNodeConfig,
    authenticator_from,
    config_from_parameters,
)

#: the PayloadRequest actions there are (a set built once: the check runs per agent per step)
_ACTIONS = frozenset(int(a) for a in PayloadAction)

#: [s wall] lockstep: re-send a bundle to an agent whose answer is not in after this long
RESEND_AFTER_WALL_S = 5.0


def _descriptor(p: ParameterSpec) -> ParameterDescriptor:
    d = ParameterDescriptor(description=p.description, read_only=p.read_only)
    if p.int_range is not None:
        d.integer_range = [IntegerRange(from_value=p.int_range[0], to_value=p.int_range[1], step=1)]
    if p.float_range is not None:
        d.floating_point_range = [
            FloatingPointRange(from_value=p.float_range[0], to_value=p.float_range[1], step=0.0)
        ]
    return d


class WorldNode(Node):
    """World simulation node; see the package README for parameters and topics."""

    def __init__(self) -> None:
        super().__init__("world")
        self.cfg, self.auth = self._read_parameters()
        self.rejected: dict[str, int] = {}  # commands / payload requests rejected, per kind
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
        for note in scenario.notes:  # e.g. water bodies of a landscape too small to refill from
            self.get_logger().info(note)
        self.gate = AnswerGate(lockstep=self.cfg.mode == "lockstep")
        self.done = Future()
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self.pub_clock = topics.publisher(self, topics.CLOCK_SPEC)
        self.pub_truth = topics.publisher(self, topics.WORLD_TRUTH_SPEC)
        self.pub_events = topics.publisher(self, topics.WORLD_EVENTS_SPEC)
        self.pub_viz = topics.publisher(self, topics.VIZ_WORLD_SPEC)
        self.pub_grid = topics.publisher(self, topics.VIZ_FIRE_GRID_SPEC)
        # only a fire on a landscape has fire types: other worlds do not advertise the topic
        self.pub_fire_type = (
            topics.publisher(self, topics.WORLD_FIRE_TYPE_SPEC)
            if self.world.fires.fire_type_grid() is not None
            else None
        )
        self.pub_tf = topics.publisher(self, topics.TF_SPEC)
        self._marker_book = viz.MarkerBook()
        self.pub_sensors = {}
        for i in range(self.n):
            self.pub_sensors[i] = topics.publisher(self, topics.SENSORS_SPEC, uav_id=i)
            if self.auth is None:  # signed: the command comes from the PayloadRequest (_on_payload)
                topics.subscription(self, topics.CMD_SPEC, lambda m, i=i: self._on_cmd(i, m), uav_id=i)
            # raw: the tag is checked on the bytes as the agent sent them (auth.check_serialized)
            topics.subscription(
                self, topics.PAYLOAD_SPEC, lambda d, i=i: self._on_payload(i, d), uav_id=i, raw=True
            )
        self._ready: set[int] = set()
        topics.subscription(self, topics.FLEET_EVENTS_SPEC, self._on_fleet_event)
        self._told_crashed: set[int] = set()  # agents sent a bundle saying their vehicle crashed
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
    def _read_parameters(self) -> tuple[WorldNodeConfig, Authenticator | None]:
        """Every parameter of :data:`~.world_config.PARAMETERS`, declared and read once; the key
        is undeclared once read, never logged (docs/security.md)."""
        for p in PARAMETERS:
            self.declare_parameter(p.name, p.default, _descriptor(p))
        values = {p.name: self.get_parameter(p.name).value for p in PARAMETERS}
        self.undeclare_parameter("fleet_key")
        cfg = config_from_parameters(values)
        if not bool(values["auth"]):
            self.get_logger().warning("authentication off: commands are taken from /uav_<k>/cmd unverified")
        return cfg, authenticator_from(bool(values["auth"]), str(values["fleet_key"]))

    def _reject(self, uid: int, topic: str, reason: str) -> None:
        """Count a rejected command / payload request of kind ``reason`` (throttled warning)."""
        self.rejected[reason] = self.rejected.get(reason, 0) + 1
        self.get_logger().warning(
            f"rejected a message on {topic} for uav {uid}: {reason} (rejections so far: {self.rejected})",
            throttle_duration_sec=2.0,
        )

    def _crashed(self, uid: int) -> bool:
        return self.world.vehicles[uid].status == VehicleStatus.CRASHED

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
        self.gate.started = True
        self._advance()

    def _advance(self) -> None:
        """Run one world step with what was received, publish, and wait for the answers."""
        if self.done.done():
            return
        commands, payload = self.gate.take_inputs()
        result = self.world.step(commands, payload)
        self._publish(result)
        if result.complete:
            self._finish(result)
            return
        self.gate.awaited_ns = result.stamp_ns
        if self.cfg.mode == "lockstep":
            awaited = set(self.world.awaited_uavs()) - self._offline(result.step)
            self.gate.await_answers(result.stamp_ns, awaited, self._steady.now().nanoseconds)
            if self.gate.complete:
                self._advance_soon()
                return
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
        gone = sorted(i for i in self.gate.waiting if self.count_publishers(topics.CMD_SPEC.for_uav(i)) == 0)
        if not gone:
            return
        for i in gone:
            self.gate.mark_lost(i)
            self.get_logger().error(
                f"step {self.world.step_index}: agent {i}'s process is gone (not in the fault schedule); "
                "no longer waiting for it, so this run is not reproducible"
            )
            self.pub_events.publish(msgs.agent_lost_msg(i, self.gate.awaited_ns))
        self._maybe_advance()

    def _resend_if_stuck(self, after_wall_s: float = RESEND_AFTER_WALL_S) -> None:
        """Re-send this step's bundle to every live agent whose answer is not in after ``after_wall_s``.

        A reliable DDS writer should never need this, yet a lockstep wait was seen to hang for
        good in test runs on a loaded machine (cause not found; it did not repeat on an idle one),
        as if a bundle or an answer was lost between matched endpoints. The copy is harmless: an
        agent that has not run the step yet ignores it (it answers only a newer bundle), and one
        that has answered already sends its answer again; the world takes one answer per step
        (:meth:`~.step_answers.AnswerGate.second_answer`). It changes no step's inputs, so a
        lockstep run stays reproducible; the warning names who was waited for.
        """
        now = self._steady.now().nanoseconds
        late = self.gate.resend_due(now, after_wall_s)
        if late is None:
            return
        g = self.gate
        waited_s = (now - g.wait_since_ns) / NS_PER_S
        self.get_logger().warning(
            f"step {g.sent_step}: waiting {waited_s:.0f} s for the answers of agents {late} "
            f"(command: {sorted(g.waiting)}, payload request: {sorted(g.waiting_payload)}); "
            "re-sending their bundles"
        )
        for uid in late:
            self.pub_sensors[uid].publish(g.sent[uid])

    def _maybe_advance(self) -> None:
        """Step once every awaited agent's command and payload request of this step are in."""
        if self.gate.complete and not self.done.done():
            self._liveness_timer.cancel()
            self._advance()

    def _on_cmd(self, uid: int, msg: TwistStamped) -> None:
        # only subscribed unsigned: TwistStamped has no tag, so signed the command comes from the
        # PayloadRequest (_on_payload) and /uav_k/cmd is not subscribed at all
        topic = topics.CMD_SPEC.for_uav(uid)
        verdict = self.gate.admit_command(
            uid, stamp_to_ns(msg.header.stamp), self._crashed(uid), self.world.t_ns
        )
        if not verdict.take:
            if verdict.rejection is not None:
                self._reject(uid, topic, verdict.rejection)
            return
        t = msg.twist
        cmd = Command(float(t.linear.x), float(t.linear.z), float(t.angular.z))
        if not cmd.is_finite():
            self._reject(uid, topic, "nan/inf")
        self.gate.record_command(uid, cmd if cmd.is_finite() else None)
        if self.cfg.mode == "lockstep":
            self._maybe_advance()

    def _on_payload(self, uid: int, data: bytes) -> None:
        if self.gate.finished:
            return  # an answer to the last bundle (see AnswerGate.admit_command)
        topic = topics.PAYLOAD_SPEC.for_uav(uid)
        msg = _read_payload(data)
        if msg is None:
            return self._reject(uid, topic, "undecodable")
        ns = msg.stamp_ns
        if msg.uav_id != uid:
            return self._reject(uid, topic, "wrong id")
        if self.auth is not None and not self.auth.check_serialized(data, topic, uid, ns):
            return self._reject(uid, topic, "bad auth")
        if msg.action not in _ACTIONS:
            return self._reject(uid, topic, "unknown action")
        tag = msg.auth if self.auth is not None else None
        verdict = self.gate.admit_payload(uid, ns, self._crashed(uid), self.world.t_ns, tag)
        if not verdict.take:
            if verdict.rejection is not None:
                self._reject(uid, topic, verdict.rejection)
            return
        if self.auth is not None and not self.gate.has_command(uid):  # the signed command (docs/security.md)
            cmd = Command(
                float(msg.cmd_linear_x_mps), float(msg.cmd_linear_z_mps), float(msg.cmd_angular_z_radps)
            )
            if not cmd.is_finite():
                self._reject(uid, topic, "nan/inf")
            self.gate.record_command(uid, cmd if cmd.is_finite() else None)
        self.gate.record_payload(uid, int(msg.action))
        if self.cfg.mode == "lockstep":
            self._maybe_advance()

    def _on_realtime_tick(self) -> None:
        if not self.gate.started:
            self.gate.started = True
        self._advance()

    # --- finishing ---------------------------------------------------------------------------
    def _finish(self, result: StepResult) -> None:
        self.gate.finished = True
        self.get_logger().info(
            f"mission complete at t = {result.stamp_ns / NS_PER_S:.1f} s: {result.complete_reason}; "
            f"rejected commands / payload requests: {self.rejected or 'none'}"
        )
        for timer in (getattr(self, "_liveness_timer", None), getattr(self, "_rt_timer", None)):
            if timer is not None:
                timer.cancel()
        # exit once every matched reader has acknowledged every message (in its reader history): a
        # reliable writer repairs a lost sample only while it lives, and the last one's loss is
        # seen only at its next heartbeat (Fast DDS: 3 s), so a world that exits on a timer can
        # take its final /world/truth with it (docs/recording.md, "Stopping")
        self._final_acks = FinalAckWait(self._steady.now().nanoseconds / NS_PER_S, FINAL_ACK_CAP_WALL_S)
        self._exit_timer = self.create_timer(FINAL_ACK_POLL_WALL_S, self._exit_when_acked, clock=self._steady)

    def _exit_when_acked(self) -> None:
        """End the spin once every publisher's messages are acknowledged by all its matched readers,
        or after ``FINAL_ACK_CAP_WALL_S`` with a warning naming the topics still waited for
        (``fire_uav_common.final_acks``: the agents wait by the same rule when signalled)."""
        done = self._final_acks.check(
            unacked_topics(self.publishers), self._steady.now().nanoseconds / NS_PER_S
        )
        if done is None:
            return
        (self.get_logger().info if done.acked else self.get_logger().warning)(done.line())
        self._exit_timer.cancel()
        if not self.done.done():
            self.done.set_result(0)

    # --- publishing --------------------------------------------------------------------------
    def _publish(self, r: StepResult) -> None:
        self.pub_clock.publish(ClockMsg(clock=stamp(r.stamp_ns)))
        offline = self._offline(r.step) if self.cfg.mode == "lockstep" else frozenset()
        self.gate.start_sending(r.step)
        for uid, b in sorted(r.bundles.items()):
            if uid not in offline:  # an offline agent's computer reads no sensors
                data = self._bundle_bytes(b)
                self.gate.record_sent(uid, data)
                self.pub_sensors[uid].publish(data)
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
                last = SensorBundleRecord(v.uav_id, r.step, r.stamp_ns, self.world.control_period_s)
                last.water_kg, last.vehicle_status = v.water_kg, int(VehicleStatus.CRASHED)
                data = self._bundle_bytes(last)
                self.gate.record_sent(v.uav_id, data)
                self.pub_sensors[v.uav_id].publish(data)
                self._told_crashed.add(v.uav_id)
        self.pub_truth.publish(msgs.truth_bytes(r))  # CDR bytes, published raw
        for e in r.events:
            self.pub_events.publish(msgs.event_msg(e))
            if e.type == EventType.CRASH:
                self.get_logger().warn(f"uav {e.uav_id} crashed: {e.detail}")
        if r.stamp_ns - self._last_viz_ns >= self._viz_period_ns or r.complete:
            self._last_viz_ns = r.stamp_ns
            self.pub_viz.publish(self._markers(r))
            self.pub_tf.publish(msgs.tf_msg(r))
            grid = self.world.fires.cell_grid()
            if grid is not None:
                self.pub_grid.publish(msgs.grid_msg(grid, r.stamp_ns))
                fire_type = self.world.fires.fire_type_grid()
                if fire_type is not None and self.pub_fire_type is not None:
                    self.pub_fire_type.publish(msgs.fire_type_msg(grid, fire_type, r.stamp_ns))

    def _bundle_bytes(self, b: SensorBundleRecord) -> bytes:
        """``b`` as a serialised SensorBundle (``fire_uav_common.codecs.sensor_bundle``), published as it is."""
        return write_sensor_bundle(b, self.world.scenario.sensors.gyro.sigma_radps)

    # the header the SensorBundle writer's tests build their reference message with
    _hdr = staticmethod(msgs.header)

    def _markers(self, r: StepResult) -> MarkerArray:
        """``/viz/world``: stable ids per UAV, fire and lake, DELETE for what is gone (:mod:`.viz`)."""
        area, terrain = self.world.scenario.area, self.world.scenario.terrain
        wanted = viz.world_markers(
            r.vehicles,
            r.fires,
            self.world.scenario.lakes,
            draw_fires=not self.world.fires.has_cells,  # fires with cells are shown by their grid
            legend_xy_m=(area.x_min_m, area.y_max_m),
            ground=lambda x, y: float(terrain.elevation(x, y)),
        )
        return msgs.marker_array(self._marker_book.frame(wanted), r.stamp_ns)


def _read_payload(data: bytes) -> WirePayloadRequest | None:
    """A PayloadRequest's bytes as received raw, or None if they are no PayloadRequest.

    Read by the codec, which skips rclpy's message objects (at 20 UAVs they cost the world as much
    per step as its physics); bytes the codec does not read (another encapsulation, trailing bytes)
    go to rclpy, so the world takes exactly the requests it took before."""
    try:
        return read_payload_request(data)
    except CdrError:
        pass
    try:
        m = deserialize_message(data, PayloadRequest)
    except RuntimeError:  # rclpy's RMWError: bytes that are no CDR of a PayloadRequest
        return None
    return WirePayloadRequest(
        stamp_to_ns(m.header.stamp),
        int(m.uav_id),
        int(m.action),
        int(m.target_fire_id),
        float(m.cmd_linear_x_mps),
        float(m.cmd_linear_z_mps),
        float(m.cmd_angular_z_radps),
        bytes(bytearray(m.auth)),
    )


def _spin_until_done(node: WorldNode) -> None:
    """``rclpy.spin_until_future_complete(node, node.done)``, except that a message rclpy cannot
    convert to Python is dropped (counted as rejected "undecodable", warned) instead of ending
    the world. It fails inside rclpy's ``take_message``, before any callback of ours, so no
    callback can guard against it; the agents have the same guard. A rogue participant can send
    such bytes, and it was seen without one too (cause not found): agents now and then drop one
    near a mission's end, and the world once got one just after "mission complete" of a 10-UAV
    run on a loaded machine, which ended the world with exit code 1 before this guard."""
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


def _profiled(fn, path: str) -> None:
    """Run ``fn()`` under cProfile over the main thread's CPU time and write the statistics to
    ``path``: on a shared machine wall time would charge a call for every wait for a core."""
    import cProfile
    import time

    prof = cProfile.Profile(time.thread_time)
    try:
        prof.runcall(fn)
    finally:
        prof.dump_stats(path)


def main(args: list[str] | None = None) -> int:
    rclpy.init(args=args)
    node = None
    code = 0
    try:
        node = WorldNode()
        prof_dir = os.environ.get("FIRE_WORLD_PROFILE_DIR")
        if prof_dir:  # profile the whole spin: executor + step + messaging (docs/profile.md)
            _profiled(lambda: _spin_until_done(node), os.path.join(prof_dir, "world.prof"))
        else:
            _spin_until_done(node)
        code = int(node.done.result() or 0) if node.done.done() else 0
    except (ScenarioError, ConfigError, InvalidParameterTypeException, InvalidParameterValueException) as e:
        # a value rclpy refuses against the declared type or range (seed:=abc) is a bad parameter
        # too: one line, not a traceback
        rclpy.logging.get_logger("world").error(" ".join(str(e).split()))
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
