"""Messaging-only skeleton with the fleet's topology, as the baseline of the scale benchmark.

``world``: publishes /clock and a SensorBundle per UAV (10 gyro, 2-3 altimeter, 1 GPS
samples, like the real world at 10 Hz control / 100 Hz gyro), then waits for every agent's
TwistStamped answering that step (lockstep), ``--steps`` times; prints steps per second.
``agent``: on each bundle publishes a UavState carrying two fires on /fleet/state (the fleet's
one peer message per step), subscribes to every peer's, and answers with its command. No
estimation, consensus or control: what is left is the cost of DDS + rclpy for this topology.
``--wire bytes`` (the default): the messages travel as the fleet's do: the world
writes each bundle as CDR bytes (``fire_uav_common.codecs.sensor_bundle``) and publishes them raw,
an agent reads its bundle and every peer state from their bytes (the same codec,
``fire_uav_common.codecs.uav_state``) and publishes its state as serialised bytes; signing is left
out. ``--wire messages``: rclpy messages end to end (bundles of ``sensor_msgs/Imu`` objects, typed
takes), as the fleet sent them before it wrote bundles and states as bytes.
``--peer-messages 2``: the older protocol with two peer messages per step (messages only): a UavState without fires
and a FireEstimateArray (two fires) on /fleet/fires.

``--fidelity full`` (the scale benchmark's reference): every process and every topic
of a fleet mission without a recorder (``fire_mission.runner --no-record``), each message of the size
and at the rate the fleet sends it, and the fleet's protocol, still without algorithms:
- ``world``: /clock, the bundles, /world/truth (every vehicle, two fires) every step, and at the
  world's 2 Hz /viz/world (N + 7 markers) and /tf (a transform per vehicle); it waits for every agent's signed PayloadRequest (HMAC checked) as the signed world
  does, and subscribes /fleet/events.
- ``agent``: waits for every peer's state of step k-1 before it answers bundle k (the fleet's
  lockstep peer wait, ``fire_uav_agent.lockstep_wait``), checks each state's HMAC, and publishes a
  signed state (one fire), a signed PayloadRequest, its TwistStamped command and /tf every step,
  and three markers (a 90-point cell outline, a centroid, a label) every 5th step; it subscribes
  the fleet topics an FF agent subscribes (/fleet/perimeter, /fleet/front, /fleet/events), idle in
  an FF mission as in the fleet.
- ``supervisor``: the runner's subscriptions (/clock, /world/truth, both event topics, /fleet/state
  drained, as messages), reading the fields the runner reads.
``--fidelity minimal`` (the older reference, for the rows measured against it): the world
publishes /clock and bundles and waits for the commands; agents publish an unsigned state and
the command as soon as a bundle arrives; no runner.

usage: python -m fire_bench.skeleton world --uavs N --steps S [--fidelity full|minimal] [--wire bytes|messages]
       python -m fire_bench.skeleton agent --uav-id K --uavs N [--fidelity ...] [--peer-messages 1|2] [--wire ...]
       python -m fire_bench.skeleton supervisor --uavs N
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time

import rclpy
from builtin_interfaces.msg import Time
from fire_uav_common import topics
from fire_uav_common.auth import Authenticator
from fire_uav_common.ros_io import spin
from fire_uav_common.stamps import s_to_ns, stamp_to_ns, step_to_ns, to_time_msg
from fire_uav_msgs.msg import (
    FireEstimate,
    FireEstimateArray,
    FireTruth,
    GpsFix,
    PayloadRequest,
    SensorBundle,
    UavState,
    VehicleTruth,
    WorldTruth,
)
from geometry_msgs.msg import Point, TransformStamped, TwistStamped
from rclpy.node import Node
from rclpy.serialization import serialize_message
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, Range
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

CONTROL_PERIOD_S = 0.1
PERIOD_NS = s_to_ns(CONTROL_PERIOD_S)
#: the skeleton's fleet key (full fidelity signs and checks as the fleet does; not a secret)
SKELETON_KEY = bytes(range(32))
VIZ_EVERY_STEPS = 5  # the world's viz_rate_hz (2 Hz) and the agents' marker_every_steps (5), at 10 Hz
# What the fleet's messages carry on average, read from the bags of ff_two_fires missions (20 UAVs
# for 15 s, 5 UAVs for 30 s; docs/benchmarks.md "Scale"): 7.0 gyro, 2.0 altimeter and 0.9 GPS samples
# a bundle; 0-1 fires a state (none known before ~7 s); 88-107 points on a cell outline; N + 7
# markers on /viz/world (an arrow a vehicle, the lake, the legend, the fires).
FIRES = 2  # fires in /world/truth (ff_two_fires)
STATE_FIRES = 1  # fires in a state (the full skeleton; the minimal one sends 2)
GYRO, ALTIMETER = 7, 2
CELL_POINTS = 90  # points of an agent's Voronoi cell outline marker
WORLD_MARKERS_BEYOND_VEHICLES = 7


def _markers(stamp: Time, specs: list[tuple[str, int, int, int]]) -> MarkerArray:
    """A MarkerArray of (namespace, id, type, points) markers, filled as the fleet fills its own."""
    arr = MarkerArray()
    for ns, i, kind, points in specs:
        m = Marker(ns=ns, id=i, type=kind, action=Marker.ADD)
        m.header.stamp, m.header.frame_id = stamp, "map"
        m.points = [Point(x=float(j), y=float(j), z=0.0) for j in range(points)]
        m.pose.position = Point(x=1.0, y=2.0, z=3.0)
        m.scale.x = m.scale.y = m.scale.z = 2.0
        m.color.g, m.color.a = 1.0, 0.8
        if kind == Marker.TEXT_VIEW_FACING:
            m.text = f"{ns} SUPPRESS fire 1 water 2000 kg"
        arr.markers.append(m)
    return arr


class SkeletonWorld(Node):
    def __init__(
        self, n: int, steps: int, wire: str = "bytes", full: bool = False, truth_subscribers: int = 1
    ) -> None:
        super().__init__("skeleton_world")
        self.n, self.steps, self.k = n, steps, 0
        self.truth_subscribers = truth_subscribers  # as the world's wait_for_subscribers (the runner: 1)
        self.full = full
        self.as_bytes = wire == "bytes"  # the fleet's wire (module docstring)
        if self.as_bytes:  # world role only: the world package is imported here, not per bundle
            from fire_uav_common.codecs import sensor_bundle
            from fire_world_sim import sensors, world

            self._wire, self._sensors, self._world = sensor_bundle, sensors, world
        self.clock_pub = topics.publisher(self, topics.CLOCK_SPEC)
        self.sensor_pubs = [topics.publisher(self, topics.SENSORS_SPEC, uav_id=i) for i in range(n)]
        self.answered: set[int] = set()
        if full:  # the signed world: the signed PayloadRequest is the answer (world_node._on_payload)
            self.auth = Authenticator(SKELETON_KEY)
            self.truth_pub = topics.publisher(self, topics.WORLD_TRUTH_SPEC)
            self.events_pub = topics.publisher(self, topics.WORLD_EVENTS_SPEC)
            self.viz_pub = topics.publisher(self, topics.VIZ_WORLD_SPEC)
            self.grid_pub = topics.publisher(self, topics.VIZ_FIRE_GRID_SPEC)  # raster fires only
            self.tf_pub = topics.publisher(self, topics.TF_SPEC)
            for i in range(n):
                topics.subscription(
                    self, topics.PAYLOAD_SPEC, lambda d, i=i: self.on_payload(i, d), uav_id=i, raw=True
                )
            topics.subscription(self, topics.FLEET_EVENTS_SPEC, lambda m: None)
        else:
            for i in range(n):
                topics.subscription(self, topics.CMD_SPEC, lambda m, i=i: self.on_cmd(i, m), uav_id=i)
        self.t0 = None
        self.started = False
        from fire_world_sim.world_node import RESEND_AFTER_WALL_S  # the real world's (world role only)

        self.resend_after_wall_s = RESEND_AFTER_WALL_S
        self.resends = 0
        self._last_progress = time.monotonic()
        self.create_timer(0.05, self.wait_for_agents)
        self.create_timer(1.0, self.resend_if_stuck)

    def wait_for_agents(self) -> None:
        if self.started:
            return
        answer = topics.PAYLOAD_SPEC if self.full else topics.CMD_SPEC
        if (
            all(p.get_subscription_count() > 0 for p in self.sensor_pubs)
            and all(self.count_publishers(answer.for_uav(i)) > 0 for i in range(self.n))
            and (not self.full or self.truth_pub.get_subscription_count() >= self.truth_subscribers)
        ):
            self.started = True
            self.t0 = time.monotonic()
            self.publish_step()

    def resend_if_stuck(self) -> None:
        """As the real world (``world_node``): after its RESEND_AFTER_WALL_S without an answer from
        every agent, send the step's bundle again to those that have not answered. A bundle
        published while discovery is still settling can be lost (a 30-UAV skeleton waited
        forever for one answer); an agent answers every bundle, and a second answer is ignored."""
        if not self.started or time.monotonic() - self._last_progress < self.resend_after_wall_s:
            return
        missing = {i for i in range(self.n) if i not in self.answered}
        self.resends += len(missing)
        self._last_progress = time.monotonic()
        self.publish_step(only=missing)

    def publish_step(self, only: set[int] | None = None) -> None:
        stamp = to_time_msg(step_to_ns(self.k, PERIOD_NS), Time)
        if only is None:
            self.clock_pub.publish(Clock(clock=stamp))
            self.answered.clear()
            self._last_progress = time.monotonic()
        for i, pub in enumerate(self.sensor_pubs):
            if only is not None and i not in only:
                continue
            pub.publish(self._bundle_bytes(i) if self.as_bytes else self._bundle_msg(i, stamp))
        if only is None and self.full:
            self._publish_world_topics(stamp)

    def _publish_world_topics(self, stamp: Time) -> None:
        """/world/truth every step; /viz/world and /tf at the world's 2 Hz (world_node._publish)."""
        m = WorldTruth(step=self.k, min_separation_m=100.0, collisions=0)
        m.header.stamp, m.header.frame_id = stamp, "map"
        m.vehicles = [
            VehicleTruth(uav_id=i, x_m=float(i), y_m=1.0, z_m=40.0, water_kg=2000.0) for i in range(self.n)
        ]
        m.fires = [
            FireTruth(fire_id=j, x_m=10.0, y_m=20.0, extent_m=30.0, area_m2=900.0) for j in range(FIRES)
        ]
        self.truth_pub.publish(m)
        if self.k % VIZ_EVERY_STEPS:
            return
        specs = [("uav", i, Marker.ARROW, 0) for i in range(self.n)]
        specs += [("legend", j, Marker.TEXT_VIEW_FACING, 0) for j in range(WORLD_MARKERS_BEYOND_VEHICLES)]
        self.viz_pub.publish(_markers(stamp, specs))
        tf = TFMessage()
        for i in range(self.n):
            t = TransformStamped()
            t.header.stamp, t.header.frame_id = stamp, "map"
            t.child_frame_id = f"uav_{i}"
            t.transform.translation.x, t.transform.translation.z = float(i), 40.0
            t.transform.rotation.z, t.transform.rotation.w = math.sin(0.5), math.cos(0.5)
            tf.transforms.append(t)
        self.tf_pub.publish(tf)

    def _bundle_msg(self, i: int, stamp: Time) -> SensorBundle:
        b = SensorBundle(uav_id=i, step=self.k, control_period_s=CONTROL_PERIOD_S)
        b.header.stamp = stamp
        b.gyro = [Imu() for _ in range(10)]
        b.altimeter = [Range() for _ in range(2 + self.k % 2)]
        b.gps = [GpsFix()]
        return b

    def _bundle_bytes(self, i: int) -> bytes:
        s, t = self._sensors, step_to_ns(self.k, PERIOD_NS)
        b = self._world.SensorBundleRecord(i, self.k, t, CONTROL_PERIOD_S)
        if self.full:  # the fleet's mean bundle (above)
            b.gyro = [s.GyroSample(t, 0.0) for _ in range(GYRO)]
            b.altimeter = [s.AltimeterSample(t, 0.0, 40.0) for _ in range(ALTIMETER)]
        else:
            b.gyro = [s.GyroSample(t, 0.0) for _ in range(10)]
            b.altimeter = [s.AltimeterSample(t, 0.0, 40.0) for _ in range(2 + self.k % 2)]
        b.gps = [s.GpsSample(t, 0.0, 0.0, 9.0)]
        return self._wire.write_sensor_bundle(b, 0.3)

    def on_payload(self, i: int, data: bytes) -> None:
        """A signed PayloadRequest: the answer of the signed world (its HMAC checked first)."""
        stamp_ns = step_to_ns(self.k, PERIOD_NS)
        if not self.auth.check_serialized(data, topics.PAYLOAD_SPEC.for_uav(i), i, stamp_ns):
            return  # another step's (a second answer) or not ours
        self._answered(i)

    def on_cmd(self, i: int, msg: TwistStamped) -> None:
        if stamp_to_ns(msg.header.stamp) != step_to_ns(self.k, PERIOD_NS):
            return
        self._answered(i)

    def _answered(self, i: int) -> None:
        self.answered.add(i)
        if len(self.answered) == self.n:
            self.k += 1
            if self.k >= self.steps:
                wall = time.monotonic() - self.t0
                print(
                    json.dumps(
                        {
                            "steps": self.k,
                            "wall_s": wall,
                            "steps_per_s": self.k / wall,
                            "resends": self.resends,
                        }
                    ),
                    flush=True,
                )
                raise SystemExit(0)
            self.publish_step()


