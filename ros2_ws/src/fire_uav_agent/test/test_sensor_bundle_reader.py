"""The ``sensor_bundle`` codec's reader against the agent node's former conversion of rclpy's
deserialisation (``rclpy_reference.to_bundle``).

Generated SensorBundles (every field random, frame ids of every length mod 8 in every header so each
alignment rule is exercised, 0-12 samples of each kind, raster cells of equal and unequal lengths)
are serialised by ``rclpy.serialization.serialize_message`` and read both ways; the results must be
equal array for array. The field lists of every message type involved are pinned. Bad bytes raise
ValueError and nothing else.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("fire_uav_msgs.msg")

from builtin_interfaces.msg import Time
from fire_uav_agent.testing import rclpy_reference as rclpy_ref
from fire_uav_agent.testing.compare import same
from fire_uav_agent.testing.msg_strategies import f32, f64, frame_ids, i32, stamps, u8, u32
from fire_uav_common.codecs.sensor_bundle import SAMPLE_FIELDS, SENSORBUNDLE_FIELDS, read_sensor_bundle
from fire_uav_msgs.msg import FireCells, FireDetection, GpsFix, SensorBundle
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import deserialize_message, serialize_message
from sensor_msgs.msg import Imu, Range

frames = frame_ids(9)


def _header(draw, h) -> None:
    h.stamp, h.frame_id = draw(stamps), draw(frames)


@st.composite
def bundles(draw) -> SensorBundle:
    m = SensorBundle(uav_id=draw(u8), step=draw(u32), control_period_s=draw(f64))
    _header(draw, m.header)
    for _ in range(draw(st.integers(0, 12))):
        s = Imu()
        _header(draw, s.header)
        s.angular_velocity.x, s.angular_velocity.z = draw(f64), draw(f64)
        s.orientation.w, s.linear_acceleration.z = draw(f64), draw(f64)
        s.orientation_covariance[0], s.angular_velocity_covariance[8] = draw(f64), draw(f64)
        m.gyro.append(s)
    for _ in range(draw(st.integers(0, 4))):
        r = Range(radiation_type=draw(u8), field_of_view=draw(f32), min_range=draw(f32))
        r.max_range, r.range, r.variance = draw(f32), draw(f32), draw(f32)
        _header(draw, r.header)
        m.altimeter.append(r)
    for _ in range(draw(st.integers(0, 3))):
        g = GpsFix(x_m=draw(f64), y_m=draw(f64), variance_m2=draw(f64))
        _header(draw, g.header)
        m.gps.append(g)
    for _ in range(draw(st.integers(0, 4))):
        f = FireDetection(track_id=draw(i32), x_m=draw(f64), y_m=draw(f64), extent_m=draw(f64))
        f.range_m = draw(f64)
        _header(draw, f.header)
        m.fires.append(f)
    c = FireCells(cell_size_m=draw(f32))
    _header(draw, c.header)
    k = draw(st.integers(0, 30))
    c.x_m = draw(st.lists(f32, min_size=k, max_size=k))
    c.y_m = draw(st.lists(f32, min_size=k, max_size=k + draw(st.sampled_from([0, 0, 1]))))
    c.state = bytes(draw(st.lists(u8, min_size=k, max_size=k)))
    m.cells = c
    m.water_kg, m.vehicle_status = draw(f32), draw(u8)
    return m


def test_the_message_definitions_are_the_ones_the_reader_reads():
    assert tuple(SensorBundle.get_fields_and_field_types().items()) == SENSORBUNDLE_FIELDS
    types = {"sensor_msgs/Imu": Imu, "sensor_msgs/Range": Range, "fire_uav_msgs/GpsFix": GpsFix}
    types |= {"fire_uav_msgs/FireDetection": FireDetection, "fire_uav_msgs/FireCells": FireCells}
    for name, fields in SAMPLE_FIELDS.items():
        assert tuple(types[name].get_fields_and_field_types().items()) == fields, name


@settings(max_examples=250, deadline=None)
@given(bundles())
def test_read_equals_the_nodes_conversion_of_rclpys_deserialisation(m):
    data = serialize_message(m)
    w = read_sensor_bundle(data)
    ref = deserialize_message(data, SensorBundle)
    assert same(w.bundle, rclpy_ref.to_bundle(ref))
    assert (w.stamp_sec, w.stamp_nanosec) == (ref.header.stamp.sec, ref.header.stamp.nanosec)


def test_values_come_through_exactly():
    m = SensorBundle(uav_id=4, step=17, control_period_s=0.1)
    m.header.stamp, m.header.frame_id = Time(sec=1, nanosec=800_000_000), "map"
    for k, w in enumerate((0.25, -0.5)):
        s = Imu()
        s.header.stamp, s.header.frame_id = Time(sec=1, nanosec=710_000_000 + 10_000_000 * k), "uav_4"
        s.angular_velocity.z, s.angular_velocity_covariance[8] = w, 0.09
        m.gyro.append(s)
    r = Range(range=12.5, max_range=40.0)
    r.header.stamp, r.header.frame_id = Time(sec=1, nanosec=760_000_000), "uav_4"
    m.altimeter = [r]
    g = GpsFix(x_m=100.0, y_m=-50.0, variance_m2=9.0)
    g.header.stamp, g.header.frame_id = Time(sec=1, nanosec=800_000_000), "map"
    m.gps = [g]
    f = FireDetection(track_id=2, x_m=300.0, y_m=310.0, extent_m=25.0, range_m=80.0)
    f.header.stamp, f.header.frame_id = Time(sec=1, nanosec=800_000_000), "map"
    m.fires = [f]
    m.cells.cell_size_m, m.cells.x_m, m.cells.y_m, m.cells.state = 5.0, [1.5, 2.5], [3.5, 4.5], b"\x01\x02"
    m.water_kg, m.vehicle_status = 150.0, SensorBundle.VEHICLE_AIRBORNE
    w = read_sensor_bundle(serialize_message(m))
    b = w.bundle
    assert (b.step, b.stamp_s, b.control_period_s, b.water_kg, b.vehicle) == (17, 1.8, 0.1, 150.0, 1)
    assert (w.stamp_sec, w.stamp_nanosec) == (1, 800_000_000)
    assert b.samples.gyro.tolist() == [[1.71, 0.25], [1.72, -0.5]]
    assert b.samples.alt.tolist() == [[1.76, 12.5]]
    assert b.samples.gps.tolist() == [[1.8, 100.0, -50.0]] and b.samples.gps_var_m2.tolist() == [9.0]
    assert b.fires.tolist() == [[1.8, 300.0, 310.0, 25.0]]
    x, y, s = b.cells
    assert (x.tolist(), y.tolist(), s.tolist(), s.dtype, b.cell_size_m) == (
        [1.5, 2.5],
        [3.5, 4.5],
        [1, 2],
        np.int64,
        5.0,
    )


def test_an_empty_bundle_has_empty_arrays_of_the_right_shapes():
    b = read_sensor_bundle(serialize_message(SensorBundle())).bundle
    shapes = (
        b.samples.gps.shape,
        b.samples.gps_var_m2.shape,
        b.samples.alt.shape,
        b.samples.gyro.shape,
        b.fires.shape,
    )
    assert shapes == ((0, 3), (0,), (0, 2), (0, 2), (0, 4)) and b.cells is None


def _sample() -> bytes:
    m = SensorBundle(step=3)
    m.gyro, m.altimeter, m.gps, m.fires = [Imu()], [Range()], [GpsFix()], [FireDetection()]
    m.cells.x_m, m.cells.y_m, m.cells.state = [1.0], [2.0], b"\x01"
    return serialize_message(m)


def test_every_truncation_is_a_value_error():
    data = _sample()
    for n in range(len(data)):
        with pytest.raises(ValueError, match="SensorBundle|length"):
            read_sensor_bundle(data[:n])


def test_bytes_left_over_and_another_encapsulation_are_refused_by_name():
    with pytest.raises(ValueError, match="1 bytes left after vehicle_status"):
        read_sensor_bundle(_sample() + b"\x00")
    with pytest.raises(ValueError, match="SensorBundle: not XCDR1 little-endian"):
        read_sensor_bundle(b"\x00\x00" + _sample()[2:])


@settings(max_examples=150, deadline=None)
@given(bundles(), st.data())
def test_a_flipped_byte_never_raises_anything_else(m, data):
    raw = bytearray(serialize_message(m))
    i = data.draw(st.integers(0, len(raw) - 1))
    raw[i] ^= data.draw(st.integers(1, 255))
    try:
        read_sensor_bundle(bytes(raw))
    except ValueError:
        pass


def test_the_padding_dds_adds_is_accepted_and_nothing_more():
    data = serialize_message(SensorBundle())  # 89 bytes: Fast DDS sends it as 92
    assert len(data) % 4 == 1
    assert same(read_sensor_bundle(data + bytes(3)).bundle, read_sensor_bundle(data).bundle)
    with pytest.raises(ValueError, match="4 bytes left after vehicle_status"):
        read_sensor_bundle(data + bytes(4))


def _error(data: bytes) -> str:
    with pytest.raises(ValueError) as e:
        read_sensor_bundle(data)
    return str(e.value)


def _set_u32(data: bytes, at: int, value: int) -> bytes:
    return data[:at] + value.to_bytes(4, "little") + data[at + 4 :]


# an empty bundle with frame "map" (89 bytes): where its counts are (fire_uav_common.cdr's layout)
_COUNTS = {
    "gyro": 36,
    "altimeter": 40,
    "gps": 44,
    "fires": 48,
    "cells.x_m": 72,
    "cells.y_m": 76,
    "cells.state": 80,
}


@pytest.mark.parametrize("name", list(_COUNTS))
def test_a_count_past_the_end_is_named_exactly(name):
    m = SensorBundle()
    m.header.frame_id = "map"
    data = serialize_message(m)
    assert len(data) == 89 and read_sensor_bundle(data).bundle.cells is None
    got = _error(_set_u32(data, _COUNTS[name], 10**6))
    assert got == f"SensorBundle {name} length 1000000 runs past the end of 89 bytes"


@pytest.mark.parametrize("field", ["x_m", "y_m"])
def test_cell_coordinates_near_the_end_read(field):
    """20 float32 with the other cell arrays empty: the count's bound is 4 bytes an element."""
    m = SensorBundle()
    setattr(m.cells, field, [float(j) for j in range(20)])
    data = serialize_message(m)
    ref = deserialize_message(data, SensorBundle)
    assert same(read_sensor_bundle(data).bundle, rclpy_ref.to_bundle(ref))


