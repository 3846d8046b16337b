"""``fire_uav_common.codecs.payload_request.read_payload_request`` against rclpy's own
deserialisation (the reference it replaces in the world's ``_on_payload``).

Generated PayloadRequests (every field random, frame ids of every length mod 8 so that each
alignment rule is exercised) are serialised by ``rclpy.serialization.serialize_message``
(rmw_fastrtps's CDR) and read both ways; the fields must be equal, bit for bit. The field list of
PayloadRequest.msg is pinned, so a message change fails here first. Bad bytes raise CdrError
(a ValueError) and nothing else, and the world's reader falls back to rclpy for them.
"""

from __future__ import annotations

import math
import struct

import pytest

pytest.importorskip("fire_uav_msgs.msg")

from builtin_interfaces.msg import Time
from fire_uav_common.auth import Authenticator
from fire_uav_common.cdr import CdrError
from fire_uav_common.codecs.payload_request import (
    PAYLOAD_REQUEST_FIELDS,
    read_payload_request,
    write_payload_request,
)
from fire_uav_common.stamps import stamp_to_ns
from fire_uav_msgs.msg import PayloadRequest
from fire_world_sim.world_node import _read_payload
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import deserialize_message, serialize_message

f64 = st.floats(allow_nan=True, allow_infinity=True)
u8 = st.integers(0, 255)
i32 = st.integers(-(2**31), 2**31 - 1)
stamps = st.builds(Time, sec=i32, nanosec=st.integers(0, 999_999_999))


@st.composite
def requests(draw) -> PayloadRequest:
    m = PayloadRequest(uav_id=draw(u8), action=draw(u8), target_fire_id=draw(i32))
    m.header.stamp = draw(stamps)
    m.header.frame_id = draw(st.text(st.characters(codec="ascii", exclude_characters="\x00"), max_size=17))
    m.cmd_linear_x_mps, m.cmd_linear_z_mps, m.cmd_angular_z_radps = draw(f64), draw(f64), draw(f64)
    m.auth = list(draw(st.binary(min_size=32, max_size=32)))
    return m


def _bits(x: float) -> bytes:
    return struct.pack("<d", x)  # NaNs compared by their bits


def _fields(ref: PayloadRequest) -> tuple:
    return (
        stamp_to_ns(ref.header.stamp),
        ref.uav_id,
        ref.action,
        ref.target_fire_id,
        _bits(ref.cmd_linear_x_mps),
        _bits(ref.cmd_linear_z_mps),
        _bits(ref.cmd_angular_z_radps),
        bytes(bytearray(ref.auth)),
    )


def _read_fields(w) -> tuple:
    return (w.stamp_ns, w.uav_id, w.action, w.target_fire_id, _bits(w.cmd_linear_x_mps),
            _bits(w.cmd_linear_z_mps), _bits(w.cmd_angular_z_radps), w.auth)  # fmt: skip


def test_the_message_definition_is_the_one_the_reader_reads():
    assert tuple(PayloadRequest.get_fields_and_field_types().items()) == PAYLOAD_REQUEST_FIELDS


@settings(max_examples=300, deadline=None)
@given(requests())
def test_read_equals_rclpys_deserialisation(m):
    data = serialize_message(m)
    assert _read_fields(read_payload_request(data)) == _fields(deserialize_message(data, PayloadRequest))


@settings(max_examples=60, deadline=None)
@given(requests(), u8, st.integers(0, 2**62))
def test_a_signed_request_reads_its_tag_as_the_check_sees_it(m, sender, step):
    m.auth = [0] * 32
    auth = Authenticator(bytes(range(32)))
    data = auth.sign_serialized(serialize_message(m), "/uav_1/payload", sender, step)
    w = read_payload_request(data)
    assert w.auth == data[-32:] != bytes(32)
    assert auth.check_serialized(data, "/uav_1/payload", sender, step)


def test_values_come_through_exactly():
    m = PayloadRequest(uav_id=7, action=PayloadRequest.ACTION_REFILL, target_fire_id=-1)
    m.header.stamp, m.header.frame_id = Time(sec=12, nanosec=300_000_000), "map"
    m.cmd_linear_x_mps, m.cmd_linear_z_mps, m.cmd_angular_z_radps = 12.5, -math.inf, 0.25
    w = read_payload_request(serialize_message(m))
    assert (w.stamp_ns, w.uav_id, w.action, w.target_fire_id) == (12_300_000_000, 7, 2, -1)
    assert (w.cmd_linear_x_mps, w.cmd_linear_z_mps, w.cmd_angular_z_radps) == (12.5, -math.inf, 0.25)


def test_every_truncation_and_a_trailing_byte_are_cdr_errors():
    data = serialize_message(PayloadRequest(uav_id=2))
    for n in range(len(data)):
        with pytest.raises(CdrError, match="PayloadRequest|CDR|length"):
            read_payload_request(data[:n])
    with pytest.raises(CdrError, match="expected its auth field to end"):
        read_payload_request(data + b"\x00")


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=200), st.booleans())
def test_noise_is_a_cdr_error_or_a_request(noise, with_header):
    try:
        read_payload_request((b"\x00\x01\x00\x00" + noise) if with_header else noise)
    except CdrError:
        pass


def test_the_world_takes_what_rclpy_takes_when_the_codec_refuses():
    """Bytes the codec refuses but rclpy decodes (one byte too many) give the same request."""
    m = PayloadRequest(uav_id=3, action=1, target_fire_id=4)
    m.header.stamp = Time(sec=1, nanosec=5)
    data = serialize_message(m) + b"\x00"
    with pytest.raises(CdrError):
        read_payload_request(data)
    try:
        ref = deserialize_message(data, PayloadRequest)
    except RuntimeError:
        assert _read_payload(data) is None
        return
    assert _read_fields(_read_payload(data)) == _fields(ref)


@settings(max_examples=300, deadline=None)
@given(stamps, u8, u8, i32, f64, f64, f64)
def test_writer_gives_the_bytes_rclpy_serialises(stamp, uav_id, action, target, vx, vz, wz) -> None:
    """The agent's request written by the codec is byte for byte rclpy's serialisation of the
    message the agent built before (frame ``map``, ``auth`` zero), NaNs and infinities included,
    but for the two bytes of alignment padding, which ``serialize_message`` leaves uninitialised
    (the writer puts zeros; no reader reads them)."""
    ref = PayloadRequest(uav_id=uav_id, action=action, target_fire_id=target)
    ref.header.stamp = stamp
    ref.header.frame_id = "map"
    ref.cmd_linear_x_mps, ref.cmd_linear_z_mps, ref.cmd_angular_z_radps = vx, vz, wz
    got = write_payload_request(stamp.sec, stamp.nanosec, uav_id, action, target, vx, vz, wz)
    want = bytearray(serialize_message(ref))
    want[22:24] = b"\x00\x00"  # the padding before target_fire_id, which rclpy leaves unset
    assert got == bytes(want)


@pytest.mark.parametrize(
    "args",
    [
        (0, 0, 256, 0, -1),  # uav_id beyond uint8
        (0, 0, 1, -1, -1),  # negative action
        (0, 0, 1, 0, 2**31),  # fire id beyond int32
        (-(2**31) - 1, 0, 1, 0, -1),  # sec beyond int32
        (0, 2**32, 1, 0, -1),  # nanosec beyond uint32
    ],
)
def test_writer_refuses_values_out_of_range(args) -> None:
    with pytest.raises(CdrError):
        write_payload_request(*args, 0.0, 0.0, 0.0)
