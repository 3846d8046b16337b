"""Raw subscriptions (signed topics, docs/security.md): bytes that are no message of the topic's
type are a counted rejection, not an exception. The agent's ``_decode`` and ``_read`` on a
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


def _readers():
    from fire_uav_common.codecs.fire_front import read_fire_front
    from fire_uav_common.codecs.perimeter_map import read_perimeter_map
    from fire_uav_common.codecs.uav_state import read_uav_state
    from fire_uav_msgs.msg import FireFront, PerimeterMap

    state = UavState(uav_id=3, step=9, sequence=4, x_m=1.5, fires_sequence=2, final=True)
    state.sent_per_topic = [1, 0, 1]
    pm = PerimeterMap(uav_id=3, sequence=4, fire_id=2, center_x_m=1.5)
    pm.outer_distance_m = [10.0, 12.5]
    ff = FireFront(uav_id=3, sequence=4, cell_size_m=5.0)
    ff.x_m, ff.y_m, ff.state, ff.observed_s, ff.spread_rate_mps = [1.5], [2.5], b"\x02", [8.25], [0.5]
    return [
        (read_uav_state, UavState, topics.FLEET_STATE_SPEC, state),
        (read_perimeter_map, PerimeterMap, topics.FLEET_PERIMETER_SPEC, pm),
        (read_fire_front, FireFront, topics.FLEET_FRONT_SPEC, ff),
    ]


@pytest.mark.parametrize("reader", _readers(), ids=lambda r: r[1].__name__)
@pytest.mark.parametrize("data", GARBAGE)
def test_a_peer_message_that_neither_reader_takes_is_counted_once(data, reader):
    read, msg_type, spec, _ = reader
    stub, reasons, log = _reading_stub()
    assert UavAgentNode._read(stub, data, read, msg_type, spec) is None
    assert reasons == ["undecodable"] and len(log.lines) == 1
    assert f"on {spec.name} that are no {msg_type.__name__}" in log.lines[0]


@pytest.mark.parametrize("reader", _readers(), ids=lambda r: r[1].__name__)
def test_a_message_the_codec_refuses_still_reads_through_rclpy(reader):
    """Another encoding than XCDR1 little-endian (e.g. a big-endian peer) is read by rclpy's
    deserialisation and re-serialised for the codec, to the same values."""
    from fire_uav_agent.testing.compare import same

    read, msg_type, spec, m = reader
    data = serialize_message(m)
    stub, reasons, _ = _reading_stub()
    fast = UavAgentNode._read(stub, data, read, msg_type, spec)

    def refuse(d):  # the bytes as received are refused; rclpy's re-serialisation of them is read
        if d is data:
            raise CdrError(f"{msg_type.__name__}: not XCDR1 little-endian CDR (encapsulation 0000)")
        return read(d)

    slow = UavAgentNode._read(stub, data, refuse, msg_type, spec)
    assert same(slow, fast) and reasons == []
    assert (slow.uav_id, slow.sequence if hasattr(slow, "sequence") else slow.state.sequence) == (3, 4)


def test_a_front_whose_arrays_differ_in_length_is_counted_and_still_arrives_for_the_lockstep():
    """A FireFront that decodes but whose cell arrays differ in length: its content dropped and
    counted (``malformed front``), the message still handed to the gate (its sender sent it: the
    lockstep wait counts it)."""
    from fire_uav_common.codecs.fire_front import read_fire_front
    from fire_uav_msgs.msg import FireFront

    ff = FireFront(uav_id=3, sequence=4, cell_size_m=5.0)
    ff.x_m, ff.y_m, ff.state, ff.observed_s, ff.spread_rate_mps = [1.5, 2.5], [2.5], b"\x02", [8.25], [0.5]
    handed: list[tuple] = []
    stub, reasons, log = _reading_stub()
    stub.cfg = types.SimpleNamespace(uav_id=0, control_period_s=0.1)
    stub._read = lambda data, reader, *a: reader(data)
    stub.gate = types.SimpleNamespace(
        on_front=lambda sender, step, front: handed.append((sender, front)) or []
    )
    stub._act = lambda decisions: None
    UavAgentNode._on_front(stub, serialize_message(ff))
    assert reasons == ["malformed front"]
    assert handed == [(3, None)]
    assert "FireFront from uav 3 dropped" in log.lines[0]
    assert read_fire_front(serialize_message(ff)).uav_id == 3
