"""Raw subscriptions (signed topics, docs/security.md): bytes that are no message of the topic's
type are a counted rejection, not an exception. The agent's ``_decode`` on a stand-in for its
node (only what the method touches); the world's side is fire_world_sim's
test_payload_undecodable.py."""

from __future__ import annotations

import types

import pytest

pytest.importorskip("rclpy")

from fire_uav_agent.agent_node import UavAgentNode
from fire_uav_common import topics
from fire_uav_msgs.msg import UavState
from rclpy.serialization import serialize_message

GARBAGE = [b"", b"\x00\x01\x00\x00", b"not a message at all", b"\x00\x01\x00\x00" + b"\xff" * 64]


class _Log:
    def __init__(self) -> None:
        self.lines: list[str] = []

    def warning(self, text: str, **kw) -> None:
        self.lines.append(text)


def _agent_stub():
    reasons: list[str] = []
    log = _Log()
    stub = types.SimpleNamespace(
        agent=types.SimpleNamespace(link=types.SimpleNamespace(count_rejection=reasons.append)),
        get_logger=lambda: log,
    )
    return stub, reasons, log


@pytest.mark.parametrize("data", GARBAGE)
def test_the_agent_counts_undecodable_bytes_and_names_the_topic(data):
    stub, reasons, log = _agent_stub()
    assert UavAgentNode._decode(stub, data, UavState, topics.FLEET_STATE_SPEC) is None
    assert reasons == ["undecodable"]
    assert f"rejected {len(data)} bytes on /fleet/state that are no UavState" in log.lines[0]


def test_the_agent_decodes_a_real_state():
    stub, reasons, _ = _agent_stub()
    m = UavState(uav_id=3, step=9)
    got = UavAgentNode._decode(stub, serialize_message(m), UavState, topics.FLEET_STATE_SPEC)
    assert (got.uav_id, got.step, reasons) == (3, 9, [])
