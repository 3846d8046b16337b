"""Helper process for test_messages: publishes or receives every fire_uav_msgs type.

usage: msg_probe.py pub | sub OUT.jsonl
Messages are filled deterministically by :func:`sample` (shared with the test), so the
receiver's JSON can be compared field for field with what the test builds itself.
"""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

import numpy as np

MSG_DIR_NAMES = None  # filled from the installed share/fire_uav_msgs/msg


def message_types() -> list[str]:
    from ament_index_python.packages import get_package_share_directory

    share = Path(get_package_share_directory("fire_uav_msgs")) / "msg"
    return sorted(p.stem for p in share.glob("*.msg"))


def _cls(type_str: str):
    pkg, name = type_str.split("/")[0], type_str.split("/")[-1]
    return getattr(importlib.import_module(f"{pkg}.msg"), name)


_BASIC = {
    "boolean": lambda i: bool(i % 2),
    "octet": lambda i: bytes([i % 256]),
    "char": lambda i: i % 128,
    "float": lambda i: 0.5 + i,
    "double": lambda i: 0.25 + i * 1.5,
    "int8": lambda i: -(i % 100),
    "uint8": lambda i: i % 200,
    "int16": lambda i: -i,
    "uint16": lambda i: i,
    "int32": lambda i: -1000 - i,
    "uint32": lambda i: 100000 + i,
    "int64": lambda i: -(2**40) - i,
    "uint64": lambda i: 2**40 + i,
    "string": lambda i: f"s{i}-é",
}


def _value(type_str: str, i: int):
    if type_str.startswith("sequence<"):
        inner = type_str[len("sequence<") : -1].split(",")[0]
        return [_value(inner, i + k) for k in range(3)]
    if type_str.endswith("]"):
        inner, n = type_str[:-1].split("[")
        return [_value(inner, i + k) for k in range(int(n))]
    if type_str in _BASIC:
        return _BASIC[type_str](i)
    if type_str.startswith("string<"):
        return f"b{i}"
    return sample(_cls(type_str), i)


def sample(cls, i: int = 1):
    """A message of ``cls`` with every field set to a distinct deterministic value."""
    msg = cls()
    for k, (name, type_str) in enumerate(cls.get_fields_and_field_types().items()):
        val = _value(type_str, i * 31 + k)
        if type_str.endswith("]") and not type_str.startswith("sequence<"):
            base = type_str.split("[")[0]
            if base in ("float", "double"):
                val = np.array(val, dtype=np.float64 if base == "double" else np.float32)
        setattr(msg, name, val)
    return msg


def to_plain(msg):
    """Message -> plain JSON-able structure (recursively)."""
    if hasattr(msg, "get_fields_and_field_types"):
        return {f: to_plain(getattr(msg, f)) for f in msg.get_fields_and_field_types()}
    if isinstance(msg, np.ndarray):
        return [to_plain(x) for x in msg.tolist()]
    if isinstance(msg, (list, tuple)) or type(msg).__name__ == "array":
        return [to_plain(x) for x in msg]
    if isinstance(msg, bytes):
        return list(msg)
    if isinstance(msg, (np.floating,)):
        return float(msg)
    if isinstance(msg, (np.integer,)):
        return int(msg)
    return msg


def main() -> int:
    import rclpy
    from fire_uav_common.ros_io import spin
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    qos = QoSProfile(
        depth=5, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
    )
    mode = sys.argv[1]
    types = message_types()
    rclpy.init()
    node = rclpy.create_node(f"msg_probe_{mode}")
    if mode == "pub":
        pubs = {t: node.create_publisher(_cls(f"fire_uav_msgs/{t}"), f"/probe/{t}", qos) for t in types}
        sent: set[str] = set()

        def tick() -> None:
            for t, p in pubs.items():
                if t not in sent and p.get_subscription_count() > 0:
                    p.publish(sample(_cls(f"fire_uav_msgs/{t}")))
                    sent.add(t)

        node.create_timer(0.05, tick)
    else:
        out = open(sys.argv[2], "w")  # closed at exit
        got: set[str] = set()

        def make_cb(t: str):
            def cb(msg) -> None:
                if t not in got:
                    got.add(t)
                    out.write(json.dumps({"type": t, "msg": to_plain(msg)}) + "\n")
                    out.flush()
                    if len(got) == len(types):
                        raise SystemExit(0)

            return cb

        for t in types:
            node.create_subscription(_cls(f"fire_uav_msgs/{t}"), f"/probe/{t}", make_cb(t), qos)
    spin(node)  # until every type arrived (SystemExit from the callback) or Ctrl-C
    return 0


if __name__ == "__main__":
    sys.exit(main())
