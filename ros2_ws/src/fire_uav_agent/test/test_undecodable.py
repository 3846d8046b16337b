"""Raw subscriptions (signed topics, docs/security.md): bytes that are no message of the topic's
type are a counted rejection, not an exception. The agent's ``_decode`` and ``_read_state`` on a
stand-in for its node (only what the methods touch); the world's side is fire_world_sim's
test_payload_undecodable.py."""

from __future__ import annotations

import types

import pytest

pytest.importorskip("rclpy")

from fire_uav_agent.agent_node import UavAgentNode
from fire_uav_common import topics
from fire_uav_common.cdr import CdrError
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


def _reading_stub():
    stub, reasons, log = _agent_stub()
    stub._decode = lambda *a: UavAgentNode._decode(stub, *a)
    return stub, reasons, log


@pytest.mark.parametrize("data", GARBAGE)
def test_a_peer_state_that_neither_reader_takes_is_counted_once(data):
    stub, reasons, log = _reading_stub()
    assert UavAgentNode._read_state(stub, data) is None
    assert reasons == ["undecodable"] and len(log.lines) == 1


def test_a_state_the_fast_reader_refuses_still_reads_through_rclpy(monkeypatch):
    """Another encoding than XCDR1 little-endian (e.g. a big-endian peer) is read by rclpy's
    deserialisation and re-serialised for the codec, to the same values."""
    import fire_uav_agent.agent_node as node

    m = UavState(uav_id=3, step=9, sequence=4, x_m=1.5, fires_sequence=2, final=True)
    m.sent_per_topic = [1, 0, 1]
    data = serialize_message(m)
    stub, reasons, _ = _reading_stub()
    fast = UavAgentNode._read_state(stub, data)

    real = node.read_uav_state

    def refuse(d):  # the bytes as received are refused; rclpy's re-serialisation of them is read
        if d is data:
            raise CdrError("UavState: not XCDR1 little-endian CDR (encapsulation 0000)")
        return real(d)

    monkeypatch.setattr(node, "read_uav_state", refuse)
    slow = UavAgentNode._read_state(stub, data)
    assert slow == fast and reasons == []
    assert (slow.uav_id, slow.step, slow.sent_per_topic, slow.final, slow.state.x_m) == (
        3,
        9,
        (1, 0, 1),
        True,
        1.5,
    )
