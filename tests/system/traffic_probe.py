"""Helper process for test_skeleton_fidelity: counts every message on the domain, per topic.

usage: traffic_probe.py UAVS OUT.json
Subscribes raw, before any traffic, to every topic of ``fire_uav_common.topics`` (per-vehicle ones
for vehicles 0..UAVS-1) with its spec's reliability, and on SIGINT writes per fleet topic
(per-vehicle topics folded into their spec: ``/uav_<k>/cmd`` under its pattern) the messages and bytes received and
the namespaces of the nodes that publish it (polled from the graph: ``/uav_k`` for agents, ``/``
for the world and the runner; a namespace, not a node name, so that a node of an earlier run
still in the graph is not counted twice).
"""

from __future__ import annotations

import json
import signal
import sys
from collections import defaultdict
from pathlib import Path

import rclpy
from fire_uav_common import topics
from fire_uav_common.ros_io import make_executor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile


class Probe(Node):
    def __init__(self, uavs: int) -> None:
        super().__init__("traffic_probe")
        self.messages: dict[str, int] = defaultdict(int)
        self.bytes: dict[str, int] = defaultdict(int)
        self.senders: dict[str, set[str]] = defaultdict(set)
        self.names: dict[str, str] = {}  # topic name -> its spec's pattern
        # /world/truth last: DDS announces a participant's endpoints in the order they are made, so a
        # world that waits for this subscriber on /world/truth starts once all the others are known
        last = [topics.WORLD_TRUTH_SPEC]
        for spec in [t for t in topics.ALL_TOPICS if t not in last] + last:
            q = spec.qos()
            qos = QoSProfile(
                depth=max(q.depth, 1000), reliability=q.reliability, durability=DurabilityPolicy.VOLATILE
            )
            for name in [spec.for_uav(k) for k in range(uavs)] if spec.per_uav else [spec.name]:
                self.names[name] = key = spec.pattern()
                self.create_subscription(
                    spec.msg_class(), name, lambda d, k=key: self.count(k, d), qos, raw=True
                )
        self.create_timer(0.2, self.poll_graph)

    def poll_graph(self) -> None:
        for name, key in self.names.items():
            for p in self.get_publishers_info_by_topic(name):
                if p.node_namespace != "_NODE_NAMESPACE_UNKNOWN_":  # its node is not discovered yet
                    self.senders[key].add(p.node_namespace)

    def count(self, key: str, data: bytes) -> None:
        self.messages[key] += 1
        self.bytes[key] += len(data)

    def result(self) -> dict:
        return {
            k: {
                "messages": self.messages.get(k, 0),
                "bytes": self.bytes.get(k, 0),
                "publishers": sorted(self.senders.get(k, ())),
            }
            for k in sorted(set(self.messages) | set(self.senders))
        }


def main() -> int:
    uavs, out = int(sys.argv[1]), Path(sys.argv[2])
    rclpy.init(signal_handler_options=rclpy.signals.SignalHandlerOptions.NO)
    node = Probe(uavs)
    ex = make_executor()
    ex.add_node(node)
    stop = []
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    while not stop:
        ex.spin_once(0.1)
    out.write_text(json.dumps(node.result(), indent=1))
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
