"""Messaging-only skeleton with the fleet's topology, as the baseline of the scale benchmark.

``world``: publishes /clock and a SensorBundle per UAV (10 gyro, 2-3 altimeter, 1 GPS
samples, like the real world at 10 Hz control / 100 Hz gyro), then waits for every agent's
TwistStamped answering that step (lockstep), ``--steps`` times; prints steps per second.
``agent``: on each bundle publishes a UavState carrying two fires on /fleet/state (the fleet's
one peer message per step), subscribes to every peer's, and answers with its command. No
estimation, consensus or control: what is left is the cost of DDS + rclpy for this topology.
``--wire bytes`` (the default): the messages travel as the fleet's do (session 13): the world
writes each bundle as CDR bytes (``fire_world_sim.bundle_wire``) and publishes them raw, an agent
reads its bundle and every peer state from their bytes (``fire_uav_agent.bundle_wire``,
``state_wire``) and publishes its state as serialised bytes; signing is left out. ``--wire
messages``: rclpy messages end to end (bundles of ``sensor_msgs/Imu`` objects, typed takes), the
skeleton of sessions 9-12.
``--peer-messages 2``: the protocol before issue [scale] (messages only): a UavState without fires
and a FireEstimateArray (two fires) on /fleet/fires.

usage: python -m fire_bench.skeleton world --uavs N --steps S [--peer-messages 1|2] [--wire bytes|messages]
       python -m fire_bench.skeleton agent --uav-id K --uavs N [--peer-messages 1|2] [--wire ...]
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import rclpy
from builtin_interfaces.msg import Time
from fire_uav_common import topics
from fire_uav_common.ros_io import spin
from fire_uav_common.stamps import s_to_ns, stamp_to_ns, step_to_ns, to_time_msg
from fire_uav_msgs.msg import FireEstimate, FireEstimateArray, GpsFix, SensorBundle, UavState
from geometry_msgs.msg import TwistStamped
from rclpy.node import Node
from rclpy.serialization import serialize_message
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, Range

CONTROL_PERIOD_S = 0.1
PERIOD_NS = s_to_ns(CONTROL_PERIOD_S)


class SkeletonWorld(Node):
    def __init__(self, n: int, steps: int, wire: str = "bytes") -> None:
        super().__init__("skeleton_world")
        self.n, self.steps, self.k = n, steps, 0
        self.as_bytes = wire == "bytes"  # the fleet's wire (module docstring)
        if self.as_bytes:  # world role only: the world package is imported here, not per bundle
            from fire_world_sim import bundle_wire, sensors, world

            self._wire, self._sensors, self._world = bundle_wire, sensors, world
        self.clock_pub = topics.publisher(self, topics.CLOCK_SPEC)
        self.sensor_pubs = [topics.publisher(self, topics.SENSORS_SPEC, uav_id=i) for i in range(n)]
        self.answered: set[int] = set()
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
        if all(p.get_subscription_count() > 0 for p in self.sensor_pubs) and all(
            self.count_publishers(topics.CMD_SPEC.for_uav(i)) > 0 for i in range(self.n)
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

    def _bundle_msg(self, i: int, stamp: Time) -> SensorBundle:
        b = SensorBundle(uav_id=i, step=self.k, control_period_s=CONTROL_PERIOD_S)
        b.header.stamp = stamp
        b.gyro = [Imu() for _ in range(10)]
        b.altimeter = [Range() for _ in range(2 + self.k % 2)]
        b.gps = [GpsFix()]
        return b

    def _bundle_bytes(self, i: int) -> bytes:
        s, t = self._sensors, step_to_ns(self.k, PERIOD_NS)
        b = self._world.Bundle(i, self.k, t, CONTROL_PERIOD_S)
        b.gyro = [s.GyroSample(t, 0.0) for _ in range(10)]
        b.altimeter = [s.AltimeterSample(t, 0.0, 40.0) for _ in range(2 + self.k % 2)]
        b.gps = [s.GpsSample(t, 0.0, 0.0, 9.0)]
        return self._wire.write_sensor_bundle(b, 0.3)

    def on_cmd(self, i: int, msg: TwistStamped) -> None:
        if stamp_to_ns(msg.header.stamp) != step_to_ns(self.k, PERIOD_NS):
            return
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
    def __init__(self, k: int, n: int, peer_messages: int = 1, wire: str = "bytes") -> None:
        super().__init__("skeleton_agent", namespace=topics.uav_namespace(k))
        self.k, self.seq = k, 0
        self.peer_messages = peer_messages
        self.cmd_pub = topics.publisher(self, topics.CMD_SPEC)
        self.state_pub = topics.publisher(self, topics.FLEET_STATE_SPEC)
        self.fires_pub = topics.publisher(self, topics.FLEET_FIRES_SPEC)
        self.as_bytes = wire == "bytes"  # the fleet's wire (module docstring)
        if self.as_bytes:
            from fire_uav_agent.bundle_wire import read_sensor_bundle
            from fire_uav_agent.state_wire import read_uav_state

            self._read_bundle, self._read_state = read_sensor_bundle, read_uav_state
        topics.subscription(self, topics.SENSORS_SPEC, self.on_bundle, raw=self.as_bytes)
        self.heard = 0
        self.cpu0: float | None = None  # process CPU time at the first bundle [s]
        self.cpu_last = 0.0
        self.bundles = 0
        topics.subscription(self, topics.FLEET_STATE_SPEC, self.on_peer, drain=True, raw=self.as_bytes)
        topics.subscription(self, topics.FLEET_FIRES_SPEC, self.on_peer, drain=True)

    def on_peer(self, msg) -> None:
        if self.as_bytes and isinstance(msg, bytes):
            self._read_state(msg)  # as the fleet reads every peer state
        self.heard += 1

    def on_bundle(self, b) -> None:
        if self.cpu0 is None:
            self.cpu0 = time.process_time()
        if self.as_bytes:
            wb = self._read_bundle(b)
            step, stamp = wb.bundle.step, Time(sec=wb.stamp_sec, nanosec=wb.stamp_nanosec)
        else:
            step, stamp = b.step, b.header.stamp
        self.bundles += 1
        self.seq += 1
        s = UavState(uav_id=self.k, sequence=self.seq, step=step)
        s.header.stamp = stamp
        if self.peer_messages == 1:
            s.fires_sequence = self.seq
            s.fires = [FireEstimate(fire_id=j) for j in range(2)]
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
        c = TwistStamped()
        c.header.stamp = stamp
        c.twist.linear.x = 50.0
        self.cmd_pub.publish(c)
        self.cpu_last = time.process_time()

    def report(self) -> None:
        """CPU per step over the stepping phase (first to last bundle), as one JSON line."""
        if self.cpu0 is not None and self.bundles > 1:
            ms = 1000 * (self.cpu_last - self.cpu0) / (self.bundles - 1)
            print(json.dumps({"cpu_ms_per_step": ms, "bundles": self.bundles}), flush=True)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="skeleton")
    p.add_argument("role", choices=["world", "agent"])
    p.add_argument("--uavs", type=int, required=True)
    p.add_argument("--uav-id", type=int, default=0)
    p.add_argument("--steps", type=int, default=300)
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
    a = p.parse_args(argv)
    if a.peer_messages == 2 and a.wire == "bytes":
        p.error("--peer-messages 2 (the protocol before issue [scale]) runs on --wire messages only")
    rclpy.init()
    node = (
        SkeletonWorld(a.uavs, a.steps, a.wire)
        if a.role == "world"
        else SkeletonAgent(a.uav_id, a.uavs, a.peer_messages, a.wire)
    )
    spin(node, node.report if isinstance(node, SkeletonAgent) else None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
