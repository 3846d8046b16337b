"""The recorder loses none of a vehicle's first messages: by the time ``/world/truth`` shows it as
a subscriber it has subscribed to every fleet topic it can name from ``uav_count``.

The world starts stepping once ``/world/truth`` has its subscribers (recorder and runner) and
every agent said AGENT_READY; nothing waits for the recorder's other subscriptions. A recorder
that subscribed only once its graph poll found a topic's publisher was still subscribing to ~90
topics at step 0 of a 20-UAV mission: late-followed vehicles lost their first 1-7 steps on
``/uav_k/sensors``, ``cmd``, ``payload`` and ``viz`` (~40 topics short in one measured run).

Here a stand-in for the world (this file run as a script) waits for the recorder on
``/world/truth`` as the world does, then makes its per-vehicle publishers and publishes from
their first moment, a burst of :data:`STEPS` steps each; every one must be in the bag.
"""

from __future__ import annotations

import signal
import sys
import time
from pathlib import Path

import pytest
from held_up import wait_for_line

pytestmark = pytest.mark.system

UAVS = 5
STEPS = 50  # per topic, back to back: fewer than the lockstep publishers' depth (100)
LOCKSTEP = ("sensors", "cmd", "payload")


def test_recorder_keeps_the_first_messages_of_publishers_made_after_it_is_seen(procs, tmp_path):
    import fire_uav_recording as bag_io
    from fire_mission.procs import ros_run_argv
    from rosbags.interfaces import QosDurability, QosReliability

    bag = tmp_path / "bag"
    procs.start(
        "recorder",
        ros_run_argv("fire_uav_recording", "recorder", ["-p", f"output:={bag}", "-p", f"uav_count:={UAVS}"]),
    )
    procs.start("world", [sys.executable, str(Path(__file__).resolve()), str(UAVS), str(STEPS)])
    wait_for_line(
        procs, "world", "acked", 60.0, lines=200, poll_s=0.01
    )  # all in the recorder's reader histories
    wait_for_line(
        procs, "recorder", "following /fleet/front", 10.0, lines=200, poll_s=0.01
    )  # its graph poll saw it
    procs.stop(["world"])
    procs.signal("recorder", signal.SIGINT)
    assert procs.children["recorder"].popen.wait(timeout=20) == 0, procs.tail("recorder")

    per_vehicle = [f"/uav_{k}/{name}" for k in range(UAVS) for name in LOCKSTEP]
    with bag_io.open_bag(bag) as b:
        assert b.warnings == []
        # a topic with a publisher but no message has its (empty) connection, as discovery made
        # it; topics nobody published on (/clock, /uav_k/viz, /fleet/fires, ...) have none
        assert set(b.topics) == {*per_vehicle, "/world/truth", "/fleet/front"}
        assert sum(c.msgcount for c in b.connections(["/fleet/front"])) == 0
        # each connection's offered QoS is its publisher's, as the graph shows it (as before)
        for conn in b.connections():
            (offered,) = bag_io.offered_qos(conn)
            assert offered.reliability == QosReliability.RELIABLE, conn.topic
            assert offered.durability == QosDurability.VOLATILE and offered.depth == 0, conn.topic
        got: dict[str, list[int]] = {t: [] for t in [*per_vehicle, "/world/truth"]}
        for topic, _, msg in b.messages(list(got)):
            got[topic].append(msg.header.stamp.sec)
    every = list(range(STEPS))
    short = {t: sorted(set(every) - set(steps)) for t, steps in got.items() if steps != every}
    lost = {
        t: f"{len(m)} of {STEPS} (steps {m[0]}-{m[-1]})" if m else "out of order" for t, m in short.items()
    }
    assert not short, f"lost {lost}; recorder log:\n{procs.tail('recorder', 60)}"


def stand_in_world(uavs: int, steps: int) -> int:
    """The world's start as the recorder sees it: make a ``/fleet/front`` publisher that never
    publishes, wait (up to 30 s) for a subscriber of ``/world/truth``, then for each of
    ``/uav_<k>/{sensors,cmd,payload}`` and ``/world/truth`` publish ``steps`` messages (header
    stamp = step [s]) back to back, the first at once after the publisher is made. Once every
    subscription acknowledged them (in its reader history) prints ``acked`` and waits for
    SIGINT/SIGTERM (exit 0); 1 on a timeout."""
    import rclpy
    from fire_uav_common import topics
    from fire_uav_msgs.msg import PayloadRequest, SensorBundle, WorldTruth
    from geometry_msgs.msg import TwistStamped
    from rclpy.duration import Duration
    from rclpy.executors import ExternalShutdownException
    from rclpy.node import Node

    rclpy.init()
    node = Node("stand_in_world")
    try:
        topics.publisher(node, topics.FLEET_FRONT_SPEC)
        truth = topics.publisher(node, topics.WORLD_TRUTH_SPEC)
        deadline = time.monotonic() + 30.0
        while truth.get_subscription_count() < 1:
            if time.monotonic() > deadline:
                print("no /world/truth subscriber within 30 s", flush=True)
                return 1
            time.sleep(0.01)
        specs = {"sensors": topics.SENSORS_SPEC, "cmd": topics.CMD_SPEC, "payload": topics.PAYLOAD_SPEC}
        kinds = {"sensors": SensorBundle, "cmd": TwistStamped, "payload": PayloadRequest}
        pubs = [truth]
        for k in range(uavs):
            for name in LOCKSTEP:
                pub = topics.publisher(node, specs[name], uav_id=k)
                pubs.append(pub)
                for step in range(steps):
                    msg = kinds[name]()
                    msg.header.stamp.sec = step
                    pub.publish(msg)
        for step in range(steps):
            msg = WorldTruth(step=step)
            msg.header.stamp.sec = step
            truth.publish(msg)
        for pub in pubs:
            if not pub.wait_for_all_acked(Duration(seconds=30)):
                print(f"{pub.topic_name}: not acknowledged within 30 s", flush=True)
                return 1
        print("acked", flush=True)
        try:
            rclpy.spin(node)  # the publishers stay on the graph until the test stops this process
        except (KeyboardInterrupt, ExternalShutdownException):
            pass
        return 0
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(stand_in_world(int(sys.argv[1]), int(sys.argv[2])))
