"""A peer's ``UavState`` read straight from its CDR bytes into the agent's ROS-free types.

Why: an agent receives 19 states a step at 20 UAVs. ``rclpy.serialization.deserialize_message``
builds a Python ``UavState`` for each (its ``__init__`` first fills every field and sub-message
with defaults, which the C conversion then replaces), and the node then copied the fields it uses
into :class:`PeerState` and :class:`PeerFires`. Reading those fields from the bytes with
``struct`` skips both (docs/profile.md, session 13). It is the same information: every decoded
field is compared against ``deserialize_message`` on generated messages (test_state_wire.py), and
the field list of ``UavState.msg`` / ``FireEstimate.msg`` is pinned there, so a change to the
message fails that test instead of being misread here.

The encoding read is the one the fleet sends: XCDR1 little-endian, as rmw_fastrtps serialises
ROS 2 messages (its layout rules: ``fire_uav_common.cdr``). Anything else (another encapsulation,
bytes that do not end exactly with the 32-byte ``auth`` field) raises :class:`ValueError`, and
the node then falls back to ``deserialize_message`` (any encoding rclpy reads) or counts the
bytes as undecodable. The reader is more lenient than rclpy in one way: it does not decode
``header.frame_id``, so it does not refuse one that is not UTF-8 (the agent never reads it, and a
signed state's bytes are covered by its tag).

ROS-free: bytes in, :mod:`peer_link` types out.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from fire_uav_common.cdr import U32, align4, align8, check_encapsulation, read_string_end

from .errors import WireError
from .peer_link import FireEntry, PeerFires, PeerState

__all__ = ["WireState", "UAVSTATE_FIELDS", "FIREESTIMATE_FIELDS", "read_uav_state"]

#: UavState.msg and FireEstimate.msg as this reader expects them (name, ROS type), in order
UAVSTATE_FIELDS = (
    ("header", "std_msgs/Header"), ("uav_id", "uint8"), ("sequence", "uint32"), ("step", "uint32"),
    ("x_m", "double"), ("y_m", "double"), ("z_m", "double"), ("yaw_rad", "double"),
    ("covariance", "double[16]"), ("objective", "uint8"), ("target_fire_id", "int32"),
    ("water_kg", "float"), ("centroid_x_m", "double"), ("centroid_y_m", "double"),
    ("alive_peers", "sequence<uint8>"), ("crashed_peers", "sequence<uint8>"),
    ("packets_received", "uint32"), ("packets_lost", "uint32"), ("packets_rejected", "uint32"),
    ("sent_per_topic", "sequence<uint16>"), ("final", "boolean"), ("fires_sequence", "uint32"),
    ("fires", "sequence<fire_uav_msgs/FireEstimate>"), ("auth", "uint8[32]"),
)  # fmt: skip
FIREESTIMATE_FIELDS = (
    ("fire_id", "uint32"), ("status", "uint8"), ("x_m", "double"), ("y_m", "double"),
    ("extent_m", "double"), ("vx_mps", "double"), ("vy_mps", "double"),
    ("last_measurement", "builtin_interfaces/Time"), ("front_x_m", "double"),
    ("front_y_m", "double"), ("max_spread_rate_mps", "double"),
)  # fmt: skip

_STATUS_ACTIVE = 0  # FireEstimate.STATUS_ACTIVE
_AUTH_BYTES = 32
_NS_PER_S = 1_000_000_000
_IDS = struct.Struct("<II")  # sequence, step
_POSE = struct.Struct("<4d")  # x, y, z, yaw; the 16 covariance doubles follow (not read)
_OBJECTIVE_TAIL = struct.Struct("<if")  # target_fire_id, water_kg
_CENTROID = struct.Struct("<2d")
_COUNTERS = struct.Struct("<3I")  # packets received, lost, rejected (not read: the peer's own)
_FIRE_HEAD = struct.Struct("<IB")  # fire_id, status
# x, y, extent, vx, vy, last_measurement (sec, nanosec), front x, y, max spread rate
_FIRE_BODY = struct.Struct("<5diI3d")
_FIRE_MIN_BYTES = _FIRE_HEAD.size + _FIRE_BODY.size  # a FireEstimate without its alignment padding


@dataclass(frozen=True, slots=True)
class WireState:
    """What an agent takes from a peer's UavState: the lockstep fields and the two inbox items."""

    uav_id: int
    step: int
    sent_per_topic: tuple[int, ...]
    final: bool
    state: PeerState
    fires: PeerFires


def read_uav_state(data: bytes | bytearray | memoryview) -> WireState:
    """A serialised ``fire_uav_msgs/UavState`` (as received raw) -> :class:`WireState`.

    Raises ValueError naming what is wrong: not XCDR1 little-endian, truncated, a length that
    runs past the end, or bytes left after the ``auth`` field. The values are the message's, as
    ``deserialize_message`` would give them (``water_kg`` is the float32 widened exactly; the fire's
    ``last_measurement`` is seconds as ``stamps.stamp_to_s`` computes them).
    """
    n = len(data)
    check_encapsulation(data, "UavState")
    try:
        i = read_string_end(data, 12, "UavState header.frame_id")  # after the stamp (sec, nanosec)
        uav_id = data[i]
        i = align4(i + 1)
        sequence, step = _IDS.unpack_from(data, i)
        i = align8(i + 8)
        x, y, z, yaw = _POSE.unpack_from(data, i)
        i += 20 * 8  # the pose and the 4x4 covariance
        objective = data[i]
        i = align4(i + 1)
        target, water = _OBJECTIVE_TAIL.unpack_from(data, i)
        i = align8(i + 8)
        cx, cy = _CENTROID.unpack_from(data, i)
        i += 16
        for _ in range(2):  # alive_peers, crashed_peers: uint8[] (not read: the peer's own view)
            (k,) = U32.unpack_from(data, i)
            i += 4 + k
            i = align4(i)
        i += _COUNTERS.size
        (k,) = U32.unpack_from(data, i)
        i += 4
        if i + 2 * k > n:
            raise WireError(f"sent_per_topic length {k} runs past the end of {n} bytes")
        sent = struct.unpack_from(f"<{k}H", data, i)
        i += 2 * k
        final = data[i]
        i = align4(i + 1)
        fires_sequence, k = _IDS.unpack_from(data, i)
        i += 8
        if i + _FIRE_MIN_BYTES * k > n:
            raise WireError(f"fires length {k} runs past the end of {n} bytes")
        fires = []
        for _ in range(k):
            i = align4(i)
            fire_id, status = _FIRE_HEAD.unpack_from(data, i)
            i = align8(i + 5)
            fx, fy, ext, vx, vy, t_sec, t_nsec, frx, fry, rate = _FIRE_BODY.unpack_from(data, i)
            i += _FIRE_BODY.size
            t_s = (t_sec * _NS_PER_S + t_nsec) / _NS_PER_S
            fires.append(
                FireEntry(fire_id, status == _STATUS_ACTIVE, fx, fy, ext, vx, vy, t_s, frx, fry, rate)
            )
    except (struct.error, IndexError):
        raise WireError(f"UavState truncated: {n} bytes") from None
    if i + _AUTH_BYTES != n:
        raise WireError(
            f"UavState of {n} bytes: expected its auth field to end at byte {n}, not {i + _AUTH_BYTES}"
        )
    state = PeerState(uav_id, sequence, step, x, y, z, yaw, objective, target, water, cx, cy)
    return WireState(
        uav_id, step, sent, bool(final), state, PeerFires(uav_id, fires_sequence, step, tuple(fires))
    )
