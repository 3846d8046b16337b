"""``fire_uav_msgs/PayloadRequest`` read from its CDR bytes (the world reads each agent's request
once per step) and written as them (each agent writes one per step), on the rules of
:mod:`fire_uav_common.cdr`; checked against ``rclpy.serialization`` in
test_payload_request_codec.py. ROS-free.

Reading the bytes as they arrive raw skips rclpy's message object (a PayloadRequest, its Header
and Time), which cost the world about as much per step as its whole physics at 20 UAVs.
"""

from __future__ import annotations

import struct
from typing import NamedTuple

from ..cdr import ENCAPSULATION, CdrError, align4, align8, check_encapsulation, read_string_end

__all__ = ["PAYLOAD_REQUEST_FIELDS", "WirePayloadRequest", "read_payload_request", "write_payload_request"]

#: the message definition this reader expects (name, ROS type), in order
PAYLOAD_REQUEST_FIELDS = (
    ("header", "std_msgs/Header"), ("uav_id", "uint8"), ("action", "uint8"),
    ("target_fire_id", "int32"), ("cmd_linear_x_mps", "double"), ("cmd_linear_z_mps", "double"),
    ("cmd_angular_z_radps", "double"), ("auth", "uint8[32]"),
)  # fmt: skip

_STAMP = struct.Struct("<iI")  # builtin_interfaces/Time: sec, nanosec
_IDS = struct.Struct("<BB")  # uav_id, action
_I32 = struct.Struct("<i")
_CMD = struct.Struct("<3d")
_NS_PER_S = 1_000_000_000
_AUTH_BYTES = 32
#: a request with ``header.frame_id`` "map", as one record: the stamp, the frame id (its length with
#: the NUL), the ids, two bytes of padding to the int32, the int32 (ending 8-aligned), the command
_MAP_REQUEST = struct.Struct("<iII4sBB2xi3d")
_ZERO_AUTH = bytes(_AUTH_BYTES)


class WirePayloadRequest(NamedTuple):
    """The fields of one PayloadRequest the world uses; ``stamp_ns`` as ``stamps.stamp_to_ns``."""

    stamp_ns: int
    uav_id: int
    action: int
    target_fire_id: int
    cmd_linear_x_mps: float
    cmd_linear_z_mps: float
    cmd_angular_z_radps: float
    auth: bytes


def read_payload_request(data: bytes | bytearray | memoryview) -> WirePayloadRequest:
    """The CDR bytes of a PayloadRequest (as received raw) -> :class:`WirePayloadRequest`.

    Raises :class:`CdrError` naming what is wrong: another encapsulation, a frame_id past the
    end, or bytes that end before the auth field or run on after it (the world then asks rclpy,
    which decodes whatever else is a PayloadRequest).
    """
    n = len(data)
    check_encapsulation(data, "PayloadRequest")
    try:
        sec, nanosec = _STAMP.unpack_from(data, 4)
        i = read_string_end(data, 12, "PayloadRequest header.frame_id")
        uav_id, action = _IDS.unpack_from(data, i)
        i = align4(i + 2)
        (target,) = _I32.unpack_from(data, i)
        i = align8(i + 4)
        vx, vz, wz = _CMD.unpack_from(data, i)
        i += 24
    except struct.error as e:
        raise CdrError(f"PayloadRequest truncated at {n} bytes: {e}") from None
    end = i + _AUTH_BYTES
    if end != n:  # as rmw_fastrtps serialises it: the auth field ends the bytes (a multiple of 8 in)
        raise CdrError(
            f"PayloadRequest: expected its auth field to end at byte {end}, but the message has {n} bytes"
        )
    return WirePayloadRequest(
        sec * _NS_PER_S + nanosec, uav_id, action, target, vx, vz, wz, bytes(data[i:end])
    )


def write_payload_request(
    sec: int,
    nanosec: int,
    uav_id: int,
    action: int,
    target_fire_id: int,
    cmd_linear_x_mps: float,
    cmd_linear_z_mps: float,
    cmd_angular_z_radps: float,
) -> bytes:
    """A PayloadRequest stamped ``sec``/``nanosec`` in the frame ``map`` as CDR bytes, ``auth`` zero
    (to be signed: ``auth.Authenticator.sign_serialized``): the bytes ``serialize_message`` gives
    for the same message. A value out of its field's range raises :class:`CdrError`, as rclpy's
    setters raise for it."""
    try:
        body = _MAP_REQUEST.pack(
            sec, nanosec, 4, b"map\x00", uav_id, action, target_fire_id,
            cmd_linear_x_mps, cmd_linear_z_mps, cmd_angular_z_radps,
        )  # fmt: skip
    except struct.error as e:
        raise CdrError(f"PayloadRequest: a field out of its range: {e}") from None
    return ENCAPSULATION + body + _ZERO_AUTH
