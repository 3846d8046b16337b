"""The CDR layout the fleet's hot messages are read and written in without rclpy's message objects.

The codecs (:mod:`fire_uav_common.codecs`: ``sensor_bundle``, ``uav_state``) use these rules; each
is checked against ``rclpy.serialization`` in its tests (docs/profile.md).

The encoding is XCDR1 little-endian (``PLAIN_CDR``), the one rmw_fastrtps serialises ROS 2 messages
in: a 4-byte encapsulation header ``00 01 00 00``, then the fields in order, each primitive aligned
to its own size (at most 8) relative to the first byte after that header (OMG DDS-XTypes 1.3,
7.4.1; OMG CORBA 3.3 part 2, 9.3). A sequence or a string is a uint32 count (a string's includes
its NUL) followed by its elements; a fixed array is its elements; a nested message is its fields.
Indices here count from the start of the bytes, header included, so the 8-byte boundaries of the
payload fall at indices 4 + 8k.

ROS-free.
"""

from __future__ import annotations

import struct

__all__ = [
    "ENCAPSULATION",
    "U32",
    "CdrError",
    "align4",
    "align8",
    "check_encapsulation",
    "pad",
    "read_string_end",
]

ENCAPSULATION = b"\x00\x01\x00\x00"  # XCDR1 (PLAIN_CDR) little-endian, no options
U32 = struct.Struct("<I")


class CdrError(ValueError):
    """Bytes that are not the CDR encoding a codec reads (truncated, a length past the end, another
    encapsulation); the message names the type and the field."""


def align4(i: int) -> int:
    """Index ``i`` rounded up to a 4-byte boundary (the payload starts at index 4, itself one)."""
    return (i + 3) & ~3


def align8(i: int) -> int:
    """Index ``i`` rounded up to an 8-byte boundary of the payload (indices 4, 12, 20, ...)."""
    return ((i + 3) & ~7) + 4


def pad(buf: bytearray, alignment: int) -> None:
    """Append the zero bytes that bring ``buf`` (header included) to ``alignment`` in the payload."""
    k = (4 - len(buf)) % alignment
    if k:
        buf += bytes(k)


def check_encapsulation(data: bytes | bytearray | memoryview, what: str) -> None:
    """:class:`CdrError` unless ``data`` starts with the XCDR1 little-endian identifier (shorter data, too:
    its slice differs; a header without a payload then fails its reader as truncated)."""
    if data[0:2] != ENCAPSULATION[0:2]:
        raise CdrError(
            f"{what}: not XCDR1 little-endian CDR (encapsulation {bytes(data[0:2]).hex() or 'missing'})"
        )


def read_string_end(data: bytes | bytearray | memoryview, i: int, what: str) -> int:
    """The index after the string whose uint32 length is at 4-aligned index ``i`` (not decoded)."""
    (k,) = U32.unpack_from(data, i)
    end = i + 4 + k
    if k < 1 or end > len(data):
        raise CdrError(f"{what} length {k} does not fit in {len(data)} bytes")
    return end