class SkeletonAgent(Node):
    def __init__(
        self, k: int, n: int, peer_messages: int = 1, wire: str = "bytes", full: bool = False
    ) -> None:
        super().__init__("skeleton_agent", namespace=topics.uav_namespace(k))
        self.k, self.n, self.seq = k, n, 0
        self.full = full
        self.peer_messages = peer_messages
        self.cmd_pub = topics.publisher(self, topics.CMD_SPEC)
        self.state_pub = topics.publisher(self, topics.FLEET_STATE_SPEC)
        if not full:  # the fleet no longer publishes /fleet/fires
            self.fires_pub = topics.publisher(self, topics.FLEET_FIRES_SPEC)
        self.as_bytes = wire == "bytes"  # the fleet's wire (module docstring)
        if self.as_bytes:
            from fire_uav_common.codecs.sensor_bundle import read_sensor_bundle
            from fire_uav_common.codecs.uav_state import read_uav_state

            self._read_bundle, self._read_state = read_sensor_bundle, read_uav_state
        topics.subscription(self, topics.SENSORS_SPEC, self.on_bundle, raw=self.as_bytes)
        self.heard = 0
        self.cpu0: float | None = None  # process CPU time at the first bundle [s]
        self.cpu_last = 0.0
        self.bundles = 0
        self.state_sub = topics.subscription(
            self, topics.FLEET_STATE_SPEC, self.on_peer, drain=True, raw=self.as_bytes
        )
        if full:  # the FF agent's other endpoints (agent_node.__init__)
            self.auth = Authenticator(SKELETON_KEY)
            self.payload_pub = None  # made once every peer and the runner hear our state (ready)
            self._ready_timer = self.create_timer(0.05, self._check_ready)
            self.viz_pub = topics.publisher(self, topics.VIZ_AGENT_SPEC)
            self.events_pub = topics.publisher(self, topics.FLEET_EVENTS_SPEC)
            self.perimeter_pub = topics.publisher(self, topics.FLEET_PERIMETER_SPEC)
            self.front_pub = topics.publisher(self, topics.FLEET_FRONT_SPEC)
            self.tf_pub = topics.publisher(self, topics.TF_SPEC)
            topics.subscription(self, topics.FLEET_PERIMETER_SPEC, lambda d: None, raw=True)
            topics.subscription(self, topics.FLEET_FRONT_SPEC, lambda m: None, drain=True)
            topics.subscription(self, topics.FLEET_EVENTS_SPEC, lambda m: None)
            self.states_of: dict[int, set[int]] = {}  # step -> peers whose state of that step is in
            self.pending: tuple[int, Time] | None = None  # a bundle waiting for the peers' states
            self.pending_since = 0.0  # [s, monotonic]
            self.last_answered = -1
            self.create_timer(2.0, self._say_what_is_missing)
        else:
            topics.subscription(self, topics.FLEET_FIRES_SPEC, self.on_peer, drain=True)

    def _say_what_is_missing(self) -> None:
        """A wait of more than 2 s is worth a line on stderr: the peers whose state it lacks."""
        if self.pending is None or time.monotonic() - self.pending_since < 2.0:
            return
        step = self.pending[0]
        have = self.states_of.get(step - 1, set())
        missing = sorted(set(range(self.n)) - have - {self.k})
        print(
            f"agent {self.k}: step {step} waits for the step-{step - 1} states of {missing}",
            file=sys.stderr,
            flush=True,
        )

    def _check_ready(self) -> None:
        """The fleet's start-up handshake (``agent_node._check_ready``), on /fleet/state: ready once
        every peer's reader is matched by our writer and every peer's writer by our reader (a state
        of step 0 sent before that is dropped by DDS, and the peer would wait for it for ever). Then
        the agent makes its payload publisher, which the world waits for before step 0 (the fleet's
        agents say AGENT_READY instead)."""
        peers = {topics.uav_namespace(j) for j in range(self.n) if j != self.k}
        me = (self.get_name(), self.get_namespace())
        name = topics.FLEET_STATE_SPEC.name
        for infos, matched in (
            (self.get_subscriptions_info_by_topic(name), self.state_pub.get_subscription_count()),
            (self.get_publishers_info_by_topic(name), self.state_sub.get_publisher_count()),
        ):
            others = [i for i in infos if (i.node_name, i.node_namespace) != me]
            if not peers <= {i.node_namespace for i in others} or matched < len(others):
                return  # a peer not discovered, or discovered and not matched yet
        self._ready_timer.cancel()
        self.payload_pub = topics.publisher(self, topics.PAYLOAD_SPEC)

    def on_peer(self, msg) -> None:
        self.heard += 1
        if not (self.as_bytes and isinstance(msg, bytes)):
            return
        w = self._read_state(msg)  # as the fleet reads every peer state
        if not self.full or w.uav_id == self.k:
            return
        if not self.auth.check_serialized(msg, topics.FLEET_STATE_SPEC.name, w.uav_id, w.step):
            return
        self.states_of.setdefault(w.step, set()).add(w.uav_id)
        self._maybe_answer()

    def on_bundle(self, b) -> None:
        if self.cpu0 is None:
            self.cpu0 = time.process_time()
        if self.as_bytes:
            wb = self._read_bundle(b)
            step, stamp = wb.bundle.step, Time(sec=wb.stamp_sec, nanosec=wb.stamp_nanosec)
        else:
            step, stamp = b.step, b.header.stamp
        if self.full and step <= self.last_answered:  # a re-sent bundle: answer again, as the fleet does
            self.answer(step, stamp)
        elif self.full:  # lockstep: step k runs once every peer's state of step k-1 is in
            if self.pending is None or self.pending[0] != step:
                self.pending_since = time.monotonic()
            self.pending = (step, stamp)
            self._maybe_answer()
        else:
            self.answer(step, stamp)

    def _maybe_answer(self) -> None:
        if self.pending is None:
            return
        step, stamp = self.pending
        if step > 0 and len(self.states_of.get(step - 1, ())) < self.n - 1:
            return
        self.pending, self.last_answered = None, step
        for s in [s for s in self.states_of if s < step]:
            del self.states_of[s]
        self.answer(step, stamp)

    def answer(self, step: int, stamp: Time) -> None:
        self.bundles += 1
        self.seq += 1
        s = UavState(uav_id=self.k, sequence=self.seq, step=step)
        s.header.stamp = stamp
        if self.peer_messages == 1:
            s.fires_sequence = self.seq
            s.fires = [FireEstimate(fire_id=j) for j in range(STATE_FIRES if self.full else 2)]
            if self.full:
                data = serialize_message(s)
                self.state_pub.publish(
                    self.auth.sign_serialized(data, topics.FLEET_STATE_SPEC.name, self.k, step)
                )
            else:
                self.state_pub.publish(serialize_message(s) if self.as_bytes else s)  # the fleet: bytes
        else:
            self.state_pub.publish(s)
            f = FireEstimateArray(
                uav_id=self.k,
                sequence=self.seq,
                step=step,
                fires=[FireEstimate(fire_id=j) for j in range(2)],
            )
            f.header.stamp = stamp
            self.fires_pub.publish(f)
        if self.full and self.payload_pub is not None:
            req = PayloadRequest(uav_id=self.k, action=0, target_fire_id=-1)
            req.header.stamp, req.header.frame_id = stamp, "map"
            req.cmd_linear_x_mps = 50.0
            topic = topics.PAYLOAD_SPEC.for_uav(self.k)
            self.payload_pub.publish(
                self.auth.sign_serialized(serialize_message(req), topic, self.k, stamp_to_ns(stamp))
            )
        c = TwistStamped()
        c.header.stamp = stamp
        if self.full:
            c.header.frame_id = f"uav_{self.k}"
        c.twist.linear.x = 50.0
        self.cmd_pub.publish(c)
        if self.full:
            ns = f"uav_{self.k}"
            if step % VIZ_EVERY_STEPS == 0:
                kinds = [(ns, 0, Marker.POINTS, CELL_POINTS), (ns, 1, Marker.SPHERE, 0)]
                self.viz_pub.publish(_markers(stamp, [*kinds, (ns, 2, Marker.TEXT_VIEW_FACING, 0)]))
            t = TransformStamped()
            t.header.stamp, t.header.frame_id = stamp, "map"
            t.child_frame_id = f"{ns}/estimate"
            t.transform.translation.x, t.transform.translation.z = 1.0, 40.0
            t.transform.rotation.z, t.transform.rotation.w = math.sin(0.5), math.cos(0.5)
            self.tf_pub.publish(TFMessage(transforms=[t]))
        self.cpu_last = time.process_time()

    def report(self) -> None:
        """CPU per step over the stepping phase (first to last bundle), as one JSON line."""
        if self.cpu0 is not None and self.bundles > 1:
            ms = 1000 * (self.cpu_last - self.cpu0) / (self.bundles - 1)
            print(json.dumps({"cpu_ms_per_step": ms, "bundles": self.bundles}), flush=True)


