"""The ``fire_uav_msgs/UavState`` codec: an agent writes its state (with its fire picture), its
peers (and the in-process harness) read it, from the same bytes.

Why bytes: an agent receives 19 states a step at 20 UAVs. ``rclpy.serialization.deserialize_message``
builds a Python ``UavState`` for each (its ``__init__`` first fills every field and sub-message
with defaults, which the C conversion then replaces), and the agent uses a few fields of it.
Reading those fields with ``struct`` skips that (docs/profile.md). It is the same information:
every decoded field is compared against ``deserialize_message`` on generated messages, the bytes
:func:`write_uav_state` writes against ``serialize_message`` of the same message
(fire_uav_agent's test_uav_state_codec.py), and the field lists of ``UavState.msg`` /
``FireEstimate.msg`` are pinned there, so a change to the message fails that test instead of
being misread here.

The encoding is the one the fleet sends: XCDR1 little-endian, as rmw_fastrtps serialises ROS 2
messages (its layout rules: :mod:`fire_uav_common.cdr`). Anything else (another encapsulation,
bytes that do not end exactly with the 32-byte ``auth`` field) raises
:class:`~fire_uav_common.cdr.CdrError`; the node then re-serialises what rclpy reads of them (any
encoding rclpy reads) and reads that, or counts the bytes as undecodable. The reader is more
lenient than rclpy in one way: it does not decode ``header.frame_id``, so it does not refuse one
that is not UTF-8 (the agent never reads it, and a signed state's bytes are covered by its tag).
:func:`write_uav_state` leaves ``auth`` zero: ``fire_uav_common.auth`` signs the bytes.

ROS-free.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields
from typing import Any

from ..cdr import ENCAPSULATION, U32, CdrError, align4, align8, check_encapsulation, pad, read_string_end

__all__ = [
    "FIREESTIMATE_FIELDS",
    "UAVSTATE_FIELDS",
    "FireEntry",
    "PeerFires",
    "PeerState",
    "WireState",
    "read_uav_state",
    "read_uav_state_checked",
    "write_uav_state",
]


@dataclass(frozen=True)
class FireEntry:
    """One fire estimate as exchanged in UavState.fires (FireEstimate.msg), units in names."""

    fire_id: int
    active: bool
    x_m: float
    y_m: float
    extent_m: float
    vx_mps: float = 0.0
    vy_mps: float = 0.0
    last_measurement_s: float = 0.0  # sim time of the newest measurement fused in
    front_x_m: float = math.nan
    front_y_m: float = math.nan
    max_spread_rate_mps: float = 0.0


@dataclass(frozen=True)
class PeerState:
    """A peer's UavState as the agent uses it, ROS-free. Positions [m; map], yaw [rad]."""

    uav_id: int
    sequence: int
    step: int
    x_m: float
    y_m: float
    z_m: float
    yaw_rad: float
    objective: int
    target_fire_id: int = -1
    water_kg: float = 0.0
    centroid_x_m: float = math.nan
    centroid_y_m: float = math.nan

    def finite(self) -> bool:
        """No NaN or infinity in the pose and water. Kept once computed (in ``__dict__``, beside
        the frozen fields, not one of them): every receiver of one state asks (the in-process
        harness hands the same object to all N - 1 peers)."""
        f = self.__dict__.get("_finite")
        if f is None:
            isf = math.isfinite  # one test per field, no generator (called for every peer state received)
            f = isf(self.x_m) and isf(self.y_m) and isf(self.z_m) and isf(self.yaw_rad) and isf(self.water_kg)
            self.__dict__["_finite"] = f
        return f


