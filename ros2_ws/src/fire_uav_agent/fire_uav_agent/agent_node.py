"""ROS 2 node ``uav_agent``: a thin adapter around :class:`fire_uav_agent.agent_core.Agent`.

One process per UAV in namespace ``/uav_<id>`` (docs/protocol.md "Agent, on SensorBundle k").
This module owns the endpoints, the timers and the publishing; it hands every bundle and peer
message to the :class:`~fire_uav_agent.peer_gate.PeerGate` and carries out its decisions. The
parameters are listed in ``agent_params`` (declared by ``agent_io.read_node_config``), the sensor
bundle, the peer state, the perimeter map and the front picture are read and written by the codecs
(``fire_uav_common.codecs``, through ``incoming`` / ``outgoing``), the other messages built in
``agent_io``; all decisions are in the pure modules.
"""

from __future__ import annotations

import functools
import math

import rclpy
from builtin_interfaces.msg import Time as TimeMsg
from fire_uav_common import topics
from fire_uav_common.cdr import CdrError
from fire_uav_common.codecs.agent_pose import write_twist_stamped
from fire_uav_common.codecs.fire_front import read_fire_front
from fire_uav_common.codecs.payload_request import write_payload_request
from fire_uav_common.codecs.perimeter_map import read_perimeter_map
from fire_uav_common.codecs.sensor_bundle import WireBundle, read_sensor_bundle
from fire_uav_common.codecs.uav_state import read_uav_state
from fire_uav_common.constants import EventType, PayloadAction, VehicleStatus
from fire_uav_common.ros_io import PublishCounts
from fire_uav_common.stamps import stamp_to_ns
from fire_uav_msgs.msg import (
    FireFront,
    MissionEvent,
    PerimeterMap,
    SensorBundle,
    UavState,
)
from rclpy.clock import Clock, ClockType
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.serialization import deserialize_message, serialize_message

from .agent_core import Agent
from .agent_io import (
    event_msg,
    log_event,
    make_executor,
    markers_msg,
    profiled,
    read_node_config,
    spin_through_bad_messages,
    tf_estimate_bytes,
)
from .agent_types import StepOutput
from .errors import ConfigError
from .incoming import message_step, peer_front, peer_perimeter
from .outgoing import front_bytes, perimeter_bytes, sent_per_topic, state_bytes
from .peer_gate import (
    AskResend,
    PeerGate,
    PeerGone,
    Rejected,
    RepeatAnswer,
    RunStep,
    StartWaiting,
    StillWaiting,
)
from .search_io import attach_search


