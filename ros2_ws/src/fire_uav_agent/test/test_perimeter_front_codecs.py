"""The PerimeterMap and FireFront codecs against rclpy (the reference they replace).

Generated messages (every field random, frame ids of every length mod 8 so that each alignment
rule is exercised) are serialised by ``rclpy.serialization.serialize_message`` (rmw_fastrtps's
CDR): the codec reads the values ``deserialize_message`` gives, and writes bytes of the same
length that rclpy reads as the same message (rclpy's padding bytes are whatever its buffer held,
so they are not compared; the writer's are zeros). On the agent's side, ``outgoing.perimeter_bytes``
/ ``front_bytes`` are the messages the node built before the codecs (``rclpy_reference``), and
``incoming`` reads them as the node did. The field lists of both messages are pinned, so a message change fails here first.
Bad bytes (every truncation, bytes left over, another encapsulation) raise ValueError naming the
message.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

pytest.importorskip("fire_uav_msgs.msg")

from builtin_interfaces.msg import Time
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.incoming import peer_front, peer_perimeter
from fire_uav_agent.outgoing import front_bytes, perimeter_bytes
from fire_uav_agent.testing import rclpy_reference as rclpy_ref
from fire_uav_agent.testing.compare import assert_same_message, same
from fire_uav_agent.testing.msg_strategies import f32, f64, frame_ids, i32, u8, u32
from fire_uav_common.auth import Authenticator
from fire_uav_common.codecs.fire_front import FIREFRONT_FIELDS, read_fire_front, write_fire_front
from fire_uav_common.codecs.perimeter_map import (
    PERIMETERMAP_FIELDS,
    read_perimeter_map,
    write_perimeter_map,
)
from fire_uav_common.stamps import stamp_to_ns, step_to_ns, to_time_msg
from fire_uav_msgs.msg import FireFront, PerimeterMap
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import deserialize_message, serialize_message

stamps = st.builds(Time, sec=st.integers(0, 2**31 - 1), nanosec=st.integers(0, 999_999_999))
frame_id = frame_ids(17)
f32_lists = st.lists(f32, max_size=40)


@st.composite
def perimeter_maps(draw) -> PerimeterMap:
    m = PerimeterMap(uav_id=draw(u8), sequence=draw(u32), fire_id=draw(i32))
    m.header.stamp, m.header.frame_id = draw(stamps), draw(frame_id)
    m.center_x_m, m.center_y_m = draw(f64), draw(f64)
    m.outer_distance_m, m.outer_visit_time_s = draw(f32_lists), draw(f32_lists)
    m.spread_rate_mps, m.importance = draw(f32_lists), draw(f32_lists)
    m.direction, m.direction_changes = draw(u8), draw(u32)
    return m


@st.composite
def fire_fronts(draw) -> FireFront:
    m = FireFront(uav_id=draw(u8), sequence=draw(u32), cell_size_m=draw(f32))
    m.header.stamp, m.header.frame_id = draw(stamps), draw(frame_id)
    m.x_m, m.y_m = draw(f32_lists), draw(f32_lists)
    m.state = draw(st.binary(max_size=41))
    m.observed_s = draw(st.lists(f64, max_size=40))
    m.spread_rate_mps = draw(f32_lists)
    return m


def _arr(xs) -> np.ndarray:
    return np.asarray(xs, dtype=float)


def _is_message(data: bytes, m) -> None:
    """``data`` is rclpy's serialisation of ``m`` without trailing bytes after the last field,
    reads back as ``m`` does (a float32 field of a Python message holds a float64 until it is
    serialised), and is a message a bag reader (rosbags) accepts."""
    ref = serialize_message(m)
    trailing = 4 if isinstance(m, FireFront) and len(m.observed_s) == 0 else 0  # Fast CDR's quirk
    assert len(data) in (len(ref), len(ref) - trailing)
    from fire_uav_recording.typestore import fleet_typestore  # the bag reader the report uses

    assert fleet_typestore().deserialize_cdr(data, f"fire_uav_msgs/msg/{type(m).__name__}") is not None
    assert_same_message(deserialize_message(data, type(m)), deserialize_message(ref, type(m)))


def test_the_message_definitions_are_the_ones_the_codecs_read():
    assert tuple(PerimeterMap.get_fields_and_field_types().items()) == PERIMETERMAP_FIELDS
    assert tuple(FireFront.get_fields_and_field_types().items()) == FIREFRONT_FIELDS


@settings(max_examples=200, deadline=None)
@given(perimeter_maps())
def test_perimeter_read_equals_rclpy_and_write_equals_its_bytes(m):
    data = serialize_message(m)
    w = read_perimeter_map(data)
    ref = deserialize_message(data, PerimeterMap)
    assert (w.stamp_ns, w.uav_id, w.sequence, w.fire_id) == (
        stamp_to_ns(ref.header.stamp), ref.uav_id, ref.sequence, ref.fire_id,
    )  # fmt: skip
    assert same((w.center_x_m, w.center_y_m), (ref.center_x_m, ref.center_y_m))
    for name in ("outer_distance_m", "outer_visit_time_s", "spread_rate_mps", "importance"):
        assert same(getattr(w, name), _arr(getattr(ref, name))), name
    assert (w.direction, w.direction_changes) == (ref.direction, ref.direction_changes)
    m.header.frame_id = "map"  # what the writer writes
    _is_message(write_perimeter_map(
        stamp_ns=w.stamp_ns, uav_id=w.uav_id, sequence=w.sequence, fire_id=w.fire_id,
        center_xy=(w.center_x_m, w.center_y_m), outer_distance_m=w.outer_distance_m,
        outer_visit_time_s=w.outer_visit_time_s, spread_rate_mps=w.spread_rate_mps,
        importance=w.importance, direction=w.direction, direction_changes=w.direction_changes,
    ), m)  # fmt: skip


@settings(max_examples=200, deadline=None)
@given(fire_fronts())
def test_front_read_equals_rclpy_and_write_equals_its_bytes(m):
    data = serialize_message(m)
    w = read_fire_front(data)
    ref = deserialize_message(data, FireFront)
    assert (w.stamp_ns, w.uav_id, w.sequence) == (stamp_to_ns(ref.header.stamp), ref.uav_id, ref.sequence)
    assert same(w.cell_size_m, ref.cell_size_m)
    for name in ("x_m", "y_m", "observed_s", "spread_rate_mps"):
        assert same(getattr(w, name), _arr(getattr(ref, name))), name
    assert same(w.state, np.frombuffer(bytes(ref.state), dtype=np.uint8).astype(np.int64))
    m.header.frame_id = "map"
    _is_message(write_fire_front(
        stamp_ns=w.stamp_ns, uav_id=w.uav_id, sequence=w.sequence, cell_size_m=w.cell_size_m,
        x_m=w.x_m, y_m=w.y_m, state=w.state, observed_s=w.observed_s, spread_rate_mps=w.spread_rate_mps,
    ), m)  # fmt: skip


# --- the agent's side: what the node built and read before the codecs -------------------------------
bins = st.integers(0, 36)


@st.composite
def outputs_with_a_map(draw):
    n = draw(bins)
    floats = st.lists(f32 | st.floats(-1e30, 1e30), min_size=n, max_size=n).map(np.array)
    summary = {
        "center_x_m": draw(f64), "center_y_m": draw(f64),
        "outer_distance_m": draw(floats), "outer_visit_time_s": draw(floats),
        "spread_rate_mps": draw(floats), "importance": draw(floats),
        "direction": draw(st.integers(0, 1)), "direction_changes": draw(st.integers(0, 10**6)),
    }  # fmt: skip
    fire_id = draw(st.one_of(st.integers(0, 2**31 - 1), st.integers(2**31, 2**40)))  # briefed: beyond int32
    return _out(draw(u8), perimeter=(fire_id, summary))


@st.composite
def outputs_with_a_front(draw):
    n = draw(bins)
    floats = st.lists(st.floats(-1e6, 1e6) | st.just(math.nan), min_size=n, max_size=n).map(np.array)
    cells = FrontCells(
        draw(floats), draw(floats), np.array(draw(st.lists(st.integers(0, 4), min_size=n, max_size=n)), dtype=np.int64),
        draw(st.lists(st.floats(0, 1e5), min_size=n, max_size=n).map(np.array)), draw(floats),
    )  # fmt: skip
    return _out(draw(u8), front=cells)


def _out(uav_id: int, **fields):
    out = type("Out", (), {"perimeter": None, "front": None})()
    out.state = type("S", (), {"uav_id": uav_id})()
    for k, v in fields.items():
        setattr(out, k, v)
    return out


@settings(max_examples=150, deadline=None)
@given(outputs_with_a_map(), u32, st.integers(0, 10**6), st.sampled_from([0.05, 0.1, 0.2]))
def test_perimeter_bytes_are_the_nodes_message_and_read_as_it_read_them(out, seq, step, period_s):
    stamp_ns = step_to_ns(step, round(period_s * 1e9))  # the bundle stamp (k + 1) T of step k
    stamp = to_time_msg(stamp_ns, Time)
    msg = rclpy_ref.perimeter_msg(out, stamp, seq)
    data = perimeter_bytes(out, stamp_ns, seq)
    _is_message(data, msg)
    got = peer_perimeter(read_perimeter_map(data), period_s)
    want = rclpy_ref.to_peer_perimeter(deserialize_message(data, PerimeterMap), period_s)
    assert same(got, want) and got.step == step


@settings(max_examples=150, deadline=None)
@given(outputs_with_a_front(), u32, st.integers(0, 10**6), st.floats(0.5, 50.0))
def test_front_bytes_are_the_nodes_message_and_read_as_it_read_them(out, seq, step, cell_size_m):
    stamp_ns = step_to_ns(step, round(0.1 * 1e9))
    msg = rclpy_ref.front_msg(out, to_time_msg(stamp_ns, Time), seq, cell_size_m)
    data = front_bytes(out, stamp_ns, seq, cell_size_m)
    _is_message(data, msg)
    got = peer_front(read_fire_front(data), 0.1)
    want = rclpy_ref.to_peer_front(deserialize_message(data, FireFront), 0.1)
    assert same(got, want) and got.step == step


def test_no_map_or_front_is_no_bytes():
    out = _out(1)
    assert perimeter_bytes(out, 10**8, 1) is None and front_bytes(out, 10**8, 1, 5.0) is None


def test_values_come_through_float32_rounded_and_the_briefed_fire_as_minus_one():
    summary = {
        "center_x_m": 0.1, "center_y_m": -2.5, "outer_distance_m": np.array([10.1, np.nan]),
        "outer_visit_time_s": np.array([812.3, np.nan]), "spread_rate_mps": np.array([0.5, 0.25]),
        "importance": np.array([1.0, 0.0]), "direction": 1, "direction_changes": 3,
    }  # fmt: skip
    w = read_perimeter_map(perimeter_bytes(_out(4, perimeter=(2**40 + 1, summary)), 4_200_000_000, 9))
    assert (w.uav_id, w.sequence, w.fire_id, w.stamp_ns, w.center_x_m) == (4, 9, -1, 4_200_000_000, 0.1)
    assert w.outer_distance_m[0] == float(np.float32(10.1)) != 10.1  # float32, widened exactly
    assert w.outer_visit_time_s[0] == pytest.approx(812.3, abs=1e-4) and math.isnan(w.outer_visit_time_s[1])
    assert (w.direction, w.direction_changes) == (1, 3)
    assert peer_perimeter(w, 0.1).step == 41  # stamped 4.2 s = (41 + 1) T: it answers step 41


def test_a_peer_front_keeps_the_senders_cell_size():
    data = write_fire_front(
        stamp_ns=10**8, uav_id=1, sequence=1, cell_size_m=7.5, x_m=[1.0], y_m=[1.0],
        state=[1], observed_s=[0.0], spread_rate_mps=[0.0],
    )  # fmt: skip
    assert peer_front(read_fire_front(data), 0.1).cell_size_m == 7.5


def test_unequal_front_arrays_are_a_clear_error_for_the_node_to_drop():
    data = write_fire_front(
        stamp_ns=10**8, uav_id=1, sequence=1, cell_size_m=5.0, x_m=[1.0], y_m=[1.0, 2.0],
        state=[1, 2], observed_s=[0.0, 0.0], spread_rate_mps=[0.0, 0.0],
    )  # fmt: skip
    with pytest.raises(ValueError, match="must have the same length"):
        peer_front(read_fire_front(data), 0.1)


def test_a_signed_perimeter_reads_as_its_message():
    m = PerimeterMap(uav_id=3, sequence=2, fire_id=1)
    m.header.frame_id = "map"
    m.outer_distance_m = [1.0, 2.0, 3.0]
    data = Authenticator(bytes(range(32))).sign_serialized(serialize_message(m), "/fleet/perimeter", 3, 7)
    assert data[-32:] != bytes(32)
    assert same(read_perimeter_map(data).outer_distance_m, np.array([1.0, 2.0, 3.0]))


def _samples() -> list[tuple[str, bytes]]:
    pm = PerimeterMap(uav_id=2, sequence=1)
    pm.header.frame_id = "map"
    pm.outer_distance_m, pm.importance = [1.0, 2.0], [0.5]
    ff = FireFront(uav_id=2, sequence=1, cell_size_m=5.0)
    ff.header.frame_id = "map"
    ff.x_m, ff.y_m, ff.state, ff.observed_s, ff.spread_rate_mps = [1.0], [2.0], b"\x01", [3.0], [0.5]
    return [("PerimeterMap", bytes(serialize_message(pm))), ("FireFront", bytes(serialize_message(ff)))]


READERS = {"PerimeterMap": read_perimeter_map, "FireFront": read_fire_front}


@pytest.mark.parametrize("name", sorted(READERS))  # by name: rclpy's padding bytes vary per run
def test_every_truncation_and_a_byte_left_over_are_value_errors_naming_the_message(name):
    data = dict(_samples())[name]
    read = READERS[name]
    for n in range(len(data)):
        with pytest.raises(ValueError, match=f"{name}|CDR"):
            read(data[:n])
    with pytest.raises(ValueError, match=f"{name} of {len(data) + 1} bytes: expected"):
        read(data + b"\x00")
    with pytest.raises(ValueError, match="not XCDR1 little-endian"):
        read(b"\x00\x00" + data[2:])


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=400), st.sampled_from(sorted(READERS)))
def test_noise_is_a_value_error_or_a_message(noise, name):
    try:
        READERS[name](b"\x00\x01\x00\x00" + noise)
    except ValueError:
        pass


def test_the_wire_types_are_frozen():
    w = read_fire_front(_samples()[1][1])
    with pytest.raises(dataclasses.FrozenInstanceError):
        w.uav_id = 3  # type: ignore[misc]


# --- edges named by the mutation run (docs/testing.md) ----------------------------------------------
def _full_samples() -> dict[str, bytes]:
    """rclpy's bytes of each message with every array non-empty."""
    out = dict(_samples())
    pm = PerimeterMap(uav_id=2, sequence=1)
    pm.header.frame_id = "map"
    pm.outer_distance_m, pm.outer_visit_time_s = [1.0, 2.0], [3.0]
    pm.spread_rate_mps, pm.importance = [0.5], [0.5]
    out["PerimeterMap"] = bytes(serialize_message(pm))
    return out


