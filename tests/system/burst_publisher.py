"""Helper process for test_recorder_stop: a burst of raw ``/fleet/state`` messages.

usage: burst_publisher.py N
Waits (up to 30 s) until a subscription has matched (the recorder's), publishes N serialized
``UavState`` messages with ``sequence`` 0..N-1 back to back (serialized before the burst, so
nothing slows it), waits until every subscription has acknowledged them (they are in its DDS
reader history, taken or not), prints ``acked N`` and exits 0; exit 1 on a timeout.
"""

from __future__ import annotations

import sys
import time


def main(n: int) -> int:
    import rclpy
    from fire_uav_common import topics
    from fire_uav_msgs.msg import UavState
    from rclpy.duration import Duration
    from rclpy.node import Node
    from rclpy.serialization import serialize_message

    rclpy.init()
    node = Node("burst_publisher")
    try:
        pub = topics.publisher(node, topics.FLEET_STATE_SPEC)
        deadline = time.monotonic() + 30.0
        while pub.get_subscription_count() < 1:
            if time.monotonic() > deadline:
                print("no subscription matched within 30 s", flush=True)
                return 1
            time.sleep(0.05)
        burst = []
        for k in range(n):
            msg = UavState()
            msg.uav_id, msg.sequence, msg.step = k % 20, k, k // 20
            burst.append(serialize_message(msg))
        for data in burst:
            pub.publish(data)
        if not pub.wait_for_all_acked(Duration(seconds=30)):
            print(f"published {n}, not acknowledged within 30 s", flush=True)
            return 1
        print(f"acked {n}", flush=True)
        return 0
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main(int(sys.argv[1])))