# --- conversions (the only place messages meet arrays) -----------------------------------------
# --- the node ------------------------------------------------------------------------------------
class UavAgentNode(Node):
    """``uav_agent``: see the package README for topics and parameters."""

    published: PublishCounts  # per topic, what this node's publishers published (create_publisher)

    def __init__(self, **kwargs) -> None:
        # every name given is declared first, so that read_node_config can refuse the unknown ones
        kwargs.setdefault("automatically_declare_parameters_from_overrides", True)
        super().__init__("uav_agent", **kwargs)
        self.config = read_node_config(self)
        self.cfg, self.mode = self.config.agent, self.config.mode
        self.liveness_s, self.marker_every = self.config.liveness_check_wall_s, self.config.marker_every_steps
        schedule = self.config.offline_schedule
        self.auth = self.config.authenticator
        self.agent = Agent(self.cfg)
        # CP coverage search over /fleet/coverage/* (None when search_mode resolves to off)
        self.search_link = attach_search(self, self.agent, self.config.search)
        uid = self.cfg.uav_id
        self.get_logger().info(
            f"uav {uid}/{self.cfg.uav_count} mode={self.mode} loss={self.cfg.loss_probability} "
            f"outages={len(self.cfg.outages)} crash_threshold={self.cfg.crash_threshold_steps}"
        )
        for line in self.agent.lakes_refused:
            self.get_logger().warning(line)
        # per-vehicle topics: relative names under the /uav_<id> namespace, absolute if launched without it
        own = None if self.get_namespace().rstrip("/") == topics.uav_namespace(uid) else uid
        self.pub_cmd = topics.publisher(self, topics.CMD_SPEC, own)
        self.pub_payload = topics.publisher(self, topics.PAYLOAD_SPEC, own)
        self.pub_viz = topics.publisher(self, topics.VIZ_AGENT_SPEC, own)
        self.pub_state = topics.publisher(self, topics.FLEET_STATE_SPEC)
        self.pub_events = topics.publisher(self, topics.FLEET_EVENTS_SPEC)
        self.pub_perimeter = topics.publisher(self, topics.FLEET_PERIMETER_SPEC)
        self._perimeter_seq = 0
        # signed topics arrive raw: the tag is checked on the bytes as sent (auth.check_serialized)
        self.sub_perimeter = topics.subscription(
            self, topics.FLEET_PERIMETER_SPEC, self._on_perimeter, drain=True, raw=True
        )
        self.pub_front = topics.publisher(self, topics.FLEET_FRONT_SPEC)
        self._front_seq = 0
        self.sub_front = topics.subscription(
            self, topics.FLEET_FRONT_SPEC, self._on_front, drain=True, raw=True
        )
        self.sub_sensors = topics.subscription(self, topics.SENSORS_SPEC, self._on_bundle, own, raw=True)
        self.sub_state = topics.subscription(
            self, topics.FLEET_STATE_SPEC, self._on_state, drain=True, raw=True
        )
        if self.search_link is not None:
            self.search_link.on_arrival = self._on_coverage_arrival
        self._answer: tuple[int, list] | None = None  # (step, [(publisher, msg)]) last sent to the world
        # admission, duplicates, resend, the pending bundle and the lockstep wait (kept per step for
        # a resend: the (publisher, message) pairs published)
        self.gate: PeerGate[WireBundle, tuple] = PeerGate(
            uid, self.cfg.uav_count, self.cfg.control_period_s, lockstep=self.mode == "lockstep",
            schedule=schedule, crash_threshold_steps=self.cfg.crash_threshold_steps,
            check_tag=None if self.auth is None else self.auth.check_serialized,
        )  # fmt: skip
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        # not a timeout: while waiting, notice a peer whose process is gone (its publishers left the graph)
        self._liveness_timer = self.create_timer(self.liveness_s, self._check_liveness, clock=self._steady)
        self._liveness_timer.cancel()
        topics.subscription(self, topics.FLEET_EVENTS_SPEC, self._on_fleet_event)
        # the start-up handshake: AGENT_READY once every fleet topic is matched with every peer
        self._ready_timer = self.create_timer(0.05, self._check_ready, clock=self._steady)

    def create_publisher(self, *args, **kwargs):
        """rclpy's, each publisher counted (``published``: the exit line of :func:`main`)."""
        counts = self.__dict__.setdefault("published", PublishCounts())  # before Node.__init__ ends, too
        return counts.wrap(super().create_publisher(*args, **kwargs))

    def _decode(self, data: bytes, msg_type: type, spec: topics.TopicSpec):
        """A raw peer message as ``msg_type``; None (counted as a rejection) if it is not one."""
        try:
            return deserialize_message(data, msg_type)
        except RuntimeError as err:  # rclpy's RMWError: bytes that are no CDR of this type
            self.agent.link.count_rejection("undecodable")
            self.get_logger().warning(
                f"rejected {len(data)} bytes on {spec.name} that are no {msg_type.__name__}: {err}",
                throttle_duration_sec=2.0,
            )
            return None

    def _act(self, decisions: list) -> None:
        """Carry out the gate's decisions, in order."""
        log = self.get_logger()
        for d in decisions:
            if isinstance(d, RunStep):
                self._run(d)
            elif isinstance(d, Rejected):
                self.agent.link.count_rejection(d.reason)
                log.warning(
                    f"rejected a message on {d.topic} claiming uav {d.sender} step {d.step}: {d.reason} "
                    f"(rejections so far: {self.agent.link.reject_reasons})",
                    throttle_duration_sec=2.0,
                )
            elif isinstance(d, RepeatAnswer) and self._answer is not None:
                log.warning(f"step {d.step}: bundle received again; re-sending this step's answer")
                for pub, m in self._answer[1]:
                    pub.publish(m)
            elif isinstance(d, StartWaiting):
                self._liveness_timer.reset()
            elif isinstance(d, StillWaiting):  # a long wait is worth a line: it names what is missing
                log.warning(
                    f"step {d.step}: waiting {d.waited_s:.0f} s for peers' step-{d.step - 1} messages: {d.missing}",
                    throttle_duration_sec=10.0,
                )
            elif isinstance(d, AskResend):
                self._ask_resend(d)
            elif isinstance(d, PeerGone):
                log.error(
                    f"step {d.step}: peer {d.peer}'s process is gone (not in the fault schedule); no longer "
                    "waiting for it, so this run is not reproducible"
                )

    # --- peer traffic ---------------------------------------------------------------------------------
    def _read(self, data: bytes, read, msg_type: type, spec: topics.TopicSpec):
        """Raw peer bytes through their codec's ``read``; an encoding the codec does not take (not
        XCDR1 little-endian) is read by ``deserialize_message`` and re-serialised for the codec;
        None (counted as ``undecodable``) if neither reads it."""
        try:
            return read(data)
        except CdrError:
            pass
        msg = self._decode(data, msg_type, spec)
        return None if msg is None else read(serialize_message(msg))

    def _on_state(self, data: bytes) -> None:
        w = self._read(data, read_uav_state, UavState, topics.FLEET_STATE_SPEC)
        if w is None or w.uav_id == self.cfg.uav_id:
            return  # undecodable, or our own broadcast
        self._act(self.gate.on_state(data, w.state, w.fires, w.sent_per_topic, w.final))

    def _on_perimeter(self, data: bytes) -> None:
        w = self._read(data, read_perimeter_map, PerimeterMap, topics.FLEET_PERIMETER_SPEC)
        if w is None or w.uav_id == self.cfg.uav_id:
            return
        self._act(self.gate.on_perimeter(data, peer_perimeter(w, self.cfg.control_period_s)))

    def _on_front(self, data: bytes) -> None:
        w = self._read(data, read_fire_front, FireFront, topics.FLEET_FRONT_SPEC)
        if w is None or w.uav_id == self.cfg.uav_id:
            return
        front = None
        try:
            front = peer_front(w, self.cfg.control_period_s)
        except ValueError as err:  # malformed: arrived for the lockstep, its content dropped and counted
            self.agent.link.count_rejection("malformed front")
            self.get_logger().warning(
                f"FireFront from uav {w.uav_id} dropped: {err}", throttle_duration_sec=5.0
            )
        self._act(self.gate.on_front(w.uav_id, message_step(w.stamp_ns, self.cfg.control_period_s), front))

    # --- resend: recovery from a message the transport lost (docs/protocol.md "Resend") ----------
    def _ask_resend(self, d: AskResend) -> None:
        """Ask peer ``d.peer`` to send its step-``d.step`` messages again.

        The lockstep wait has no timeout (determinism), so a message the transport lost (a reader
        history overrun by a flood on the topic) would block the fleet for good. Wall time decides
        only *when* a copy is asked for, never *what* the agent then decides.
        """
        j = d.peer
        detail = f"waited {d.waited_s:.0f} s for uav {j}'s step-{d.step} messages"
        self.pub_events.publish(
            event_msg(EventType.RESEND_REQUEST, self.cfg.uav_id, j, value=d.step, detail=detail)
        )
        self.get_logger().warning(f"step {d.step + 1}: asked uav {j} to resend its step-{d.step} messages")

    def _on_fleet_event(self, msg: MissionEvent) -> None:
        if msg.type != EventType.RESEND_REQUEST or msg.peer_id != self.cfg.uav_id:
            return
        if not math.isfinite(msg.value):
            return
        step = int(msg.value)
        sent = self.gate.to_resend(step, self._steady.now().nanoseconds)
        if sent is None:
            return  # not kept (too old or never sent), or resent just now
        for pub, m in sent:
            pub.publish(m)
        self.get_logger().warning(
            f"resent step {step}'s {len(sent)} messages at uav {msg.uav_id}'s request "
            f"({self.gate.resend.resends_served} so far)"
        )

    def _on_coverage_arrival(self, sender: int, step: int, loss_index: int) -> None:
        self._act(self.gate.on_arrival(sender, step, loss_index))

    # --- lockstep -------------------------------------------------------------------------------------
    def _check_ready(self) -> None:
        """Say AGENT_READY (once) when the world's topics and every peer's fleet topics are matched.

        A message published before its reader is matched is dropped by DDS, so step 0 may start
        only when every writer has matched every peer reader; each agent checks its own writers
        and readers against the DDS graph, and the world starts when all have said ready.
        """
        if self.pub_payload.get_subscription_count() == 0:
            return
        if self.auth is None and self.pub_cmd.get_subscription_count() == 0:
            return  # unsigned, the world takes the command from /uav_k/cmd (signed: from the payload)
        if self.sub_sensors.get_publisher_count() == 0:
            return
        peers = {topics.uav_namespace(j) for j in range(self.cfg.uav_count) if j != self.cfg.uav_id}
        me = (self.get_name(), self.get_namespace())
        endpoints = [(self.pub_state, True), (self.pub_perimeter, True)]
        endpoints += [(self.sub_state, False), (self.sub_perimeter, False)]
        if self.search_link is not None:
            endpoints += self.search_link.endpoints()
        for ep, is_pub in endpoints:
            infos = (self.get_subscriptions_info_by_topic if is_pub else self.get_publishers_info_by_topic)(
                ep.topic_name
            )
            others = [i for i in infos if (i.node_name, i.node_namespace) != me]
            if not peers <= {i.node_namespace for i in others}:
                return  # a peer is not discovered yet
            matched = ep.get_subscription_count() if is_pub else ep.get_publisher_count()
            if matched < len(others):
                return  # discovered but not matched yet
        self._ready_timer.cancel()
        ready = event_msg(EventType.AGENT_READY, self.cfg.uav_id, detail="ready: world and peers matched")
        self.pub_events.publish(ready)
        self.get_logger().info(f"ready for step 0 (world and {len(peers)} peers matched)")

    def _read_bundle(self, data: bytes) -> WireBundle | None:
        """A raw SensorBundle -> :class:`WireBundle` (the ``sensor_bundle`` codec); another encoding
        is read by ``deserialize_message`` and re-serialised for the codec; None (logged) if
        neither reads it."""
        try:
            return read_sensor_bundle(data)
        except CdrError as fast_err:
            try:
                msg = deserialize_message(data, SensorBundle)
            except RuntimeError as err:  # rclpy's RMWError: bytes that are no CDR of this type
                self.get_logger().error(
                    f"dropped {len(data)} bytes on {topics.SENSORS_SPEC.for_uav(self.cfg.uav_id)} that are "
                    f"no SensorBundle: {fast_err}; {err}",
                    throttle_duration_sec=2.0,
                )
                return None
        return read_sensor_bundle(serialize_message(msg))

    def _on_bundle(self, data: bytes) -> None:
        wb = self._read_bundle(data)
        if wb is None:
            return
        self._act(self.gate.on_bundle(wb.bundle.step, wb, self._steady.now().nanoseconds))

    def _check_liveness(self) -> None:
        """Stop waiting for a peer whose process is gone (unscheduled death; not reproducible)."""
        if self.gate.pending_step is None:
            self._liveness_timer.cancel()
            return

        def alive() -> set[int]:
            graph = {
                i.node_namespace for i in self.get_publishers_info_by_topic(topics.FLEET_STATE_SPEC.name)
            }
            return {j for j in range(self.cfg.uav_count) if topics.uav_namespace(j) in graph}

        self._act(self.gate.on_liveness(self._steady.now().nanoseconds, alive))

    def _run(self, d: RunStep[WireBundle, tuple]) -> None:
        self._liveness_timer.cancel()
        wb, k = d.bundle, d.step
        out = self.agent.step(wb.bundle, d.inbox, want_markers=self._want_markers(k))
        if out is None:
            return
        for j, cell_m in self.agent.raster.cell_size_refused:  # this step's, counted in the link
            picture = self.agent.front
            self.get_logger().warning(
                f"step {k}: rejected a FireFront from uav {j}: cell size {cell_m:g} m, this UAV's "
                f"picture has {picture.cfg.cell_size_m if picture else float('nan'):g} m "
                f"(rejections so far: {self.agent.link.reject_reasons})",
                throttle_duration_sec=5.0,
            )
        if self.agent.guide.skip_note is not None:  # why its drop runs are not flown: once per agent
            self.get_logger().info(self.agent.guide.skip_note, once=True)
        coverage = []
        if self.search_link is not None:
            coverage = self.search_link.step(out.stamp_s, out.step, out.state.alive_peers)
        final = wb.bundle.vehicle == VehicleStatus.CRASHED
        self._publish(out, TimeMsg(sec=wb.stamp_sec, nanosec=wb.stamp_nanosec), coverage, final)

    def _want_markers(self, k: int) -> bool:
        """Markers at step ``k``: every ``marker_every_steps`` steps, while a reader of ``viz`` is
        matched. The topic is best effort and volatile, so markers published with no reader reach
        no one; building them costs ~1 ms (the cell's border, a ``MarkerArray`` of ~100 points and
        its conversion), ~0.2 ms per step at every fifth step, and the agent decides nothing by them."""
        return (
            self.marker_every > 0 and k % self.marker_every == 0 and self.pub_viz.get_subscription_count() > 0
        )

    # --- output ---------------------------------------------------------------------------------------
    def _publish(self, out: StepOutput, stamp: TimeMsg, coverage: list, final: bool) -> None:
        """Publish step ``out.step``: the state first (it tells peers what else to wait for)."""
        uid = self.cfg.uav_id
        stamp_ns = stamp_to_ns(stamp)
        self._perimeter_seq += out.perimeter is not None
        pm = perimeter_bytes(out, stamp_ns, self._perimeter_seq)
        fm = None
        if self.agent.front is not None:
            self._front_seq += out.front is not None
            fm = front_bytes(out, stamp_ns, self._front_seq, self.agent.front.cfg.cell_size_m)
        counts = None if self.search_link is None else self.search_link.counts(coverage)
        sent = sent_per_topic(pm is not None, fm is not None, counts)
        state = state_bytes(out, stamp_ns, sent, final)
        if self.auth is not None:  # signed: the bytes that go out (auth.sign_serialized), kept as sent
            state = self.auth.sign_serialized(state, topics.FLEET_STATE_SPEC.name, uid, out.step)
            if pm is not None:
                pm_step = message_step(stamp_ns, self.cfg.control_period_s)
                pm = self.auth.sign_serialized(pm, topics.FLEET_PERIMETER_SPEC.name, uid, pm_step)
        self.pub_state.publish(state)
        log = [(self.pub_state, state)]
        answer = []  # what the world waits for: kept to answer a re-sent bundle (_on_bundle)
        v_lin, v_z, omega_z = (float(v) for v in out.command)
        # exactly one request per step (ACTION_NONE if nothing): the lockstep world waits for it
        for action, fire_id in out.payload_requests or [(PayloadAction.NONE, -1)]:
            # written as CDR bytes (codecs.payload_request: what serialize_message gives), published
            # raw; the command rides along: TwistStamped has no room for a tag (docs/security.md)
            req = write_payload_request(
                stamp.sec, stamp.nanosec, uid, int(action), int(fire_id), v_lin, v_z, omega_z
            )
            if self.auth is not None:
                req = self.auth.sign_serialized(req, topics.PAYLOAD_SPEC.for_uav(uid), uid, stamp_ns)
            self.pub_payload.publish(req)
            answer.append((self.pub_payload, req))
            what = PayloadAction(action).name
            if action == PayloadAction.DROP:
                self.get_logger().info(f"step {out.step}: {what} on fire {fire_id}")
            else:
                self.get_logger().debug(f"step {out.step}: {what}", throttle_duration_sec=2.0)
        if pm is not None:
            self.pub_perimeter.publish(pm)
            log.append((self.pub_perimeter, pm))
        if fm is not None:
            self.pub_front.publish(fm)
            log.append((self.pub_front, fm))
        self.gate.keep(out.step, log)
        if self.search_link is not None:
            self.search_link.publish(coverage)
            plan = self.search_link.plan_marker(stamp)
            if plan is not None:
                self.pub_viz.publish(plan)
        # CDR bytes published raw (codecs.agent_pose): a TwistStamped to every reader
        cmd = write_twist_stamped(stamp.sec, stamp.nanosec, f"uav_{uid}", v_lin, v_z, omega_z)
        self.pub_cmd.publish(cmd)
        answer.append((self.pub_cmd, cmd))
        self._answer = (out.step, answer)
        if out.markers is not None:
            self.pub_viz.publish(markers_msg(out, stamp, f"uav_{uid}"))
        if getattr(self, "_pub_tf", None) is None:
            self._pub_tf = topics.publisher(self, topics.TF_SPEC)
        self._pub_tf.publish(tf_estimate_bytes(out, stamp, uid))
        for ev in out.events:
            self.pub_events.publish(
                event_msg(ev.type, uid, ev.peer_id, ev.fire_id, ev.x_m, ev.y_m, ev.value, ev.detail, stamp)
            )
            log_event(self.get_logger(), out.step, ev)


