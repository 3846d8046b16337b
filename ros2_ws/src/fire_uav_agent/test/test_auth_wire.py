"""Authentication on the real serialiser: the tag over the bytes as sent (auth.sign_serialized).

The CDR bytes of a message are not canonical: the serialiser leaves alignment padding
uninitialised, so two serialisations of equal messages can differ, and checking a tag on a
re-serialisation made every UavState fail (the fleet stalled at step 1). The fleet therefore tags
the bytes it sends and checks the bytes that arrive. These tests go through the real serialiser
with every signed type: each ends in its auth field at every alignment, a tag checks on its bytes
and on nothing else, and every byte, padding included, is covered.
"""

import math
import struct

import pytest
from fire_uav_common.auth import Authenticator
from fire_uav_msgs.msg import FireEstimate, FireEstimateArray, PayloadRequest, PerimeterMap, UavState
from rclpy.serialization import deserialize_message, serialize_message

KEY = bytes(range(32))


def _state() -> UavState:
    m = UavState(uav_id=1, sequence=5, step=4, objective=2, target_fire_id=-1, final=False)
    m.header.stamp.sec, m.header.stamp.nanosec = 0, 400_000_000
    m.header.frame_id = "map"
    m.x_m, m.y_m, m.z_m, m.yaw_rad = 101.25, -3.5, 40.0, 0.3
    m.covariance = [0.1 * i for i in range(16)]
    m.water_kg = 412.7  # a double in a float32 field: the wire rounds it
    m.centroid_x_m, m.centroid_y_m = math.pi, -math.e
    m.alive_peers, m.crashed_peers = [0, 1, 2], [3]
    m.packets_received, m.packets_lost, m.packets_rejected = 17, 2, 1
    m.sent_per_topic = [1, 1, 0, 0, 0, 0, 1]
    m.fires_sequence = 4  # the fire picture rides in the state: the tag covers it
    m.fires = [FireEstimate(fire_id=7, x_m=12.5, y_m=-0.25, extent_m=9.0, vy_mps=-0.5, front_y_m=math.nan)]
    return m


def _fires() -> FireEstimateArray:
    m = FireEstimateArray(uav_id=2, step=9)
    m.header.frame_id = "map"
    m.fires = [
        FireEstimate(
            fire_id=(2 << 16) | 1, x_m=300.5, y_m=280.25, extent_m=31.7, vx_mps=0.5, front_x_m=math.nan
        )
    ]
    return m


def _request() -> PayloadRequest:
    m = PayloadRequest(uav_id=0, action=1, target_fire_id=3)
    m.header.stamp.sec = 12
    m.cmd_linear_x_mps, m.cmd_linear_z_mps, m.cmd_angular_z_radps = 20.0, 0.1, -0.25
    return m


def _plain(v):
    """A message as nested Python values: floats by their bits, arrays as lists."""
    if hasattr(v, "get_fields_and_field_types"):
        return {k: _plain(getattr(v, k)) for k in v.get_fields_and_field_types() if k != "auth"}
    if isinstance(v, (str, bytes)):
        return v
    if hasattr(v, "__len__"):
        return [_plain(x) for x in v]
    if isinstance(v, float):
        return struct.pack(">d", v).hex()  # the bits: two NaNs of other payloads differ
    return v


def _equal_but_auth(a, b) -> bool:
    """Equal field values once both went over the wire (so a float32 holds its rounded value)."""
    a2, b2 = (
        deserialize_message(serialize_message(a), type(a)),
        deserialize_message(serialize_message(b), type(b)),
    )
    return _plain(a2) == _plain(b2)


def test_the_state_has_padding_bytes_and_the_tag_covers_them():
    """UavState is the type that stalled the fleet: it has alignment padding, which the serialiser
    leaves uninitialised. A flipped padding byte leaves every field as it was, yet the check
    fails: the tag covers the bytes as sent, so no re-serialisation may stand in for them."""
    auth = Authenticator(KEY)
    data = auth.sign_serialized(serialize_message(_state()), "/fleet/state", 1, 4)
    pads = 0
    for i in range(4, len(data) - 32):
        flipped = bytearray(data)
        flipped[i] ^= 0xFF
        try:
            got = deserialize_message(bytes(flipped), UavState)
        except Exception:  # a flipped length can make the bytes unreadable
            continue
        if _equal_but_auth(got, _state()):
            pads += 1
            assert not auth.check_serialized(bytes(flipped), "/fleet/state", 1, 4), i
    assert pads > 0


