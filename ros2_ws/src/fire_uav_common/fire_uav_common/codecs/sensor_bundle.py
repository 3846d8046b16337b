"""The ``fire_uav_msgs/SensorBundle`` codec: the world writes it, the agents (and the in-process
harness) read it, from the same bytes.

Why bytes and not rclpy's message objects: a bundle carries ~10 ``sensor_msgs/Imu`` gyro samples
(100 Hz at a 10 Hz step), and building them as Python messages (each a Header, a Quaternion, two
Vector3 and three 9-element numpy arrays) and converting them for ``publish``, or back with
``deserialize_message``, cost ~150-200 us a bundle, on the lockstep's serial path where every agent
waits for its bundle (docs/profile.md). The reader takes the fields the agent uses: per gyro sample
the stamp and ``angular_velocity.z``, and so on.

- :func:`write_sensor_bundle`: a world bundle (``fire_world_sim.world.SensorBundleRecord``: stamps [ns], samples)
  -> the standard CDR of the message; any subscriber (the agents, the recorder, ``ros2 topic echo``)
  reads them as the message the world node built before (fire_world_sim's test_sensor_bundle_writer.py,
  with rclpy). The padding bytes are zeros.
- :func:`read_sensor_bundle`: those bytes -> :class:`WireBundle` (:class:`Bundle`, the agent's
  ROS-free view, and the header stamp the agent's answers echo). Compared with rclpy's
  deserialisation on generated bundles (fire_uav_agent's test_sensor_bundle_reader.py), which also pins the
  field lists of every message type involved. Another encapsulation, truncated bytes or bytes left
  after ``vehicle_status`` (beyond the padding to 4 bytes that Fast DDS adds on the wire) raise
  :class:`~fire_uav_common.cdr.CdrError`. The ``frame_id`` strings are not decoded.

The layout rules: :mod:`fire_uav_common.cdr`. ROS-free.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..cdr import ENCAPSULATION, U32, CdrError, align4, align8, check_encapsulation, pad, read_string_end

__all__ = [
    "RANGE_ULTRASOUND",
    "SAMPLE_FIELDS",
    "SENSORBUNDLE_FIELDS",
    "Bundle",
    "Samples",
    "WireBundle",
    "read_sensor_bundle",
    "write_sensor_bundle",
]

#: ``fire_world_sim.world.SensorBundleRecord`` (duck-typed: this package sits below the world)
WorldBundle = Any

_STAMP = struct.Struct("<iI")  # builtin_interfaces/Time: sec, nanosec
_F64 = struct.Struct("<d")
_F32 = struct.Struct("<f")
_GPS = struct.Struct("<3d")
_DETECTION = struct.Struct("<4d")  # x, y, extent, range (after the int32 track_id)


# --- the agent's view -----------------------------------------------------------------------------
@dataclass
class Samples:
    """Sensor samples of one control step, each row stamped with its sim time [s].

    gps: (N, 3) rows (t_s, x_m, y_m); gps_var_m2: (N,) reported variance (<= 0: use config).
    alt: (N, 2) rows (t_s, height_above_ground_m). gyro: (N, 2) rows (t_s, omega_z_radps).
    """

    gps: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    gps_var_m2: np.ndarray = field(default_factory=lambda: np.zeros(0))
    alt: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    gyro: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))


@dataclass
class Bundle:
    """One SensorBundle, ROS-free. fires: (N, 4) rows (t_s, x_m, y_m, extent_m)."""

    step: int
    stamp_s: float  # t_{k+1}
    samples: Samples
    fires: np.ndarray
    water_kg: float
    vehicle: int  # VehicleStatus
    control_period_s: float = 0.1
    cells: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # FireCells: x_m, y_m, state
    cell_size_m: float = 0.0  # [m] FireCells.cell_size_m, 0 without a raster fire


# --- writing (the world) ---------------------------------------------------------------------------
_NS_PER_S = 1_000_000_000
RANGE_ULTRASOUND = 0  # sensor_msgs/Range.ULTRASOUND
RANGE_FIELD_OF_VIEW_RAD = 0.5  # [rad] the altimeter message's field_of_view, as before
_I32 = struct.Struct("<i")
_IMU_TAIL = struct.Struct("<9d3d9d")  # angular_velocity_covariance, linear_acceleration (0), its covariance
# orientation (0, 0, 0, 1), orientation_covariance (-1: not provided), angular_velocity x, y
_IMU_HEAD = struct.pack("<4d9d2d", 0.0, 0.0, 0.0, 1.0, -1.0, *([0.0] * 8), 0.0, 0.0)
_RANGE = struct.Struct("<5f")  # field_of_view, min_range, max_range, range, variance
_MAP = b"map\x00"


def _header(buf: bytearray, stamp_ns: int, frame: bytes) -> None:
    """A std_msgs/Header: stamp (as ``stamps.to_time_msg``: negative refused) and ``frame`` (with NUL)."""
    if stamp_ns < 0:
        raise CdrError(f"stamp must be >= 0 ns, got {stamp_ns}")
    pad(buf, 4)
    buf += _STAMP.pack(*divmod(stamp_ns, _NS_PER_S))
    buf += U32.pack(len(frame))
    buf += frame


def _count(buf: bytearray, k: int) -> None:
    pad(buf, 4)
    buf += U32.pack(k)


_SampleKey = tuple[str, int, int]
_SAMPLE_STRUCTS: dict[_SampleKey, struct.Struct] = {}
# a sample's fields after its Header: (alignment of its first field, struct format from there)
_IMU_BODY = (8, f"{len(_IMU_HEAD)}sd{_IMU_TAIL.size}s")  # the constant head, angular_velocity.z, the tail
_SAMPLE_BODIES = {
    "imu": _IMU_BODY,
    "range": (1, "B"),  # radiation_type, then (aligned to 4) the five floats: see _sample_struct
    "gps": (8, "3d"),
    "fire": (4, "i"),  # track_id, then (aligned to 8) the four doubles
}


def _sample_struct(kind: str, start: int, frame_len: int) -> struct.Struct:
    """One whole sample (its std_msgs/Header, the padding, its fields) as one :class:`struct.Struct`,
    for a sample whose bytes begin at an index ``start`` (only ``start % 8`` matters) with a frame_id
    of ``frame_len`` bytes (NUL included): the padding :func:`_header` and :func:`pad` add, as ``x``
    bytes (zeros), at the same places. Pack it with (sec, nanosec, frame_len, frame, *fields)."""
    key = (kind, start & 7, frame_len)
    st = _SAMPLE_STRUCTS.get(key)
    if st is not None:
        return st
    i = align4(start)  # the Header's stamp
    fmt = f"<{i - start}xiII{frame_len}s"
    i += 12 + frame_len
    align, body = _SAMPLE_BODIES[kind]
    j = align8(i) if align == 8 else align4(i) if align == 4 else i
    fmt += f"{j - i}x{body}"
    if kind == "range":  # radiation_type (1 byte), then the float32 run aligned to 4
        k = align4(j + 1)
        fmt += f"{k - j - 1}x5f"
    elif kind == "fire":  # track_id (4 bytes), then the doubles aligned to 8
        k = align8(j + 4)
        fmt += f"{k - j - 4}x4d"
    st = _SAMPLE_STRUCTS[key] = struct.Struct(fmt)
    return st


def write_sensor_bundle(b: WorldBundle, gyro_sigma_radps: float) -> bytes:
    """``b`` as the CDR bytes of its SensorBundle (fire_world_sim's test_sensor_bundle_writer.py: ``reference_bundle_msg``).

    ``gyro_sigma_radps``: the gyro's noise, reported as ``angular_velocity_covariance[8]`` (its
    square). Values out of a field's range raise (struct.error), as rclpy's message setters do.
    Each sample is one ``pack`` of a struct that holds its padding (:func:`_sample_struct`): the
    bytes of :func:`_header` and :func:`~fire_uav_common.cdr.pad` field by field, in fewer calls
    (the world node writes a bundle per UAV on the lockstep's serial path).
    """
    buf = bytearray(ENCAPSULATION)
    _header(buf, b.stamp_ns, _MAP)
    buf.append(b.uav_id)
    pad(buf, 4)
    buf += U32.pack(b.step)
    pad(buf, 8)
    buf += _F64.pack(b.control_period_s)
    own = f"uav_{b.uav_id}".encode() + b"\x00"
    n_own, n_map = len(own), len(_MAP)
    # angular_velocity_covariance (var at [8]), linear_acceleration (0), its covariance (-1: none)
    imu_tail = _IMU_TAIL.pack(*([0.0] * 8), gyro_sigma_radps**2, 0.0, 0.0, 0.0, -1.0, *([0.0] * 8))
    ns = _NS_PER_S
    _count(buf, len(b.gyro))
    for g in b.gyro:
        t = g.stamp_ns
        if t < 0:
            raise CdrError(f"stamp must be >= 0 ns, got {t}")
        buf += _sample_struct("imu", len(buf), n_own).pack(
            t // ns, t % ns, n_own, own, _IMU_HEAD, float(g.omega_z_radps), imu_tail
        )
    _count(buf, len(b.altimeter))
    for a in b.altimeter:
        t = a.stamp_ns
        if t < 0:
            raise CdrError(f"stamp must be >= 0 ns, got {t}")
        buf += _sample_struct("range", len(buf), n_own).pack(
            t // ns, t % ns, n_own, own, RANGE_ULTRASOUND,
            RANGE_FIELD_OF_VIEW_RAD, 0.0, float(a.max_range_m), float(a.range_m), 0.0,
        )  # fmt: skip
    _count(buf, len(b.gps))
    for p in b.gps:
        t = p.stamp_ns
        if t < 0:
            raise CdrError(f"stamp must be >= 0 ns, got {t}")
        buf += _sample_struct("gps", len(buf), n_map).pack(
            t // ns, t % ns, n_map, _MAP, float(p.x_m), float(p.y_m), float(p.variance_m2)
        )
    _count(buf, len(b.fires))
    for f in b.fires:
        t = f.stamp_ns
        if t < 0:
            raise CdrError(f"stamp must be >= 0 ns, got {t}")
        buf += _sample_struct("fire", len(buf), n_map).pack(
            t // ns, t % ns, n_map, _MAP, int(f.track_id),
            float(f.x_m), float(f.y_m), float(f.extent_m), float(f.range_m),
        )  # fmt: skip
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


# --- reading (the agents) ---------------------------------------------------------------------------
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

_STEP = struct.Struct("<I")
_IMU_DOUBLES = 4 + 9 + 3 + 9 + 3 + 9  # orientation, its covariance, angular velocity, ...
_IMU_OMEGA_Z = 8 * (4 + 9 + 2)  # [B] offset of angular_velocity.z in the Imu's doubles
_RANGE_RANGE = 4 * 3  # [B] offset of ``range`` in the Range's float32 run after radiation_type
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

    The arrays: gyro (t_s, omega_z), altimeter (t_s, range),
    GPS (t_s, x, y) with its variances, fires (t_s, x, y, extent), and the raster cells (x, y as
    float64 from their float32, states as int64), or None if the cell arrays are empty or unequal.
    Raises :class:`CdrError` naming what is wrong.
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
                raise CdrError(f"SensorBundle {what} length {k} runs past the end of {n} bytes")
            return k, i + 4

        # the samples' headers read inline (as _sample_header: this loop runs ~12 times a bundle)
        stamp_at, u32_at, ns = _STAMP.unpack_from, U32.unpack_from, _NS_PER_S

        def frame_end(i: int, what: str) -> int:
            """The index after the frame_id whose length is at ``i`` (read_string_end's check)."""
            (m,) = u32_at(data, i)
            end = i + 4 + m
            if m < 1 or end > n:
                raise CdrError(f"{what} length {m} does not fit in {n} bytes")
            return end

        k, i = count(align4(i), "gyro", _MIN_SAMPLE_BYTES)
        gyro = []
        f64_at = _F64.unpack_from
        for _ in range(k):
            i = (i + 3) & ~3
            t_sec, t_nsec = stamp_at(data, i)
            i = frame_end(i + 8, "Imu header.frame_id")
            i = ((i + 3) & ~7) + 4  # align8
            gyro.append(((t_sec * ns + t_nsec) / ns, f64_at(data, i + _IMU_OMEGA_Z)[0]))
            i += 8 * _IMU_DOUBLES
        k, i = count(align4(i), "altimeter", _MIN_SAMPLE_BYTES)
        alt = []
        f32_at = _F32.unpack_from
        for _ in range(k):
            i = (i + 3) & ~3
            t_sec, t_nsec = stamp_at(data, i)
            i = frame_end(i + 8, "Range header.frame_id")
            i = (i + 4) & ~3  # align4, after radiation_type
            alt.append(((t_sec * ns + t_nsec) / ns, f32_at(data, i + _RANGE_RANGE)[0]))
            i += 4 * 5
        k, i = count(align4(i), "gps", _MIN_SAMPLE_BYTES)
        gps, gps_var = [], []
        gps_at = _GPS.unpack_from
        for _ in range(k):
            i = (i + 3) & ~3
            t_sec, t_nsec = stamp_at(data, i)
            i = frame_end(i + 8, "GpsFix header.frame_id")
            i = ((i + 3) & ~7) + 4  # align8
            x, y, var = gps_at(data, i)
            gps.append(((t_sec * ns + t_nsec) / ns, x, y))
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
        raise CdrError(f"SensorBundle truncated: {n} bytes") from None
    if n not in (i, align4(i)):  # DDS delivers the payload padded to 4 bytes (serialize_message does not)
        raise CdrError(f"SensorBundle of {n} bytes: {n - i} bytes left after vehicle_status")
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
