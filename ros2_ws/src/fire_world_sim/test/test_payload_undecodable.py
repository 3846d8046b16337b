"""Raw payload subscriptions (docs/security.md): bytes that are no PayloadRequest are a counted
rejection (``undecodable``), not an exception. ``WorldNode._on_payload`` on a stand-in for the
node (only what the method touches before its id check)."""

from __future__ import annotations

import types

import pytest

pytest.importorskip("rclpy")

from fire_uav_msgs.msg import PayloadRequest
from fire_world_sim.world_node import WorldNode
from rclpy.serialization import serialize_message

GARBAGE = [b"", b"\x00\x01\x00\x00", b"not a message at all", b"\x00\x01\x00\x00" + b"\xff" * 64]


@pytest.mark.parametrize("data", GARBAGE)
def test_the_world_rejects_undecodable_payload_bytes(data):
    rejected: list[tuple[int, str, str]] = []
    stub = types.SimpleNamespace(
        gate=types.SimpleNamespace(finished=False),
        _reject=lambda uid, topic, why: rejected.append((uid, topic, why)),
    )
    WorldNode._on_payload(stub, 1, data)
    assert rejected == [(1, "/uav_1/payload", "undecodable")]


def test_the_world_reads_a_real_request_past_the_decoding():
    """A well-formed request for another vehicle gets as far as the id check."""
    rejected: list[tuple[int, str, str]] = []
    stub = types.SimpleNamespace(
        gate=types.SimpleNamespace(finished=False),
        _reject=lambda uid, topic, why: rejected.append((uid, topic, why)),
    )
    WorldNode._on_payload(stub, 1, serialize_message(PayloadRequest(uav_id=2)))
    assert rejected == [(1, "/uav_1/payload", "wrong id")]