@dataclass(frozen=True)
class PeerFires:
    """A peer's fire picture (UavState.fires, fires_sequence), ROS-free; its own loss draw and count."""

    uav_id: int
    sequence: int
    step: int
    fires: tuple[FireEntry, ...] = ()

    def finite(self) -> bool:
        """No NaN or infinity in any fire's fields; kept once computed, as :meth:`PeerState.finite`."""
        ok = self.__dict__.get("_finite")
        if ok is None:
            isf = math.isfinite
            ok = True
            for f in self.fires:  # a loop, not all() over a generator: asked of every picture received
                if not (
                    isf(f.x_m) and isf(f.y_m) and isf(f.extent_m) and isf(f.vx_mps) and isf(f.vy_mps)
                    and isf(f.last_measurement_s)
                ):  # fmt: skip
                    ok = False
                    break
            self.__dict__["_finite"] = ok
        return ok


#: UavState.msg and FireEstimate.msg as this reader expects them (name, ROS type), in order
UAVSTATE_FIELDS = (
    ("header", "std_msgs/Header"), ("uav_id", "uint8"), ("sequence", "uint32"), ("step", "uint32"),
    ("x_m", "double"), ("y_m", "double"), ("z_m", "double"), ("yaw_rad", "double"),
    ("covariance", "double[16]"), ("objective", "uint8"), ("target_fire_id", "int32"),
    ("water_kg", "float"), ("centroid_x_m", "double"), ("centroid_y_m", "double"),
    ("alive_peers", "sequence<uint8>"), ("crashed_peers", "sequence<uint8>"),
    ("packets_received", "uint32"), ("packets_lost", "uint32"), ("packets_rejected", "uint32"),
    ("sent_per_topic", "sequence<uint16>"), ("final", "boolean"), ("fires_sequence", "uint32"),
    ("fires", "sequence<fire_uav_msgs/FireEstimate>"), ("auth", "uint8[32]"),
)  # fmt: skip
FIREESTIMATE_FIELDS = (
    ("fire_id", "uint32"), ("status", "uint8"), ("x_m", "double"), ("y_m", "double"),
    ("extent_m", "double"), ("vx_mps", "double"), ("vy_mps", "double"),
    ("last_measurement", "builtin_interfaces/Time"), ("front_x_m", "double"),
    ("front_y_m", "double"), ("max_spread_rate_mps", "double"),
)  # fmt: skip

_STATUS_ACTIVE = 0  # FireEstimate.STATUS_ACTIVE
_STATUS_EXTINGUISHED = 1  # FireEstimate.STATUS_EXTINGUISHED
_AUTH_BYTES = 32
_NS_PER_S = 1_000_000_000
_IDS = struct.Struct("<II")  # sequence, step
_POSE = struct.Struct("<4d")  # x, y, z, yaw; the 16 covariance doubles follow (not read)
_OBJECTIVE_TAIL = struct.Struct("<if")  # target_fire_id, water_kg
_CENTROID = struct.Struct("<2d")
_COUNTERS = struct.Struct("<3I")  # packets received, lost, rejected (not read: the peer's own)
_FIRE_HEAD = struct.Struct("<IB")  # fire_id, status
# x, y, extent, vx, vy, last_measurement (sec, nanosec), front x, y, max spread rate
_FIRE_BODY = struct.Struct("<5diI3d")
_FIRE_MIN_BYTES = _FIRE_HEAD.size + _FIRE_BODY.size  # a FireEstimate without its alignment padding


@dataclass(frozen=True, slots=True)
class WireState:
    """What an agent takes from a peer's UavState: the lockstep fields and the two inbox items."""

    uav_id: int
    step: int
    sent_per_topic: tuple[int, ...]
    final: bool
    state: PeerState
    fires: PeerFires


# --- the fast reading: one unpack for the fixed fields, one per fire, the objects built directly ----
_HEADS: dict[int, struct.Struct] = {}  # header.frame_id length (NUL included) -> _head_struct(k)
_HEADS_KEPT = 16  # frame ids of so many lengths kept (the fleet sends one: "map")
# a FireEstimate whose fire_id is at a payload index 8m (phase 0) or 8m + 4 (phase 4): fire_id,
# status, the padding to the next 8-byte boundary, x, y, extent, vx, vy, last_measurement (sec,
# nanosec), front x, y, max spread rate
_FIRE_AT_PHASE = (struct.Struct("<IB3x5diI3d"), struct.Struct("<IB7x5diI3d"))