def test_a_cut_right_after_the_cell_centres_is_a_truncation():
    m = SensorBundle()
    m.cells.x_m = [1.0, 2.0]
    data = serialize_message(m)
    end = data.index(np.array([1.0, 2.0], "<f4").tobytes()) + 8
    assert _error(data[:end]) == f"SensorBundle truncated: {end} bytes"


def _bundle_with_frame_id(kind: str) -> tuple[bytes, bytes]:
    """A serialized bundle whose ``kind`` header (the bundle's, its cells', or one sample's) has
    the frame_id ``frame_of_<kind>``; and that frame_id as CDR stores it (NUL-terminated)."""
    m = SensorBundle()
    sample = {"Imu": Imu(), "Range": Range(), "GpsFix": GpsFix(), "FireDetection": FireDetection()}.get(kind)
    header = {"SensorBundle": m.header, "FireCells": m.cells.header}.get(kind) or sample.header
    header.frame_id = "frame_of_" + kind
    if sample is not None:
        {"Imu": m.gyro, "Range": m.altimeter, "GpsFix": m.gps, "FireDetection": m.fires}[kind].append(sample)
    return serialize_message(m), ("frame_of_" + kind).encode() + b"\x00"


@pytest.mark.parametrize("kind", ["SensorBundle", "Imu", "Range", "GpsFix", "FireDetection", "FireCells"])
def test_a_frame_id_past_the_end_names_its_message(kind):
    data, text = _bundle_with_frame_id(kind)
    end = data.index(text) + len(text)  # the string's end
    got = _error(data[: end - 1])
    assert got == f"{kind} header.frame_id length {len(text)} does not fit in {end - 1} bytes"


@pytest.mark.parametrize("kind", ["SensorBundle", "Imu", "Range", "GpsFix", "FireDetection", "FireCells"])
def test_a_cut_right_after_a_frame_id_is_a_truncation_not_a_bad_frame_id(kind):
    """The frame_id fits whole (as ``cdr.read_string_end`` judges it: it ends at the last byte);
    what is cut is the fields after it."""
    data, text = _bundle_with_frame_id(kind)
    end = data.index(text) + len(text)
    assert _error(data[:end]) == f"SensorBundle truncated: {end} bytes"
