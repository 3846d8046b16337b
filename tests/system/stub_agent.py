"""A stub agent for world-only system tests: answers every SensorBundle with a command that
depends only on the bundle (take off, then fly a fixed circle), never on wall time.

usage: stub_agent.py UAV_ID
"""

from __future__ import annotations

import sys

import rclpy
from fire_uav_common import topics
from fire_uav_msgs.msg import SensorBundle
from geometry_msgs.msg import TwistStamped
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node


class StubAgent(Node):
    def __init__(self, k: int) -> None:
        super().__init__("stub_agent", namespace=topics.uav_namespace(k))
        self.k = k
        self.pub = self.create_publisher(TwistStamped, topics.CMD, topics.qos("lockstep"))
        self.create_subscription(SensorBundle, topics.SENSORS, self.on_bundle, topics.qos("lockstep"))

    def on_bundle(self, b: SensorBundle) -> None:
        c = TwistStamped()
        c.header.stamp = b.header.stamp
        c.twist.linear.x = 50.0  # above stall: take off and cruise
        c.twist.linear.z = 5.0 if b.step < 40 else 0.0
        c.twist.angular.z = 0.2 + 0.05 * self.k
        self.pub.publish(c)


def main() -> int:
    rclpy.init()
    node = StubAgent(int(sys.argv[1]))
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
