"""The ``fire_uav_msgs/PerimeterMap`` codec: a monitor writes its on-board fire map, its peers (and
the in-process harness) read it, from the same bytes.

One conversion in each direction, so that the node and the harness see the same numbers: the
per-bin arrays travel as float32 (rounded to nearest, as rclpy rounds a float assigned to a
float32 field) and come back widened exactly to float64; the stamp is whole nanoseconds. The bytes
:func:`write_perimeter_map` writes equal ``serialize_message`` of the same message, and
:func:`read_perimeter_map` gives the values ``deserialize_message`` gives (fire_uav_agent's
test_perimeter_front_codecs.py, which also pins the field list of ``PerimeterMap.msg``).

The encoding is XCDR1 little-endian (the rules: :mod:`fire_uav_common.cdr`). Other bytes (another
encapsulation, truncated, not ending exactly with the 32-byte ``auth`` field) raise
:class:`~fire_uav_common.cdr.CdrError`. ``header.frame_id`` is not decoded. The writer leaves
``auth`` zero: ``fire_uav_common.auth`` signs the bytes. ROS-free.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

import numpy as np

from ..cdr import ENCAPSULATION, U32, CdrError, align4, align8, check_encapsulation, pad, read_string_end

__all__ = ["PERIMETERMAP_FIELDS", "WirePerimeter", "read_perimeter_map", "write_perimeter_map"]

#: PerimeterMap.msg as this codec expects it (name, ROS type), in order
PERIMETERMAP_FIELDS = (
    ("header", "std_msgs/Header"), ("uav_id", "uint8"), ("sequence", "uint32"), ("fire_id", "int32"),
    ("center_x_m", "double"), ("center_y_m", "double"), ("outer_distance_m", "sequence<float>"),
    ("outer_visit_time_s", "sequence<float>"), ("spread_rate_mps", "sequence<float>"),
    ("importance", "sequence<float>"), ("direction", "uint8"), ("direction_changes", "uint32"),
    ("auth", "uint8[32]"),
)  # fmt: skip

_NS_PER_S = 1_000_000_000
_STAMP = struct.Struct("<iI")
_IDS = struct.Struct("<Ii")  # sequence, fire_id
_CENTER = struct.Struct("<2d")
_U8 = struct.Struct("<B")
_MAP = b"map\x00"
_AUTH_BYTES = 32


@dataclass(frozen=True)
class WirePerimeter:
    """A PerimeterMap's fields, ROS-free; the per-bin arrays are float64 (widened from float32)."""

    stamp_ns: int
    uav_id: int
    sequence: int
    fire_id: int
    center_x_m: float
    center_y_m: float
    outer_distance_m: np.ndarray
    outer_visit_time_s: np.ndarray
    spread_rate_mps: np.ndarray
    importance: np.ndarray
    direction: int
    direction_changes: int


def write_perimeter_map(
    *,
    stamp_ns: int,
    uav_id: int,
    sequence: int,
    fire_id: int,
    center_xy: tuple[float, float],
    outer_distance_m: object,
    outer_visit_time_s: object,
    spread_rate_mps: object,
    importance: object,
    direction: int,
    direction_changes: int,
) -> bytes:
    """A PerimeterMap as CDR bytes, ``auth`` zero (to be signed); ``header.frame_id`` is ``map``.

    ``stamp_ns``: the header stamp [ns]; the four per-bin arrays (any float sequences) are written
    as float32. Values out of a field's range raise :class:`CdrError` naming the field.
    """
    if stamp_ns < 0:
        raise CdrError(f"PerimeterMap stamp must be >= 0 ns, got {stamp_ns}")
    if not -(2**31) <= fire_id < 2**31:
        raise CdrError(f"PerimeterMap fire_id {fire_id} is out of int32")
    buf = bytearray(ENCAPSULATION)
    buf += _STAMP.pack(*divmod(int(stamp_ns), _NS_PER_S))
    buf += U32.pack(len(_MAP)) + _MAP
    try:
        buf += _U8.pack(uav_id)
        pad(buf, 4)
        buf += _IDS.pack(sequence, fire_id)
        pad(buf, 8)
        buf += _CENTER.pack(float(center_xy[0]), float(center_xy[1]))
        for xs in (outer_distance_m, outer_visit_time_s, spread_rate_mps, importance):
            v = np.asarray(xs, dtype="<f4").ravel()  # as rclpy: rounded to nearest float32
            buf += U32.pack(v.size) + v.tobytes()
        buf += _U8.pack(direction)
        pad(buf, 4)
        buf += U32.pack(direction_changes)
    except struct.error as err:
        raise CdrError(f"PerimeterMap of uav {uav_id}: a field out of range: {err}") from None
    buf += bytes(_AUTH_BYTES)
    return bytes(buf)


def _floats(data: bytes | bytearray | memoryview, i: int, field: str) -> tuple[np.ndarray, int]:
    (k,) = U32.unpack_from(data, i)
    end = i + 4 + 4 * k
    if end > len(data):
        raise CdrError(f"PerimeterMap {field} length {k} runs past the end of {len(data)} bytes")
    return np.frombuffer(bytes(data[i + 4 : end]), dtype="<f4").astype(float), end


def read_perimeter_map(data: bytes | bytearray | memoryview) -> WirePerimeter:
    """A serialised ``fire_uav_msgs/PerimeterMap`` -> :class:`WirePerimeter`.

    Raises :class:`CdrError` naming what is wrong: not XCDR1 little-endian, truncated, a length
    that runs past the end, or bytes left after the ``auth`` field.
    """
    n = len(data)
    check_encapsulation(data, "PerimeterMap")
    try:
        sec, nsec = _STAMP.unpack_from(data, 4)
        i = read_string_end(data, 12, "PerimeterMap header.frame_id")
        uav_id = data[i]
        i = align4(i + 1)
        sequence, fire_id = _IDS.unpack_from(data, i)
        i = align8(i + 8)
        cx, cy = _CENTER.unpack_from(data, i)
        i += _CENTER.size
        distance, i = _floats(data, i, "outer_distance_m")
        visit, i = _floats(data, i, "outer_visit_time_s")
        rate, i = _floats(data, i, "spread_rate_mps")
        importance, i = _floats(data, i, "importance")
        direction = data[i]
        i = align4(i + 1)
        (changes,) = U32.unpack_from(data, i)
        i += 4
    except (struct.error, IndexError):
        raise CdrError(f"PerimeterMap truncated: {n} bytes") from None
    if i + _AUTH_BYTES != n:
        raise CdrError(
            f"PerimeterMap of {n} bytes: expected its auth field to end at byte {n}, not {i + _AUTH_BYTES}"
        )
    return WirePerimeter(
        sec * _NS_PER_S + nsec, uav_id, sequence, fire_id, cx, cy, distance, visit, rate, importance,
        direction, changes,
    )  # fmt: skip
