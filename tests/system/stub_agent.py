"""A stub agent for world-only system tests: answers every SensorBundle with a command that
depends only on the bundle (take off, then fly a fixed circle), never on wall time.

usage: stub_agent.py UAV_ID
"""

from __future__ import annotations

import sys

import rclpy
from fire_uav_common import topics
from fire_uav_common.constants import EventType, PayloadAction
from fire_uav_common.ros_io import spin
from fire_uav_msgs.msg import MissionEvent, PayloadRequest, SensorBundle
from geometry_msgs.msg import TwistStamped
from rclpy.node import Node


class StubAgent(Node):
    def __init__(self, k: int) -> None:
        super().__init__("stub_agent", namespace=topics.uav_namespace(k))
        self.k = k
        self.pub = topics.publisher(self, topics.CMD_SPEC)
        self.payload = topics.publisher(self, topics.PAYLOAD_SPEC)
        self.sub = topics.subscription(self, topics.SENSORS_SPEC, self.on_bundle)
        self.events = topics.publisher(self, topics.FLEET_EVENTS_SPEC)
        # the lockstep start-up handshake: ready once the world's topics are matched
        self.ready_timer = self.create_timer(0.05, self.say_ready)

    def say_ready(self) -> None:
        if 0 in (
            self.pub.get_subscription_count(),
            self.payload.get_subscription_count(),
            self.sub.get_publisher_count(),
        ):
            return
        self.ready_timer.cancel()
        ev = MissionEvent(type=int(EventType.AGENT_READY), uav_id=self.k, peer_id=-1, fire_id=-1)
        ev.detail = "stub ready"
        self.events.publish(ev)

    def on_bundle(self, b: SensorBundle) -> None:
        c = TwistStamped()
        c.header.stamp = b.header.stamp
        c.twist.linear.x = 50.0  # above stall: take off and cruise
        c.twist.linear.z = 5.0 if b.step < 40 else 0.0
        c.twist.angular.z = 0.2 + 0.05 * self.k
        self.payload.publish(
            PayloadRequest(header=c.header, uav_id=self.k, action=int(PayloadAction.NONE), target_fire_id=-1)
        )
        self.pub.publish(c)


def main() -> int:
    rclpy.init()
    node = StubAgent(int(sys.argv[1]))
    spin(node)
    return 0


if __name__ == "__main__":
    sys.exit(main())
