"""``fire_uav_common.codecs.agent_pose`` against rclpy's serialisation of the messages the agent
built before (its command on ``/uav_<k>/cmd`` and its pose estimate on ``/tf``): the bytes must be
equal, for every value (NaN and infinities included) and frame ids of every length mod 8, so that
each alignment rule is hit, except the alignment padding, which ``serialize_message`` leaves
uninitialised (seen: ``f0 12 00 0a`` where the writer puts zeros) and which no reader reads. The
field lists are pinned, so a message change fails here first."""

from __future__ import annotations

import pytest

pytest.importorskip("geometry_msgs.msg")

from builtin_interfaces.msg import Time
from fire_uav_common.cdr import CdrError, align4, align8
from fire_uav_common.codecs.agent_pose import (
    TF_MESSAGE_FIELDS,
    TWIST_STAMPED_FIELDS,
    write_tf_one,
    write_twist_stamped,
)
from geometry_msgs.msg import TransformStamped, TwistStamped
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import serialize_message
from tf2_msgs.msg import TFMessage

f64 = st.floats(allow_nan=True, allow_infinity=True)
i32 = st.integers(-(2**31), 2**31 - 1)
u32 = st.integers(0, 2**32 - 1)
frames = st.text(st.characters(codec="ascii", exclude_characters="\x00"), max_size=19)


def _blank(data: bytes, *spans: tuple[int, int]) -> bytes:
    """``data`` with the byte ranges ``spans`` (alignment padding) zeroed."""
    out = bytearray(data)
    for a, b in spans:
        out[a:b] = bytes(b - a)
    return bytes(out)


def _string_end(start: int, text: str) -> int:
    return start + 4 + len(text.encode()) + 1


def test_field_lists_are_the_messages() -> None:
    assert tuple(TwistStamped.get_fields_and_field_types().items()) == TWIST_STAMPED_FIELDS
    assert tuple(TFMessage.get_fields_and_field_types().items()) == TF_MESSAGE_FIELDS
    assert tuple(TransformStamped.get_fields_and_field_types().items()) == (
        ("header", "std_msgs/Header"),
        ("child_frame_id", "string"),
        ("transform", "geometry_msgs/Transform"),
    )


@settings(max_examples=300, deadline=None)
@given(i32, u32, frames, f64, f64, f64)
def test_twist_stamped_is_rclpys_bytes(sec, nanosec, frame, vx, vz, wz) -> None:
    ref = TwistStamped()  # as agent_node built it before
    ref.header.stamp = Time(sec=sec, nanosec=nanosec)
    ref.header.frame_id = frame
    ref.twist.linear.x, ref.twist.linear.z, ref.twist.angular.z = vx, vz, wz
    got = write_twist_stamped(sec, nanosec, frame, vx, vz, wz)
    end = _string_end(12, frame)  # after the stamp
    assert got == _blank(bytes(serialize_message(ref)), (end, align8(end)))


@settings(max_examples=300, deadline=None)
@given(i32, u32, frames, frames, st.tuples(f64, f64, f64), f64, f64)
def test_tf_one_is_rclpys_bytes(sec, nanosec, frame, child, xyz, qz, qw) -> None:
    t = TransformStamped()  # as agent_io.tf_estimate_msg built it before
    t.header.stamp, t.header.frame_id = Time(sec=sec, nanosec=nanosec), frame
    t.child_frame_id = child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = xyz
    t.transform.rotation.z, t.transform.rotation.w = qz, qw
    ref = TFMessage(transforms=[t])
    got = write_tf_one(sec, nanosec, frame, child, xyz, (0.0, 0.0, qz, qw))
    e1 = _string_end(16, frame)  # after the sequence length and the stamp
    e2 = _string_end(align4(e1), child)
    assert got == _blank(bytes(serialize_message(ref)), (e1, align4(e1)), (e2, align8(e2)))


@pytest.mark.parametrize(
    "call",
    [
        lambda: write_twist_stamped(2**31, 0, "uav_0", 0.0, 0.0, 0.0),
        lambda: write_twist_stamped(0, -1, "uav_0", 0.0, 0.0, 0.0),
        lambda: write_twist_stamped(0, 0, "a\x00b", 0.0, 0.0, 0.0),
        lambda: write_tf_one(0, 0, "map", "x\x00", (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
    ],
)
def test_out_of_range_refused(call) -> None:
    with pytest.raises(CdrError):
        call()