def _messages_of_every_truncation(name: str) -> set[str]:
    data = _full_samples()[name]
    out = set()
    for n in range(len(data)):
        with pytest.raises(ValueError) as err:
            READERS[name](data[:n])
        out.add(str(err.value))
    return out


@pytest.mark.parametrize(
    ("name", "fields"),
    [
        ("PerimeterMap", ("outer_distance_m", "outer_visit_time_s", "spread_rate_mps", "importance")),
        ("FireFront", ("x_m", "y_m", "state", "observed_s", "spread_rate_mps")),
    ],
)
def test_a_cut_array_or_header_is_named_in_the_one_error_line(name: str, fields: tuple[str, ...]) -> None:
    """rclpy's bytes cut just after an array's length: the error names that field of that message,
    the header's frame id, and the encapsulation's message."""
    said = _messages_of_every_truncation(name)
    for f in fields:
        assert any(m.startswith(f"{name} {f} length ") and "runs past the end" in m for m in said), f
    assert any(m.startswith(f"{name} header.frame_id length ") for m in said)
    data = _full_samples()[name]
    with pytest.raises(ValueError, match=f"^{name}: not XCDR1 little-endian"):
        READERS[name](b"\x00\x00" + data[2:])
    with pytest.raises(ValueError, match=f"^{name} of {len(data) + 1} bytes: expected .* not {len(data)}$"):
        READERS[name](data + b"\x00")


