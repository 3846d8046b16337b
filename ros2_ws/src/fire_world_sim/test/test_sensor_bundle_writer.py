"""``fire_uav_common.codecs.sensor_bundle.write_sensor_bundle`` against the message the world node built and published
before it (``reference_bundle_msg`` below): rclpy must read the bytes as exactly that message.

Generated world bundles (any number of each sample kind, raster cells or none, stamps and values
over their ranges) are written and deserialised by ``rclpy.serialization.deserialize_message``; the
result is compared slot for slot with the reference message of the same bundle (NaN equal to NaN).
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("fire_uav_msgs.msg")

from fire_uav_common.codecs import sensor_bundle
from fire_uav_common.codecs.sensor_bundle import write_sensor_bundle
from fire_uav_msgs.msg import FireDetection, GpsFix, SensorBundle
from fire_world_sim.sensors import AltimeterSample, CellsSample, FireDetectionSample, GpsSample, GyroSample
from fire_world_sim.world import SensorBundleRecord
from fire_world_sim.world_node import FRAME, WorldNode, stamp
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import Imu, Range


@pytest.fixture(autouse=True)
def _fresh_sample_structs(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each test builds the per-sample structs it needs (``_sample_struct``'s cache starts empty),
    so the bytes checked are those of the padding rules, not of structs an earlier test (or, in a
    mutation run, the unmutated code in the parent process) left in the module's cache."""
    monkeypatch.setattr(sensor_bundle, "_SAMPLE_STRUCTS", {})


f64 = st.floats(allow_nan=True, allow_infinity=True)
f32 = st.floats(width=32, allow_nan=True, allow_infinity=True)
ns = st.integers(0, 2**31 * 10**9 - 1)
i32 = st.integers(-(2**31), 2**31 - 1)


@st.composite
def world_bundles(draw) -> SensorBundleRecord:
    b = SensorBundleRecord(draw(st.integers(0, 255)), draw(st.integers(0, 2**32 - 1)), draw(ns), draw(f64))
    b.gyro = [GyroSample(draw(ns), draw(f64)) for _ in range(draw(st.integers(0, 12)))]
    b.altimeter = [AltimeterSample(draw(ns), draw(f32), draw(f32)) for _ in range(draw(st.integers(0, 4)))]
    b.gps = [GpsSample(draw(ns), draw(f64), draw(f64), draw(f64)) for _ in range(draw(st.integers(0, 3)))]
    b.fires = [
        FireDetectionSample(draw(ns), draw(i32), draw(f64), draw(f64), draw(f64), draw(f64))
        for _ in range(draw(st.integers(0, 4)))
    ]
    if draw(st.booleans()):
        k = draw(st.integers(0, 40))
        xy = [np.array(draw(st.lists(f32, min_size=k, max_size=k)), dtype=np.float32) for _ in range(2)]
        state = np.array(draw(st.lists(st.integers(0, 2), min_size=k, max_size=k)), dtype=np.uint8)
        b.cells = CellsSample(draw(ns), draw(f32), xy[0], xy[1], state)
    b.water_kg, b.vehicle_status = draw(f32), draw(st.integers(0, 3))
    return b


_hdr = WorldNode._hdr


def reference_bundle_msg(b: SensorBundleRecord, gyro_sigma_radps: float) -> SensorBundle:
    """The SensorBundle the world built and published before it wrote bytes (its former
    ``WorldNode._bundle_msg``, unchanged but for its arguments): the reference for the bytes."""
    m = SensorBundle()
    m.header.stamp = stamp(b.stamp_ns)
    m.header.frame_id = FRAME
    m.uav_id = b.uav_id
    m.step = b.step
    m.control_period_s = b.control_period_s
    for g in b.gyro:
        imu = Imu()
        imu.header.stamp = stamp(g.stamp_ns)
        imu.header.frame_id = f"uav_{b.uav_id}"
        imu.orientation_covariance[0] = -1.0
        imu.linear_acceleration_covariance[0] = -1.0
        imu.angular_velocity.z = float(g.omega_z_radps)
        imu.angular_velocity_covariance[8] = gyro_sigma_radps**2
        m.gyro.append(imu)
    for a in b.altimeter:
        rg = Range()
        rg.header.stamp = stamp(a.stamp_ns)
        rg.header.frame_id = f"uav_{b.uav_id}"
        rg.radiation_type = Range.ULTRASOUND
        rg.field_of_view = 0.5
        rg.min_range = 0.0
        rg.max_range = float(a.max_range_m)
        rg.range = float(a.range_m)
        m.altimeter.append(rg)
    for p in b.gps:
        m.gps.append(
            GpsFix(
                header=_hdr(p.stamp_ns),
                x_m=float(p.x_m),
                y_m=float(p.y_m),
                variance_m2=float(p.variance_m2),
            )
        )
    for f in b.fires:
        m.fires.append(
            FireDetection(
                header=_hdr(f.stamp_ns),
                track_id=int(f.track_id),
                x_m=float(f.x_m),
                y_m=float(f.y_m),
                extent_m=float(f.extent_m),
                range_m=float(f.range_m),
            )
        )
    m.cells.header = _hdr(b.stamp_ns)
    if b.cells is not None:
        m.cells.cell_size_m = float(b.cells.cell_size_m)
        m.cells.x_m = b.cells.x_m.astype(float).tolist()
        m.cells.y_m = b.cells.y_m.astype(float).tolist()
        m.cells.state = b.cells.state.tobytes()
    m.water_kg = float(b.water_kg)
    m.vehicle_status = int(b.vehicle_status)
    return m


