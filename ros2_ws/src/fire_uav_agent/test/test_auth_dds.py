"""A serialised tag survives DDS: the bytes a raw subscription hands over are the bytes published.

``Authenticator.sign_serialized`` / ``check_serialized`` (docs/security.md) rest on that: the
receiver hashes what arrived, alignment padding included, with no re-serialisation. Real rclpy
and Fast DDS (shared memory between two nodes of this process), the fleet's topic helpers and
QoS, a drained raw subscription as the agents have; private context and domain.
"""

from __future__ import annotations

import time

import pytest

rclpy = pytest.importorskip("rclpy")

from fire_uav_common import topics  # noqa: E402
from fire_uav_common.auth import Authenticator  # noqa: E402
from fire_uav_msgs.msg import FireEstimate, UavState  # noqa: E402
from rclpy.serialization import deserialize_message, serialize_message  # noqa: E402

KEY = bytes(range(1, 33))


def _state(k: int) -> UavState:
    m = UavState(uav_id=2, sequence=k + 1, step=k, objective=1, target_fire_id=k % 3 - 1)
    m.header.frame_id = "map"[: k % 4]  # every length mod 4: the padding moves
    m.water_kg = 400.0 - 0.1 * k
    m.alive_peers = list(range(k % 5))
    m.fires = [FireEstimate(fire_id=j, x_m=10.0 * j, extent_m=3.0) for j in range(k % 3)]
    return m


def test_signed_bytes_arrive_unchanged_and_check(node_pair):
    a, b, spin = node_pair
    auth = Authenticator(KEY)
    got: list[bytes] = []
    topics.subscription(b, topics.FLEET_STATE_SPEC, got.append, drain=True, raw=True)
    pub = topics.publisher(a, topics.FLEET_STATE_SPEC)
    end = time.monotonic() + 10
    while pub.get_subscription_count() == 0 and time.monotonic() < end:
        spin()
    sent = [
        auth.sign_serialized(serialize_message(_state(k)), topics.FLEET_STATE_SPEC.name, 2, k)
        for k in range(40)
    ]
    for data in sent:
        pub.publish(data)
    end = time.monotonic() + 10
    while len(got) < len(sent) and time.monotonic() < end:
        spin()
    assert got == sent  # byte for byte, in order
    for k, data in enumerate(got):
        assert auth.check_serialized(data, topics.FLEET_STATE_SPEC.name, 2, k)
        m = deserialize_message(data, UavState)
        assert (m.step, m.sequence, len(m.fires), m.header.frame_id) == (k, k + 1, k % 3, "map"[: k % 4])