def test_a_perimeter_cut_after_its_last_array_is_truncated_not_an_overlong_array() -> None:
    """The importance array fits in full; what is missing is direction, direction_changes and auth
    (1 + 3 padding + 4 + 32 bytes)."""
    data = _full_samples()["PerimeterMap"]
    with pytest.raises(ValueError, match="^PerimeterMap truncated"):
        read_perimeter_map(data[: len(data) - 40])


def _perimeter(**kw) -> bytes:
    args = dict(
        stamp_ns=10**8, uav_id=1, sequence=1, fire_id=0, center_xy=(0.0, 0.0), outer_distance_m=[1.0],
        outer_visit_time_s=[1.0], spread_rate_mps=[1.0], importance=[1.0], direction=0, direction_changes=0,
    )  # fmt: skip
    args.update(kw)
    return write_perimeter_map(**args)


def _front(**kw) -> bytes:
    args = dict(
        stamp_ns=10**8, uav_id=1, sequence=1, cell_size_m=5.0, x_m=[1.0], y_m=[2.0], state=[1],
        observed_s=[3.0], spread_rate_mps=[0.5],
    )  # fmt: skip
    args.update(kw)
    return write_fire_front(**args)


def test_the_writers_refuse_what_the_message_cannot_hold_naming_the_field() -> None:
    """int32 fire_id (ROS: -2**31..2**31 - 1), uint8 states and ids, a stamp before 0."""
    for fire_id in (-(2**31), 2**31 - 1):
        m = deserialize_message(_perimeter(fire_id=fire_id), PerimeterMap)
        assert m.fire_id == fire_id
    for fire_id in (-(2**31) - 1, 2**31):
        with pytest.raises(ValueError, match=f"^PerimeterMap fire_id {fire_id} is out of int32$"):
            _perimeter(fire_id=fire_id)
    with pytest.raises(ValueError, match="^PerimeterMap stamp must be >= 0 ns, got -1$"):
        _perimeter(stamp_ns=-1)
    with pytest.raises(ValueError, match="^PerimeterMap of uav 256: a field out of range"):
        _perimeter(uav_id=256)
    with pytest.raises(ValueError, match="^FireFront stamp must be >= 0 ns, got -1$"):
        _front(stamp_ns=-1)
    with pytest.raises(ValueError, match="^FireFront of uav 256: a field out of range"):
        _front(uav_id=256)
    for bad in ([-1, 3], [0, 256]):
        with pytest.raises(ValueError, match=r"^FireFront of uav 1: a state outside uint8"):
            _front(state=bad, x_m=[1.0, 1.0], y_m=[2.0, 2.0])
    m = deserialize_message(_front(state=[0, 255], observed_s=[1.0, 2.0]), FireFront)
    assert bytes(m.state) == b"\x00\xff"


def test_observation_times_go_as_float64_whatever_array_they_come_in() -> None:
    """float32 or int inputs are written as the float64 values they hold, as rclpy converts them."""
    for times in (np.array([3.5, 1.25], dtype=np.float32), [3, 1], np.array([3.5, 1.25])):
        m = deserialize_message(_front(observed_s=times, state=[1, 1]), FireFront)
        assert list(m.observed_s) == [float(t) for t in np.asarray(times, dtype=float)]
