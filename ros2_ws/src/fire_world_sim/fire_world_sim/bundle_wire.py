"""The world's ``SensorBundle`` written straight into CDR bytes, without rclpy's message objects.

Why: a bundle carries ~10 ``sensor_msgs/Imu`` gyro samples, and building them as Python messages
(each a Header, a Quaternion, two Vector3 and three 9-element numpy arrays) and then converting
them for ``publish`` cost ~150 us a bundle, 20 bundles a step on the lockstep's serial path, where
every agent waits for its bundle (docs/profile.md, session 13). The bytes are the standard CDR of
``fire_uav_msgs/SensorBundle``: any subscriber (the agents, the recorder, ``ros2 topic echo``)
reads them as the message the world node built before (``reference_bundle_msg`` in
test_bundle_wire.py), checked on generated bundles by deserialising them with rclpy. The padding
bytes are zeros.

The layout rules: ``fire_uav_common.cdr``. ROS-free: world types in, bytes out.
"""

from __future__ import annotations

import struct

import numpy as np
from fire_uav_common.cdr import ENCAPSULATION, U32, pad

from .world import Bundle

__all__ = ["RANGE_ULTRASOUND", "write_sensor_bundle"]

NS_PER_S = 1_000_000_000
RANGE_ULTRASOUND = 0  # sensor_msgs/Range.ULTRASOUND
RANGE_FIELD_OF_VIEW_RAD = 0.5  # [rad] the altimeter message's field_of_view, as before
_STAMP = struct.Struct("<iI")
_F64 = struct.Struct("<d")
_F32 = struct.Struct("<f")
_I32 = struct.Struct("<i")
_IMU_TAIL = struct.Struct("<9d3d9d")  # angular_velocity_covariance, linear_acceleration (0), its covariance
# orientation (0, 0, 0, 1), orientation_covariance (-1: not provided), angular_velocity x, y
_IMU_HEAD = struct.pack("<4d9d2d", 0.0, 0.0, 0.0, 1.0, -1.0, *([0.0] * 8), 0.0, 0.0)
_RANGE = struct.Struct("<5f")  # field_of_view, min_range, max_range, range, variance
_GPS = struct.Struct("<3d")
_DETECTION = struct.Struct("<4d")
_MAP = b"map\x00"


def _header(buf: bytearray, stamp_ns: int, frame: bytes) -> None:
    """A std_msgs/Header: stamp (as ``stamps.to_time_msg``: negative refused) and ``frame`` (with NUL)."""
    if stamp_ns < 0:
        raise ValueError(f"stamp must be >= 0 ns, got {stamp_ns}")
    pad(buf, 4)
    buf += _STAMP.pack(*divmod(stamp_ns, NS_PER_S))
    buf += U32.pack(len(frame))
    buf += frame


def _count(buf: bytearray, k: int) -> None:
    pad(buf, 4)
    buf += U32.pack(k)


def write_sensor_bundle(b: Bundle, gyro_sigma_radps: float) -> bytes:
    """``b`` as the CDR bytes of its SensorBundle (test_bundle_wire.py: ``reference_bundle_msg``).

    ``gyro_sigma_radps``: the gyro's noise, reported as ``angular_velocity_covariance[8]`` (its
    square). Values out of a field's range raise (struct.error), as rclpy's message setters do.
    """
    buf = bytearray(ENCAPSULATION)
    _header(buf, b.stamp_ns, _MAP)
    buf.append(b.uav_id)
    pad(buf, 4)
    buf += U32.pack(b.step)
    pad(buf, 8)
    buf += _F64.pack(b.control_period_s)
    own = f"uav_{b.uav_id}".encode() + b"\x00"
    # angular_velocity_covariance (var at [8]), linear_acceleration (0), its covariance (-1: none)
    imu_tail = _IMU_TAIL.pack(*([0.0] * 8), gyro_sigma_radps**2, 0.0, 0.0, 0.0, -1.0, *([0.0] * 8))
    _count(buf, len(b.gyro))
    for g in b.gyro:
        _header(buf, g.stamp_ns, own)
        pad(buf, 8)
        buf += _IMU_HEAD
        buf += _F64.pack(float(g.omega_z_radps))
        buf += imu_tail
    _count(buf, len(b.altimeter))
    for a in b.altimeter:
        _header(buf, a.stamp_ns, own)
        buf.append(RANGE_ULTRASOUND)
        pad(buf, 4)
        buf += _RANGE.pack(RANGE_FIELD_OF_VIEW_RAD, 0.0, float(a.max_range_m), float(a.range_m), 0.0)
    _count(buf, len(b.gps))
    for p in b.gps:
        _header(buf, p.stamp_ns, _MAP)
        pad(buf, 8)
        buf += _GPS.pack(float(p.x_m), float(p.y_m), float(p.variance_m2))
    _count(buf, len(b.fires))
    for f in b.fires:
        _header(buf, f.stamp_ns, _MAP)
        pad(buf, 4)
        buf += _I32.pack(int(f.track_id))
        pad(buf, 8)
        buf += _DETECTION.pack(float(f.x_m), float(f.y_m), float(f.extent_m), float(f.range_m))
    _header(buf, b.stamp_ns, _MAP)  # FireCells
    pad(buf, 4)
    c = b.cells
    if c is None:
        buf += _F32.pack(0.0) + bytes(12)  # cell_size_m, and three empty sequences
    else:
        buf += _F32.pack(float(c.cell_size_m))
        for xs in (c.x_m, c.y_m):
            v = np.asarray(xs, dtype="<f4")  # as rclpy: any float -> float32, rounded to nearest
            buf += U32.pack(v.size) + v.tobytes()
        s = c.state.tobytes()  # uint8 (CellsSample), its bytes as they are
        buf += U32.pack(len(s)) + s
    pad(buf, 4)
    buf += _F32.pack(float(b.water_kg))
    buf.append(int(b.vehicle_status))
    return bytes(buf)
