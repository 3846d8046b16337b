"""The agent's ``SensorBundle`` read straight from its CDR bytes into a :class:`Bundle`.

Why: a bundle carries ~10 ``sensor_msgs/Imu`` gyro samples (100 Hz at a 10 Hz step), and
``deserialize_message`` builds each as Python objects (a Header, a Quaternion, two Vector3 and
three 9-element numpy arrays, first as defaults and then again from the bytes), ~200 us a bundle,
of which the agent uses two numbers per sample: the stamp and ``angular_velocity.z``
(docs/profile.md, session 13). This reads the fields ``agent_node._to_bundle`` reads, from the
bytes, to the same values: test_bundle_wire.py compares the two on generated bundles and pins the
field lists of every message type involved.

The encoding and its rules: ``fire_uav_common.cdr``. Another encapsulation, truncated bytes or
bytes left after ``vehicle_status`` (beyond the padding to 4 bytes that Fast DDS adds on the wire)
raise ValueError (the node then falls back to
``deserialize_message``). Like ``state_wire`` it does not decode the ``frame_id`` strings.

ROS-free: bytes in, :class:`Bundle` out.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

import numpy as np
from fire_uav_common.cdr import U32, align4, align8, check_encapsulation, read_string_end

from .agent_types import Bundle
from .errors import WireError
from .estimation import Samples

__all__ = ["WireBundle", "SENSORBUNDLE_FIELDS", "SAMPLE_FIELDS", "read_sensor_bundle"]

#: the message definitions this reader expects (name, ROS type), in order
SENSORBUNDLE_FIELDS = (
    ("header", "std_msgs/Header"), ("uav_id", "uint8"), ("step", "uint32"),
    ("control_period_s", "double"), ("gyro", "sequence<sensor_msgs/Imu>"),
    ("altimeter", "sequence<sensor_msgs/Range>"), ("gps", "sequence<fire_uav_msgs/GpsFix>"),
    ("fires", "sequence<fire_uav_msgs/FireDetection>"), ("cells", "fire_uav_msgs/FireCells"),
    ("water_kg", "float"), ("vehicle_status", "uint8"),
)  # fmt: skip
SAMPLE_FIELDS = {
    "sensor_msgs/Imu": (
        ("header", "std_msgs/Header"), ("orientation", "geometry_msgs/Quaternion"),
        ("orientation_covariance", "double[9]"), ("angular_velocity", "geometry_msgs/Vector3"),
        ("angular_velocity_covariance", "double[9]"), ("linear_acceleration", "geometry_msgs/Vector3"),
        ("linear_acceleration_covariance", "double[9]"),
    ),
    "sensor_msgs/Range": (
        ("header", "std_msgs/Header"), ("radiation_type", "uint8"), ("field_of_view", "float"),
        ("min_range", "float"), ("max_range", "float"), ("range", "float"), ("variance", "float"),
    ),
    "fire_uav_msgs/GpsFix": (
        ("header", "std_msgs/Header"), ("x_m", "double"), ("y_m", "double"), ("variance_m2", "double"),
    ),
    "fire_uav_msgs/FireDetection": (
        ("header", "std_msgs/Header"), ("track_id", "int32"), ("x_m", "double"), ("y_m", "double"),
        ("extent_m", "double"), ("range_m", "double"),
    ),
    "fire_uav_msgs/FireCells": (
        ("header", "std_msgs/Header"), ("cell_size_m", "float"), ("x_m", "sequence<float>"),
        ("y_m", "sequence<float>"), ("state", "sequence<uint8>"),
    ),
}  # fmt: skip

_NS_PER_S = 1_000_000_000
_STAMP = struct.Struct("<iI")  # builtin_interfaces/Time: sec, nanosec
_F64 = struct.Struct("<d")
_F32 = struct.Struct("<f")
_STEP = struct.Struct("<I")
_IMU_DOUBLES = 4 + 9 + 3 + 9 + 3 + 9  # orientation, its covariance, angular velocity, ...
_IMU_OMEGA_Z = 8 * (4 + 9 + 2)  # [B] offset of angular_velocity.z in the Imu's doubles
_RANGE_RANGE = 4 * 3  # [B] offset of ``range`` in the Range's float32 run after radiation_type
_GPS = struct.Struct("<3d")
_DETECTION = struct.Struct("<4d")  # x, y, extent, range (after the int32 track_id)
_MIN_SAMPLE_BYTES = 12  # a Header with an empty frame_id: the least any sample can take


@dataclass(frozen=True, slots=True)
class WireBundle:
    """A bundle as the agent uses it, with its header stamp (the agent's answers echo it)."""

    bundle: Bundle
    stamp_sec: int
    stamp_nanosec: int


def _stamp_s(sec: int, nanosec: int) -> float:
    return (sec * _NS_PER_S + nanosec) / _NS_PER_S  # as stamps.stamp_to_s


def _sample_header(data: bytes | bytearray | memoryview, i: int, what: str) -> tuple[float, int]:
    """A sample's std_msgs/Header starting at (unaligned) index ``i``: (its stamp [s], the index
    after its frame_id)."""
    i = align4(i)
    sec, nanosec = _STAMP.unpack_from(data, i)
    return _stamp_s(sec, nanosec), read_string_end(data, i + 8, what)


def read_sensor_bundle(data: bytes | bytearray | memoryview) -> WireBundle:
    """A serialised ``fire_uav_msgs/SensorBundle`` (as received raw) -> :class:`WireBundle`.

    The arrays are those of ``agent_node._to_bundle``: gyro (t_s, omega_z), altimeter (t_s, range),
    GPS (t_s, x, y) with its variances, fires (t_s, x, y, extent), and the raster cells (x, y as
    float64 from their float32, states as int64), or None if the cell arrays are empty or unequal.
    Raises ValueError naming what is wrong.
    """
    n = len(data)
    check_encapsulation(data, "SensorBundle")
    try:
        sec, nsec = _STAMP.unpack_from(data, 4)
        i = read_string_end(data, 12, "SensorBundle header.frame_id")
        i = align4(i + 1)  # after uav_id
        (step,) = _STEP.unpack_from(data, i)
        i = align8(i + 4)
        (period,) = _F64.unpack_from(data, i)
        i += 8

        def count(i: int, what: str, least: int) -> tuple[int, int]:
            (k,) = U32.unpack_from(data, i)
            if i + 4 + least * k > n:
                raise WireError(f"SensorBundle {what} length {k} runs past the end of {n} bytes")
            return k, i + 4

        k, i = count(align4(i), "gyro", _MIN_SAMPLE_BYTES)
        gyro = []
        for _ in range(k):
            t_s, i = _sample_header(data, i, "Imu header.frame_id")
            i = align8(i)
            gyro.append((t_s, _F64.unpack_from(data, i + _IMU_OMEGA_Z)[0]))
            i += 8 * _IMU_DOUBLES
        k, i = count(align4(i), "altimeter", _MIN_SAMPLE_BYTES)
        alt = []
        for _ in range(k):
            t_s, i = _sample_header(data, i, "Range header.frame_id")
            i = align4(i + 1)  # after radiation_type
            alt.append((t_s, _F32.unpack_from(data, i + _RANGE_RANGE)[0]))
            i += 4 * 5
        k, i = count(align4(i), "gps", _MIN_SAMPLE_BYTES)
        gps, gps_var = [], []
        for _ in range(k):
            t_s, i = _sample_header(data, i, "GpsFix header.frame_id")
            i = align8(i)
            x, y, var = _GPS.unpack_from(data, i)
            gps.append((t_s, x, y))
            gps_var.append(var)
            i += _GPS.size
        k, i = count(align4(i), "fires", _MIN_SAMPLE_BYTES)
        fires = []
        for _ in range(k):
            t_s, i = _sample_header(data, i, "FireDetection header.frame_id")
            i = align8(align4(i) + 4)  # after track_id
            x, y, ext, _range = _DETECTION.unpack_from(data, i)
            fires.append((t_s, x, y, ext))
            i += _DETECTION.size
        _t, i = _sample_header(data, i, "FireCells header.frame_id")
        i = align4(i)
        (cell_size,) = _F32.unpack_from(data, i)
        k, i = count(i + 4, "cells.x_m", 4)
        cx = np.frombuffer(data, "<f4", k, i)
        k, i = count(i + 4 * k, "cells.y_m", 4)
        cy = np.frombuffer(data, "<f4", k, i)
        k, i = count(i + 4 * k, "cells.state", 1)
        cs = np.frombuffer(data, np.uint8, k, i)
        i = align4(i + k)
        (water,) = _F32.unpack_from(data, i)
        vehicle = data[i + 4]
        i += 5
    except (struct.error, IndexError):
        raise WireError(f"SensorBundle truncated: {n} bytes") from None
    if n not in (i, align4(i)):  # DDS delivers the payload padded to 4 bytes (serialize_message does not)
        raise WireError(f"SensorBundle of {n} bytes: {n - i} bytes left after vehicle_status")
    cells = None
    if len(cx) > 0 and len(cx) == len(cy) == len(cs):
        cells = (cx.astype(float), cy.astype(float), cs.astype(np.int64))
    # the rows are Python floats (struct), so float64 arrays; an empty list too, in its shape
    bundle = Bundle(
        step=step,
        stamp_s=_stamp_s(sec, nsec),
        samples=Samples(
            np.array(gps).reshape(-1, 3),
            np.array(gps_var, dtype=float),
            np.array(alt).reshape(-1, 2),
            np.array(gyro).reshape(-1, 2),
        ),
        fires=np.array(fires).reshape(-1, 4),
        water_kg=water,
        vehicle=vehicle,
        control_period_s=period,
        cells=cells,
        cell_size_m=cell_size,
    )
    return WireBundle(bundle, sec, nsec)
