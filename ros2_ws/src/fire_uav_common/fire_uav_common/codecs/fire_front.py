"""The ``fire_uav_msgs/FireFront`` codec: an agent writes its picture of a raster fire's front, its
peers (and the in-process harness) read it, from the same bytes.

One conversion in each direction, so that the node and the harness see the same numbers: cell
centres and spread rates travel as float32 (rounded to nearest, as rclpy rounds a float assigned
to a float32 field) and come back widened exactly to float64, observation times as float64, states
as uint8; the stamp is whole nanoseconds. The bytes :func:`write_fire_front` writes equal
``serialize_message`` of the same message (less the trailing bytes of the quirk below), and :func:`read_fire_front` gives the values
``deserialize_message`` gives (fire_uav_agent's test_perimeter_front_codecs.py, which also pins the field list of
``FireFront.msg``). The reader does not require the five arrays to have one length (the message
does not either); the agent refuses unequal ones.

The encoding is XCDR1 little-endian (the rules: :mod:`fire_uav_common.cdr`). The reader also
accepts one quirk of Fast CDR's (:func:`_empty_doubles_tail`), which the writer does not copy: a
bag reader such as rosbags refuses those trailing bytes. Other bytes (another encapsulation, truncated, bytes left
after ``spread_rate_mps`` beyond that quirk's) raise
:class:`~fire_uav_common.cdr.CdrError`. ``header.frame_id`` is not decoded. ROS-free.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

import numpy as np

from ..cdr import ENCAPSULATION, U32, CdrError, align4, align8, check_encapsulation, pad, read_string_end

__all__ = ["FIREFRONT_FIELDS", "WireFront", "read_fire_front", "write_fire_front"]

#: FireFront.msg as this codec expects it (name, ROS type), in order
FIREFRONT_FIELDS = (
    ("header", "std_msgs/Header"), ("uav_id", "uint8"), ("sequence", "uint32"),
    ("cell_size_m", "float"), ("x_m", "sequence<float>"), ("y_m", "sequence<float>"),
    ("state", "sequence<uint8>"), ("observed_s", "sequence<double>"),
    ("spread_rate_mps", "sequence<float>"),
)  # fmt: skip

_NS_PER_S = 1_000_000_000
_STAMP = struct.Struct("<iI")
_SEQ_CELL = struct.Struct("<If")  # sequence, cell_size_m
_U8 = struct.Struct("<B")
_MAP = b"map\x00"


@dataclass(frozen=True)
class WireFront:
    """A FireFront's fields, ROS-free: float64 arrays (centres and rates widened from float32),
    ``state`` as int64."""

    stamp_ns: int
    uav_id: int
    sequence: int
    cell_size_m: float
    x_m: np.ndarray
    y_m: np.ndarray
    state: np.ndarray
    observed_s: np.ndarray
    spread_rate_mps: np.ndarray


def write_fire_front(
    *,
    stamp_ns: int,
    uav_id: int,
    sequence: int,
    cell_size_m: float,
    x_m: object,
    y_m: object,
    state: object,
    observed_s: object,
    spread_rate_mps: object,
) -> bytes:
    """A FireFront as CDR bytes; ``header.frame_id`` is ``map``. Centres, rates and the cell size
    are written as float32, ``state`` as uint8 (values outside 0..255 raise), ``observed_s`` as
    float64."""
    if stamp_ns < 0:
        raise CdrError(f"FireFront stamp must be >= 0 ns, got {stamp_ns}")
    s = np.asarray(state).ravel()
    if s.size and (s.min() < 0 or s.max() > 255):
        raise CdrError(f"FireFront of uav {uav_id}: a state outside uint8 ({s.min()}..{s.max()})")
    buf = bytearray(ENCAPSULATION)
    buf += _STAMP.pack(*divmod(int(stamp_ns), _NS_PER_S))
    buf += U32.pack(len(_MAP)) + _MAP
    try:
        buf += _U8.pack(uav_id)
        pad(buf, 4)
        buf += _SEQ_CELL.pack(sequence, float(cell_size_m))
    except struct.error as err:
        raise CdrError(f"FireFront of uav {uav_id}: a field out of range: {err}") from None
    for xs in (x_m, y_m):
        v = np.asarray(xs, dtype="<f4").ravel()  # as rclpy: rounded to nearest float32
        buf += U32.pack(v.size) + v.tobytes()
    buf += U32.pack(s.size) + s.astype(np.uint8).tobytes()
    t = np.asarray(observed_s, dtype="<f8").ravel()
    pad(buf, 4)
    buf += U32.pack(t.size)
    if t.size:
        pad(buf, 8)
        buf += t.tobytes()
    r = np.asarray(spread_rate_mps, dtype="<f4").ravel()
    buf += U32.pack(r.size) + r.tobytes()
    # no trailing bytes after the last field, even where rclpy's serialize_message leaves some
    # (:func:`_empty_doubles_tail`): rosbags refuses a message with 4 or more trailing bytes, and
    # rclpy reads the exact form back
    return bytes(buf)


def _empty_doubles_tail(i: int) -> int:
    """Bytes Fast CDR adds at the end when ``observed_s`` (ending at index ``i``) is empty: it
    sizes the message as if the empty double sequence were aligned to 8, but writes no padding
    there, so the difference trails the last field (rclpy's ``serialize_message`` leaves whatever
    its buffer held there; these are zeros)."""
    return (align8(i) - i) % 8


def _array(
    data: bytes | bytearray | memoryview, i: int, field: str, dtype: str, size: int
) -> tuple[np.ndarray, int]:
    (k,) = U32.unpack_from(data, i)
    i += 4
    if size == 8 and k:
        i = align8(i)
    end = i + size * k
    if end > len(data):
        raise CdrError(f"FireFront {field} length {k} runs past the end of {len(data)} bytes")
    return np.frombuffer(bytes(data[i:end]), dtype=dtype), end


def read_fire_front(data: bytes | bytearray | memoryview) -> WireFront:
    """A serialised ``fire_uav_msgs/FireFront`` -> :class:`WireFront`.

    Raises :class:`CdrError` naming what is wrong: not XCDR1 little-endian, truncated, a length
    that runs past the end, or bytes left after the last field.
    """
    n = len(data)
    check_encapsulation(data, "FireFront")
    try:
        sec, nsec = _STAMP.unpack_from(data, 4)
        i = read_string_end(data, 12, "FireFront header.frame_id")
        uav_id = data[i]
        i = align4(i + 1)
        sequence, cell = _SEQ_CELL.unpack_from(data, i)
        i += _SEQ_CELL.size
        x, i = _array(data, i, "x_m", "<f4", 4)
        y, i = _array(data, i, "y_m", "<f4", 4)
        state, i = _array(data, i, "state", "u1", 1)
        t, i = _array(data, align4(i), "observed_s", "<f8", 8)
        tail = _empty_doubles_tail(i) if t.size == 0 else 0
        rate, i = _array(data, i, "spread_rate_mps", "<f4", 4)
    except (struct.error, IndexError):
        raise CdrError(f"FireFront truncated: {n} bytes") from None
    if n not in (i, i + tail):
        raise CdrError(f"FireFront of {n} bytes: expected its last field to end at byte {n}, not {i}")
    return WireFront(
        sec * _NS_PER_S + nsec, uav_id, sequence, cell, x.astype(float), y.astype(float),
        state.astype(np.int64), t.astype(float), rate.astype(float),
    )  # fmt: skip
