"""``ros_messages.truth_bytes`` (what the node publishes on /world/truth) against
``serialize_message(truth_msg(r))`` (what it published before): as long, and read back by rclpy as
the same message field for field (floats bit for bit), so a recorded mission's truth is unchanged.
Only the alignment padding may differ: rclpy leaves whatever was in its buffer there (seen: bytes
of a type name), the writer writes zeros. Generated step results: any number of vehicles and fires
(so every alignment case of the two sequences occurs), values over their fields' ranges, NaN and
infinities included; and the step results of a real world."""

from __future__ import annotations

import struct

import pytest

pytest.importorskip("fire_uav_msgs.msg")

from fire_uav_msgs.msg import WorldTruth
from fire_world_sim import ros_messages
from fire_world_sim.fires import FireTruthRecord
from fire_world_sim.vehicle import Command
from fire_world_sim.world import StepResult, VehicleTruthRecord, World
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import deserialize_message, serialize_message

f64 = st.floats(allow_nan=True, allow_infinity=True)
f32 = st.floats(width=32, allow_nan=True, allow_infinity=True)
u8, u32 = st.integers(0, 255), st.integers(0, 2**32 - 1)
ns = st.integers(0, 2**31 * 10**9 - 1)


@st.composite
def step_results(draw) -> StepResult:
    vehicles = [
        VehicleTruthRecord(
            draw(u8), draw(u8), *(draw(f64) for _ in range(7)), draw(f32), draw(u32), draw(u32)
        )
        for _ in range(draw(st.integers(0, 5)))
    ]
    fires = [_fire(draw) for _ in range(draw(st.integers(0, 4)))]
    return StepResult(
        step=draw(u32), stamp_ns=draw(ns), bundles={}, vehicles=vehicles, fires=fires, events=[],
        min_separation_m=draw(f64), collisions=draw(u32),
    )  # fmt: skip


def _fire(draw) -> FireTruthRecord:
    return FireTruthRecord(
        fire_id=draw(u8), status=draw(u8), x_m=draw(f64), y_m=draw(f64), extent_m=draw(f64),
        area_m2=draw(f64), drops_received=draw(u32),
    )  # fmt: skip


def _flat(m: WorldTruth) -> tuple:
    """Every field of ``m``, floats as their float64 bits (NaN equal to NaN)."""

    def v(x):
        return struct.pack("<d", x) if isinstance(x, float) else x

    def fields(o):
        return tuple(v(getattr(o, f)) for f in o.get_fields_and_field_types() if f != "header")

    return (
        m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id,
        fields(m)[:3], tuple(fields(x) for x in m.vehicles), tuple(fields(x) for x in m.fires),
    )  # fmt: skip


def _same(r: StepResult) -> None:
    data = ros_messages.truth_bytes(r)
    ref = serialize_message(ros_messages.truth_msg(r))
    assert len(data) == len(ref)
    assert _flat(deserialize_message(data, WorldTruth)) == _flat(deserialize_message(ref, WorldTruth))
    assert _flat(deserialize_message(data, WorldTruth)) == _flat(ros_messages.truth_msg(r))
    assert ros_messages.truth_bytes(r) == data  # zeros in the padding: the same bytes every time


@settings(max_examples=300, deadline=None)
@given(step_results())
def test_the_bytes_are_the_message_rclpy_serialises(r):
    _same(r)


def test_a_real_worlds_steps_give_the_same_bytes(tiny):
    w = World(tiny, seed=4)
    for k in range(60):
        r = w.step({i: Command(50.0, 3.0 if k < 30 else 0.0, 0.3) for i in range(w.uav_count)})
        assert r.vehicles
        _same(r)