# --- the scheme the fleet uses: the tag over the serialised bytes as sent (sign_serialized) ----
def _perimeter(n: int) -> PerimeterMap:
    m = PerimeterMap(uav_id=3, sequence=n + 1, fire_id=2, direction=1, direction_changes=n)
    m.header.frame_id = "m" * n
    m.outer_distance_m = [1.5 * i for i in range(n)]
    m.importance = [0.25] * (n % 3)
    return m


def _varied(n: int) -> list:
    """Each signed type with n-dependent strings, sequences and nested lists (so every alignment
    of the trailing tag occurs): the tag must be the last 32 bytes of each."""
    s = _state()
    s.header.frame_id = "x" * n
    s.alive_peers = list(range(n))
    s.fires = [FireEstimate(fire_id=i, x_m=float(i)) for i in range(n % 4)]
    r = _request()
    r.header.frame_id = "y" * n
    f = _fires()
    f.fires = f.fires * (n % 3)
    return [s, r, f, _perimeter(n)]


@pytest.mark.parametrize("n", range(9))
def test_every_signed_type_ends_in_its_auth_field(n):
    """sign_serialized relies on it (and refuses bytes where it does not hold)."""
    for msg in _varied(n):
        assert list(msg.get_fields_and_field_types())[-1] == "auth", type(msg).__name__
        msg.auth = [0xA5] * 32
        assert serialize_message(msg)[-32:] == bytes([0xA5]) * 32, (type(msg).__name__, n)


@pytest.mark.parametrize("n", range(9))
def test_a_serialised_tag_checks_on_the_same_bytes_and_is_the_messages_auth(n):
    auth = Authenticator(KEY)
    for msg in _varied(n):
        data = auth.sign_serialized(serialize_message(msg), "/fleet/state", 4, 17 + n)
        assert auth.check_serialized(data, "/fleet/state", 4, 17 + n)
        got = deserialize_message(data, type(msg))
        assert bytes(bytearray(got.auth)) == data[-32:]  # the receiver's message carries the tag
        assert _equal_but_auth(got, msg)
        assert not auth.check_serialized(data, "/fleet/state", 5, 17 + n)  # another sender
        assert not auth.check_serialized(data, "/fleet/state", 4, 18 + n)  # another step
        assert not auth.check_serialized(data, "/fleet/perimeter", 4, 17 + n)  # another topic
        assert not Authenticator(bytes(32)).check_serialized(data, "/fleet/state", 4, 17 + n)  # another key


def test_every_byte_of_the_serialised_form_is_covered_padding_and_header_included():
    """Unlike the canonical tag, nothing is exempt: the receiver hashes what arrived, so a flipped
    padding byte is a changed message (a rogue cannot smuggle bits through the padding)."""
    auth = Authenticator(KEY)
    data = auth.sign_serialized(serialize_message(_state()), "/fleet/state", 1, 4)
    for i in range(len(data)):
        flipped = bytearray(data)
        flipped[i] ^= 0x01
        assert not auth.check_serialized(bytes(flipped), "/fleet/state", 1, 4), i
    assert not auth.check_serialized(data + b"\x00", "/fleet/state", 1, 4)  # appended
    assert not auth.check_serialized(data[:-1], "/fleet/state", 1, 4)  # truncated


def test_signing_refuses_bytes_whose_tail_is_not_a_zero_auth_field():
    auth = Authenticator(KEY)
    msg = _state()
    msg.auth = [1] * 32  # signed twice, or a type whose auth is not last
    with pytest.raises(ValueError, match="last 32 bytes are not a zero auth field"):
        auth.sign_serialized(serialize_message(msg), "/fleet/state", 1, 4)
    with pytest.raises(ValueError, match="expected the CDR bytes of a message"):
        auth.sign_serialized(b"\x00\x01\x00\x00", "/fleet/state", 1, 4)
    with pytest.raises(ValueError, match="expected the CDR bytes of a message"):
        auth.sign_serialized(bytearray(64), "/fleet/state", 1, 4)  # type: ignore[arg-type]
    for bad in [b"", b"\x00" * 35, None, 42, "text"]:
        assert not auth.check_serialized(bad, "/fleet/state", 1, 4)  # type: ignore[arg-type]