def _same(a, b, path="msg") -> None:
    """Assert two ROS messages equal slot for slot (floats by repr, so NaN equals NaN)."""
    if hasattr(a, "get_fields_and_field_types"):
        assert type(a) is type(b), path
        for name in a.get_fields_and_field_types():
            _same(getattr(a, name), getattr(b, name), f"{path}.{name}")
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        assert np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True), path
    elif isinstance(a, (list, tuple)) or hasattr(a, "typecode"):
        a, b = list(a), list(b)
        assert len(a) == len(b), path
        for k, (x, y) in enumerate(zip(a, b, strict=True)):
            _same(x, y, f"{path}[{k}]")
    else:
        assert repr(a) == repr(b), f"{path}: {a!r} != {b!r}"


@settings(max_examples=200, deadline=None)
@given(world_bundles(), st.floats(0.0, 1.0))
def test_rclpy_reads_the_bytes_as_the_message_the_node_built(b, sigma):
    got = deserialize_message(write_sensor_bundle(b, sigma), SensorBundle)
    _same(got, reference_bundle_msg(b, sigma))


def test_a_hand_built_bundle():
    b = SensorBundleRecord(
        3, 7, 1_200_000_000, 0.1, gyro=[GyroSample(1_110_000_000, 0.25)], water_kg=5.0, vehicle_status=1
    )
    b.altimeter = [AltimeterSample(1_140_000_000, 12.5, 40.0)]
    m = deserialize_message(write_sensor_bundle(b, 0.3), SensorBundle)
    assert (m.uav_id, m.step, m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id) == (
        3,
        7,
        1,
        200_000_000,
        "map",
    )
    g = m.gyro[0]
    assert (g.header.frame_id, g.header.stamp.nanosec, g.angular_velocity.z) == ("uav_3", 110_000_000, 0.25)
    assert g.angular_velocity_covariance[8] == pytest.approx(0.09) and g.orientation_covariance[0] == -1.0
    assert (m.altimeter[0].range, m.altimeter[0].max_range, m.water_kg, m.vehicle_status) == (
        12.5,
        40.0,
        5.0,
        1,
    )
    assert len(m.cells.x_m) == 0 and m.cells.cell_size_m == 0.0


def test_a_negative_stamp_is_refused_by_name():
    with pytest.raises(ValueError, match="stamp must be >= 0 ns, got -1"):
        write_sensor_bundle(SensorBundleRecord(0, 0, -1, 0.1), 0.3)


@pytest.mark.parametrize("kind", ["gyro", "altimeter", "gps", "fires"])
def test_a_negative_sample_stamp_is_refused_by_name(kind):
    b = SensorBundleRecord(0, 0, 0, 0.1)
    sample = {
        "gyro": GyroSample(-7, 0.0),
        "altimeter": AltimeterSample(-7, 1.0, 2.0),
        "gps": GpsSample(-7, 0.0, 0.0, 1.0),
        "fires": FireDetectionSample(-7, 1, 0.0, 0.0, 1.0, 1.0),
    }[kind]
    getattr(b, kind).append(sample)
    with pytest.raises(ValueError) as e:
        write_sensor_bundle(b, 0.3)
    assert str(e.value) == "stamp must be >= 0 ns, got -7"


def test_float64_cell_centres_are_rounded_to_float32_as_the_message_type_does():
    """As the reference's float32[] conversion in rclpy (the world's own are float32 already)."""
    x = np.array([0.1, 1e-3, 12345.678])
    c = CellsSample(5, 2.5, x, -x, np.array([0, 1, 2], dtype=np.uint8))
    b = SensorBundleRecord(0, 1, 5, 0.1, cells=c)
    _same(deserialize_message(write_sensor_bundle(b, 0.3), SensorBundle), reference_bundle_msg(b, 0.3))