def _head_struct(k: int) -> struct.Struct:
    """The fields from ``uav_id`` to ``alive_peers``' length of a UavState whose frame id takes ``k``
    bytes, as one little-endian Struct read at index 16 + k: the alignment padding of
    :func:`read_uav_state_checked` (the same ``align4`` / ``align8``) written as pad bytes."""
    s = _HEADS.get(k)
    if s is None:
        at = 16 + k  # uav_id
        ids = align4(at + 1)  # sequence, step
        pose = align8(ids + 8)  # x, y, z, yaw, then the 16 covariance doubles (skipped)
        objective = pose + 20 * 8
        tail = align4(objective + 1)  # target_fire_id, water_kg
        centroid = align8(tail + 8)  # then alive_peers' uint32 length at centroid + 16
        s = struct.Struct(
            f"<B{ids - at - 1}xII{pose - ids - 8}x4d128xB{tail - objective - 1}xif{centroid - tail - 8}x2dI"
        )
        if len(_HEADS) < _HEADS_KEPT:
            _HEADS[k] = s
    return s


def _builder(cls: type) -> Callable[[tuple], Any]:
    """``build(values)``: an instance of the frozen dataclass ``cls`` with its fields set to
    ``values`` (every field, in order), as its ``__init__`` leaves it (none of these classes has a
    ``__post_init__``), written into its ``__dict__`` without the ``object.__setattr__`` per field
    a frozen ``__init__`` pays (~3x faster at 12 fields). Generated as dataclasses generates
    ``__init__``, so a field added to the class is one more the builder sets."""
    names = tuple(f.name for f in fields(cls))
    lines = "".join(f"    d[{name!r}] = values[{i}]\n" for i, name in enumerate(names))
    namespace: dict[str, Any] = {"new": object.__new__, "cls": cls}
    exec(f"def build(values):\n    obj = new(cls)\n    d = obj.__dict__\n{lines}    return obj\n", namespace)
    return namespace["build"]


_fire_entry, _peer_state, _peer_fires = _builder(FireEntry), _builder(PeerState), _builder(PeerFires)


def read_uav_state(data: bytes | bytearray | memoryview) -> WireState:
    """A serialised ``fire_uav_msgs/UavState`` (as received raw) -> :class:`WireState`.

    Raises :class:`CdrError` naming what is wrong: not XCDR1 little-endian, truncated, a length that
    runs past the end, or bytes left after the ``auth`` field. The values are the message's, as
    ``deserialize_message`` would give them (``water_kg`` is the float32 widened exactly; the fire's
    ``last_measurement`` is seconds as ``stamps.stamp_to_s`` computes them).

    The same reading as :func:`read_uav_state_checked` with fewer Python steps (at 30 UAVs an agent
    reads 29 states a step): the fixed fields in one ``unpack_from`` (:func:`_head_struct`), a fire
    in one, the objects built without their frozen ``__init__`` (:func:`_builder`). Bytes it does not
    take as they are (any length or position check that fails, a truncation) are read again by
    :func:`read_uav_state_checked`, which raises the error that names them.
    """
    n = len(data)
    if data[0:2] != b"\x00\x01" or n < 20:
        return read_uav_state_checked(data)
    try:
        (k,) = U32.unpack_from(data, 12)  # header.frame_id's length, after the stamp
        if k < 1 or 16 + k > n:
            return read_uav_state_checked(data)
        head = _head_struct(k)
        uav_id, sequence, step, x, y, z, yaw, objective, target, water, cx, cy, m = head.unpack_from(
            data, 16 + k
        )
        i = align4(16 + k + head.size + m)  # past alive_peers (uint8[], not read)
        (m,) = U32.unpack_from(data, i)
        i = align4(i + 4 + m) + 12  # past crashed_peers and the three packet counters (not read)
        (m,) = U32.unpack_from(data, i)
        i += 4
        if i + 2 * m > n:
            return read_uav_state_checked(data)
        sent = struct.unpack_from(f"<{m}H", data, i)
        i += 2 * m
        final = data[i]
        fires_sequence, m = _IDS.unpack_from(data, align4(i + 1))
        i = align4(i + 1) + 8
        if i + _FIRE_MIN_BYTES * m > n:
            return read_uav_state_checked(data)
        fires = []
        for _ in range(m):
            i = align4(i)
            f = _FIRE_AT_PHASE[(i - 4) >> 2 & 1]  # i - 4 is 0 or 4 mod 8
            fire_id, status, fx, fy, ext, vx, vy, t_sec, t_nsec, frx, fry, rate = f.unpack_from(data, i)
            i += f.size
            t_s = (t_sec * _NS_PER_S + t_nsec) / _NS_PER_S
            fires.append(
                _fire_entry((fire_id, status == _STATUS_ACTIVE, fx, fy, ext, vx, vy, t_s, frx, fry, rate))
            )
    except (struct.error, IndexError):
        return read_uav_state_checked(data)
    if i + _AUTH_BYTES != n:
        return read_uav_state_checked(data)
    state = _peer_state((uav_id, sequence, step, x, y, z, yaw, objective, target, water, cx, cy))
    picture = _peer_fires((uav_id, fires_sequence, step, tuple(fires)))
    return WireState(uav_id, step, sent, bool(final), state, picture)  # type: ignore[arg-type]


