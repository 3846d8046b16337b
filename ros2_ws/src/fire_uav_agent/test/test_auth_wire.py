"""Authentication survives the wire: a tag made on the sender's message checks on what arrives.

The CDR bytes of a message are not canonical: the serialiser leaves alignment padding
uninitialised, so two serialisations of equal messages can differ. Signing them made every
UavState fail its check (the fleet stalled at step 1). These tests go through the real
serialiser: a tag checks after a round trip, whatever the padding bytes hold, and fails when any
byte that carries a field changes.
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


CASES = [
    (_state, "/fleet/state", 1, 4),
    (_fires, "/fleet/fires", 2, 9),
    (_request, "/uav_0/payload", 0, 12 * 10**9),
]


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


@pytest.mark.parametrize("make,topic,sender,step", CASES, ids=[c[1] for c in CASES])
def test_tag_checks_after_the_wire_and_any_field_byte_breaks_it(make, topic, sender, step):
    auth = Authenticator(KEY)
    msg = make()
    auth.sign(msg, topic, sender, step)
    wire = bytearray(serialize_message(msg))
    assert auth.check(deserialize_message(bytes(wire), type(msg)), topic, sender, step)
    padding = carrying = 0
    for i in range(4, len(wire)):  # past the 4-byte CDR encapsulation header
        flipped = bytearray(wire)
        flipped[i] ^= 0x5A
        try:
            got = deserialize_message(bytes(flipped), type(msg))
        except Exception:  # a flipped length can make the bytes unreadable: nothing to check
            continue
        if _equal_but_auth(got, msg) and list(got.auth) == list(msg.auth):
            padding += 1  # a padding byte: must not matter
            assert auth.check(got, topic, sender, step), f"byte {i} (padding) broke the tag"
        else:
            carrying += 1
            assert not auth.check(got, topic, sender, step), f"byte {i} changed a field yet the tag checks"
    assert carrying > 0


def test_the_state_has_padding_bytes_the_tag_ignores():
    """UavState is the type that stalled the fleet: it does have alignment padding."""
    wire = serialize_message(_state())
    pads = 0
    for i in range(4, len(wire)):
        flipped = bytearray(wire)
        flipped[i] ^= 0xFF
        try:
            got = deserialize_message(bytes(flipped), UavState)
        except Exception:
            continue
        pads += _equal_but_auth(got, _state())
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


def test_the_two_schemes_never_accept_each_others_tags():
    auth = Authenticator(KEY)
    msg = _state()
    wire = auth.sign_serialized(serialize_message(msg), "/fleet/state", 1, 4)
    got = deserialize_message(wire, UavState)
    assert not auth.check(got, "/fleet/state", 1, 4)  # a serialised tag is no canonical one
    auth.sign(msg, "/fleet/state", 1, 4)
    assert not auth.check_serialized(serialize_message(msg), "/fleet/state", 1, 4)


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
