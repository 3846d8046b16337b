"""The two small messages an agent publishes every step besides its fleet messages, written as CDR
bytes: its command as ``geometry_msgs/TwistStamped`` (``/uav_<k>/cmd``) and its pose estimate as a
``tf2_msgs/TFMessage`` of one transform (``/tf``), on the rules of :mod:`fire_uav_common.cdr`.
Checked byte for byte against ``rclpy.serialization.serialize_message`` of the messages the agent
built before (fire_uav_agent's test_agent_pose_codec.py). ROS-free.

Building them as rclpy messages cost an agent a Header, a Time and their sub-messages per step,
then rclpy's C conversion at the publish; the bytes are published raw and read as the same
messages by every subscriber.
"""

from __future__ import annotations

import struct

from ..cdr import ENCAPSULATION, U32, CdrError, pad

__all__ = ["TF_MESSAGE_FIELDS", "TWIST_STAMPED_FIELDS", "write_tf_one", "write_twist_stamped"]

#: the message definitions these writers follow (name, ROS type), in order
TWIST_STAMPED_FIELDS = (("header", "std_msgs/Header"), ("twist", "geometry_msgs/Twist"))
TF_MESSAGE_FIELDS = (("transforms", "sequence<geometry_msgs/TransformStamped>"),)

_STAMP = struct.Struct("<iI")  # builtin_interfaces/Time: sec, nanosec
_SIX = struct.Struct("<6d")  # Twist: linear x, y, z, angular x, y, z
_SEVEN = struct.Struct("<7d")  # Transform: translation x, y, z, rotation x, y, z, w


def _string(buf: bytearray, text: str) -> None:
    raw = text.encode("utf-8")
    if b"\x00" in raw:
        raise CdrError(f"a CDR string cannot hold a NUL: {text!r}")
    pad(buf, 4)  # its length is a uint32
    buf += U32.pack(len(raw) + 1)
    buf += raw
    buf += b"\x00"


def _header(buf: bytearray, sec: int, nanosec: int, frame_id: str) -> None:
    try:
        buf += _STAMP.pack(sec, nanosec)
    except struct.error as e:
        raise CdrError(f"stamp out of range: {e}") from None
    _string(buf, frame_id)


def write_twist_stamped(
    sec: int, nanosec: int, frame_id: str, linear_x: float, linear_z: float, angular_z: float
) -> bytes:
    """A TwistStamped with only ``linear.x``, ``linear.z`` and ``angular.z`` set (the agent's
    command: forward speed [m/s], climb rate [m/s], yaw rate [rad/s]) as CDR bytes."""
    buf = bytearray(ENCAPSULATION)
    _header(buf, sec, nanosec, frame_id)
    pad(buf, 8)
    buf += _SIX.pack(linear_x, 0.0, linear_z, 0.0, 0.0, angular_z)
    return bytes(buf)


def write_tf_one(
    sec: int,
    nanosec: int,
    frame_id: str,
    child_frame_id: str,
    translation: tuple[float, float, float],
    rotation_xyzw: tuple[float, float, float, float],
) -> bytes:
    """A TFMessage holding one TransformStamped (``frame_id`` -> ``child_frame_id``) as CDR bytes."""
    buf = bytearray(ENCAPSULATION)
    buf += U32.pack(1)
    _header(buf, sec, nanosec, frame_id)
    _string(buf, child_frame_id)
    pad(buf, 8)
    buf += _SEVEN.pack(*translation, *rotation_xyzw)
    return bytes(buf)