def read_uav_state_checked(data: bytes | bytearray | memoryview) -> WireState:
    """:func:`read_uav_state` field by field, each length and position checked as it is read: the
    reading the fast one falls back to, whose errors name what is wrong."""
    n = len(data)
    check_encapsulation(data, "UavState")
    try:
        i = read_string_end(data, 12, "UavState header.frame_id")  # after the stamp (sec, nanosec)
        uav_id = data[i]
        i = align4(i + 1)
        sequence, step = _IDS.unpack_from(data, i)
        i = align8(i + 8)
        x, y, z, yaw = _POSE.unpack_from(data, i)
        i += 20 * 8  # the pose and the 4x4 covariance
        objective = data[i]
        i = align4(i + 1)
        target, water = _OBJECTIVE_TAIL.unpack_from(data, i)
        i = align8(i + 8)
        cx, cy = _CENTROID.unpack_from(data, i)
        i += 16
        for _ in range(2):  # alive_peers, crashed_peers: uint8[] (not read: the peer's own view)
            (k,) = U32.unpack_from(data, i)
            i += 4 + k
            i = align4(i)
        i += _COUNTERS.size
        (k,) = U32.unpack_from(data, i)
        i += 4
        if i + 2 * k > n:
            raise CdrError(f"sent_per_topic length {k} runs past the end of {n} bytes")
        sent = struct.unpack_from(f"<{k}H", data, i)
        i += 2 * k
        final = data[i]
        i = align4(i + 1)
        fires_sequence, k = _IDS.unpack_from(data, i)
        i += 8
        if i + _FIRE_MIN_BYTES * k > n:
            raise CdrError(f"fires length {k} runs past the end of {n} bytes")
        fires = []
        for _ in range(k):
            i = align4(i)
            fire_id, status = _FIRE_HEAD.unpack_from(data, i)
            i = align8(i + 5)
            fx, fy, ext, vx, vy, t_sec, t_nsec, frx, fry, rate = _FIRE_BODY.unpack_from(data, i)
            i += _FIRE_BODY.size
            t_s = (t_sec * _NS_PER_S + t_nsec) / _NS_PER_S
            fires.append(
                FireEntry(fire_id, status == _STATUS_ACTIVE, fx, fy, ext, vx, vy, t_s, frx, fry, rate)
            )
    except (struct.error, IndexError):
        raise CdrError(f"UavState truncated: {n} bytes") from None
    if i + _AUTH_BYTES != n:
        raise CdrError(
            f"UavState of {n} bytes: expected its auth field to end at byte {n}, not {i + _AUTH_BYTES}"
        )
    state = PeerState(uav_id, sequence, step, x, y, z, yaw, objective, target, water, cx, cy)
    return WireState(
        uav_id, step, sent, bool(final), state, PeerFires(uav_id, fires_sequence, step, tuple(fires))
    )


