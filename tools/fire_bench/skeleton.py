"""Messaging-only skeleton with the fleet's topology, as the baseline of the scale benchmark.

``world``: publishes /clock and a SensorBundle per UAV (10 gyro, 2-3 altimeter, 1 GPS
samples, like the real world at 10 Hz control / 100 Hz gyro), then waits for every agent's
TwistStamped answering that step (lockstep), ``--steps`` times; prints steps per second.
``agent``: on each bundle publishes a UavState carrying two fires on /fleet/state (the fleet's
one peer message per step), subscribes to every peer's, and answers with its command. No
estimation, consensus or control: what is left is the cost of DDS + rclpy for this topology.
``--peer-messages 2``: the protocol before issue [scale]: a UavState without fires and a
FireEstimateArray (two fires) on /fleet/fires.

usage: python -m fire_bench.skeleton world --uavs N --steps S
       python -m fire_bench.skeleton agent --uav-id K --uavs N [--peer-messages 1|2]
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
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, Range

CONTROL_PERIOD_S = 0.1
PERIOD_NS = s_to_ns(CONTROL_PERIOD_S)


class SkeletonWorld(Node):
    def __init__(self, n: int, steps: int) -> None:
        super().__init__("skeleton_world")
        self.n, self.steps, self.k = n, steps, 0
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
            b = SensorBundle(uav_id=i, step=self.k, control_period_s=CONTROL_PERIOD_S)
            b.header.stamp = stamp
            b.gyro = [Imu() for _ in range(10)]
            b.altimeter = [Range() for _ in range(2 + self.k % 2)]
            b.gps = [GpsFix()]
            pub.publish(b)

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
    def __init__(self, k: int, n: int, peer_messages: int = 2) -> None:
        super().__init__("skeleton_agent", namespace=topics.uav_namespace(k))
        self.k, self.seq = k, 0
        self.peer_messages = peer_messages
        self.cmd_pub = topics.publisher(self, topics.CMD_SPEC)
        self.state_pub = topics.publisher(self, topics.FLEET_STATE_SPEC)
        self.fires_pub = topics.publisher(self, topics.FLEET_FIRES_SPEC)
        topics.subscription(self, topics.SENSORS_SPEC, self.on_bundle)
        self.heard = 0
        self.cpu0: float | None = None  # process CPU time at the first bundle [s]
        self.cpu_last = 0.0
        self.bundles = 0
        topics.subscription(self, topics.FLEET_STATE_SPEC, self.on_peer, drain=True)
        topics.subscription(self, topics.FLEET_FIRES_SPEC, self.on_peer, drain=True)

    def on_peer(self, msg) -> None:
        self.heard += 1

    def on_bundle(self, b: SensorBundle) -> None:
        if self.cpu0 is None:
            self.cpu0 = time.process_time()
        self.bundles += 1
        self.seq += 1
        s = UavState(uav_id=self.k, sequence=self.seq, step=b.step)
        s.header.stamp = b.header.stamp
        if self.peer_messages == 1:
            s.fires_sequence = self.seq
            s.fires = [FireEstimate(fire_id=j) for j in range(2)]
        self.state_pub.publish(s)
        if self.peer_messages == 2:
            f = FireEstimateArray(
                uav_id=self.k,
                sequence=self.seq,
                step=b.step,
                fires=[FireEstimate(fire_id=j) for j in range(2)],
            )
            f.header.stamp = b.header.stamp
            self.fires_pub.publish(f)
        c = TwistStamped()
        c.header.stamp = b.header.stamp
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
        help="agent: peer messages per step (1: UavState with the fires, as the fleet; 2: UavState + FireEstimateArray)",
    )
    a = p.parse_args(argv)
    rclpy.init()
    node = (
        SkeletonWorld(a.uavs, a.steps)
        if a.role == "world"
        else SkeletonAgent(a.uav_id, a.uavs, a.peer_messages)
    )
    spin(node, node.report if isinstance(node, SkeletonAgent) else None)
    return 0


if __name__ == "__main__":
    sys.exit(main())