class SkeletonSupervisor(Node):
    """The runner's subscriptions (``fire_mission.runner``): what it takes and reads every step."""

    def __init__(self) -> None:
        super().__init__("skeleton_supervisor")
        self.t_s = 0.0
        self.vehicles: dict[int, tuple[float, float]] = {}
        self.states: dict[int, tuple] = {}
        topics.subscription(self, topics.CLOCK_SPEC, self.on_clock)
        topics.subscription(self, topics.WORLD_TRUTH_SPEC, self.on_truth)
        topics.subscription(self, topics.WORLD_EVENTS_SPEC, lambda m: None)
        topics.subscription(self, topics.FLEET_EVENTS_SPEC, lambda m: None)
        topics.subscription(self, topics.FLEET_STATE_SPEC, self.on_state, drain=True)

    def on_clock(self, msg: Clock) -> None:
        self.t_s = stamp_to_ns(msg.clock) / 1e9

    def on_truth(self, msg: WorldTruth) -> None:
        for v in msg.vehicles:
            self.vehicles[v.uav_id] = (float(v.water_kg), v.status)

    def on_state(self, msg: UavState) -> None:
        self.states[int(msg.uav_id)] = (
            stamp_to_ns(msg.header.stamp),
            (msg.packets_received, msg.packets_lost, msg.packets_rejected),
            list(msg.alive_peers),
            int(msg.objective),
        )


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="skeleton")
    p.add_argument("role", choices=["world", "agent", "supervisor"])
    p.add_argument("--uavs", type=int, required=True)
    p.add_argument("--uav-id", type=int, default=0)
    p.add_argument("--steps", type=int, default=300)
    p.add_argument(
        "--fidelity",
        choices=["full", "minimal"],
        default="full",
        help="full: every process and topic of the fleet, signed, with the lockstep peer wait (default); "
        "minimal: bundles, one unsigned state and the command",
    )
    p.add_argument(
        "--peer-messages",
        type=int,
        choices=[1, 2],
        default=1,
        help="peer messages per step (1: UavState with the fires, as the fleet, on the fleet's byte wire; "
        "2: UavState + FireEstimateArray, as messages)",
    )
    p.add_argument(
        "--wire",
        choices=["bytes", "messages"],
        default="bytes",
        help="bytes: bundles and states read and written as CDR bytes, as the fleet (default); "
        "messages: rclpy messages end to end",
    )
    p.add_argument(
        "--wait-for-subscribers",
        type=int,
        default=1,
        help="world, full fidelity: start once /world/truth has this many subscribers (the runner's: 1; "
        "a test's probe that subscribes to /world/truth last makes 2)",
    )
    a = p.parse_args(argv)
    if a.peer_messages == 2 and a.wire == "bytes":
        p.error("--peer-messages 2 (the older two-message protocol) runs on --wire messages only")
    if a.wait_for_subscribers < 1:
        p.error(f"--wait-for-subscribers must be >= 1, got {a.wait_for_subscribers}")
    full = a.fidelity == "full"
    if full and (a.wire != "bytes" or a.peer_messages != 1):
        p.error("--fidelity full is the fleet's protocol: --wire bytes and --peer-messages 1 only")
    rclpy.init()
    node: Node
    if a.role == "world":
        node = SkeletonWorld(a.uavs, a.steps, a.wire, full, a.wait_for_subscribers)
    elif a.role == "agent":
        node = SkeletonAgent(a.uav_id, a.uavs, a.peer_messages, a.wire, full)
    else:
        node = SkeletonSupervisor()
    spin(node, node.report if isinstance(node, SkeletonAgent) else None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