# --- writing ----------------------------------------------------------------------------------------
_STAMP = struct.Struct("<iI")
_U8 = struct.Struct("<B")
_POSE_COV = struct.Struct("<20d")  # x, y, z, yaw and the 4x4 covariance
_MAP = b"map\x00"


def write_uav_state(
    *,
    stamp_ns: int,
    uav_id: int,
    sequence: int,
    step: int,
    pose: Sequence[float],
    covariance: Sequence[float],
    objective: int,
    target_fire_id: int,
    water_kg: float,
    centroid_xy: tuple[float, float],
    alive_peers: Sequence[int],
    crashed_peers: Sequence[int],
    packets: tuple[int, int, int],
    sent_per_topic: Sequence[int],
    final: bool,
    fires_sequence: int,
    fires: Sequence[FireEntry],
) -> bytes:
    """A UavState as CDR bytes, ``auth`` zero (to be signed); ``header.frame_id`` is ``map``.

    ``stamp_ns``: the header stamp [ns] (the bundle stamp the state answers); ``pose``: x, y, z [m],
    yaw [rad]; ``covariance``: its 16 values, row-major; ``packets``: received, lost, rejected. A
    fire's ``last_measurement_s`` is written as a stamp of whole nanoseconds (0 when negative or
    not finite), ``active`` as status ACTIVE / EXTINGUISHED. Values out of a field's range raise,
    as rclpy's message setters do.
    """
    if stamp_ns < 0:
        raise CdrError(f"UavState stamp must be >= 0 ns, got {stamp_ns}")
    if len(pose) != 4 or len(covariance) != 16:
        raise CdrError(
            f"UavState pose needs 4 values and covariance 16, got {len(pose)} and {len(covariance)}"
        )
    buf = bytearray(ENCAPSULATION)
    buf += _STAMP.pack(*divmod(int(stamp_ns), _NS_PER_S))
    buf += U32.pack(len(_MAP)) + _MAP
    buf += _U8.pack(uav_id)
    pad(buf, 4)
    buf += _IDS.pack(sequence, step)
    pad(buf, 8)
    buf += _POSE_COV.pack(*(float(v) for v in pose), *(float(v) for v in covariance))
    buf += _U8.pack(objective)
    pad(buf, 4)
    buf += _OBJECTIVE_TAIL.pack(target_fire_id, float(water_kg))
    pad(buf, 8)
    buf += _CENTROID.pack(float(centroid_xy[0]), float(centroid_xy[1]))
    for ids in (alive_peers, crashed_peers):
        pad(buf, 4)
        buf += U32.pack(len(ids)) + bytes(int(j) for j in ids)
    pad(buf, 4)
    buf += _COUNTERS.pack(*packets)
    buf += U32.pack(len(sent_per_topic)) + struct.pack(f"<{len(sent_per_topic)}H", *sent_per_topic)
    buf += _U8.pack(bool(final))
    pad(buf, 4)
    buf += _IDS.pack(fires_sequence, len(fires))
    for f in fires:
        pad(buf, 4)
        buf += _FIRE_HEAD.pack(f.fire_id, _STATUS_ACTIVE if f.active else _STATUS_EXTINGUISHED)
        pad(buf, 8)
        t = f.last_measurement_s
        t_ns = round(max(0.0, t) * _NS_PER_S) if math.isfinite(t) else 0
        sec, nsec = divmod(t_ns, _NS_PER_S)
        buf += _FIRE_BODY.pack(
            f.x_m,
            f.y_m,
            f.extent_m,
            f.vx_mps,
            f.vy_mps,
            sec,
            nsec,
            f.front_x_m,
            f.front_y_m,
            f.max_spread_rate_mps,
        )
    buf += bytes(_AUTH_BYTES)
    return bytes(buf)