def main(args: list[str] | None = None) -> int:
    """Spin one agent; 2 (and one error line naming the parameter or scenario field) on a bad
    configuration, 0 otherwise.

    SIGINT/SIGTERM end the spin but leave the context alive (``ros_io.StopSignals``): the agent
    then exits once every matched reader has acknowledged every message it published, at most
    ``final_acks.FINAL_ACK_CAP_WALL_S``, or at a second signal (a warning names the topics still
    waited for), and logs how many messages it published per topic. rclpy's own handlers would
    shut the context down at the signal, and the agent would exit with its last messages perhaps
    still on their way to a reader held up (the recorder on a busy machine): a reliable writer
    repairs a loss only while it lives (docs/recording.md, "Stopping")."""
    import os

    from fire_uav_common.final_acks import published_line, wait_for_final_acks
    from fire_uav_common.ros_io import StopSignals, unacked_topics
    from fire_uav_common.scenario import ScenarioError
    from rclpy.exceptions import InvalidParameterTypeException, InvalidParameterValueException
    from rclpy.signals import SignalHandlerOptions

    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    stop = StopSignals()
    node = None
    executor = None
    code = 0
    try:
        executor = make_executor()
        stop.install(executor)
        node = UavAgentNode()
        executor.add_node(node)
        prof_dir = os.environ.get("FIRE_UAV_PROFILE_DIR")
        spin = functools.partial(spin_through_bad_messages, executor, node, lambda: stop.count > 0)
        if prof_dir:  # profile the whole spin: executor + callbacks (docs/profile.md)
            profiled(spin, os.path.join(prof_dir, f"agent_{node.cfg.uav_id}.prof"))
        else:
            spin()
    except (ConfigError, ScenarioError, InvalidParameterTypeException, InvalidParameterValueException) as e:
        # a value rclpy refuses against the declared type or range (uav_id:=abc) is a bad
        # parameter too: one line, not a traceback
        rclpy.logging.get_logger("uav_agent").error(" ".join(str(e).split()))
        code = 2
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        stop.detach()
        if node is not None and rclpy.ok():
            log = node.get_logger()
            try:
                done = wait_for_final_acks(
                    lambda: unacked_topics(node.publishers), cancelled=lambda: stop.count > 1
                )
                (log.info if done.acked else log.warning)(done.line())
            except Exception as err:  # the context went away meanwhile: nothing left to wait on
                log.warning(f"exiting without waiting for acknowledgements: {err}")
            log.info(published_line(node.published.by_topic))
        if executor is not None:
            executor.shutdown()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
        stop.uninstall()
    return code


if __name__ == "__main__":
    import sys

    sys.exit(main())
