"""``fire_uav_common.cdr``: the alignment rules against their definition, and the two checks.

The definition (OMG DDS-XTypes 1.3, 7.4.1, XCDR1): a primitive of size ``a`` starts at a payload
offset that is a multiple of ``a``; the payload starts after the 4-byte encapsulation header, so
index ``i`` of the bytes is payload offset ``i - 4``. The wire codecs' tests compare whole
messages with rclpy; these pin the helpers on their own.
"""

from __future__ import annotations

import pytest
from fire_uav_common.cdr import ENCAPSULATION, align4, align8, check_encapsulation, pad, read_string_end


def _next_aligned(i: int, a: int) -> int:
    """The smallest index j >= i whose payload offset j - 4 is a multiple of a (brute force)."""
    j = i
    while (j - 4) % a:
        j += 1
    return j


@pytest.mark.parametrize("i", range(4, 60))
def test_alignment_is_relative_to_the_payload(i):
    assert align4(i) == _next_aligned(i, 4)
    assert align8(i) == _next_aligned(i, 8)


@pytest.mark.parametrize("n", range(4, 30))
@pytest.mark.parametrize("a", [1, 2, 4, 8])
def test_pad_appends_zeros_up_to_the_next_boundary(n, a):
    buf = bytearray(b"\x07" * n)
    pad(buf, a)
    assert len(buf) == _next_aligned(n, a)
    assert buf[n:] == bytes(len(buf) - n)


def test_the_encapsulation_is_checked_and_named_exactly():
    check_encapsulation(ENCAPSULATION + b"\x01", "X")
    check_encapsulation(b"\x00\x01", "X")  # the identifier; a missing payload is the reader's error
    for data, shown in (
        (b"\x00\x00\x00\x00", "0000"),
        (b"\x01\x01", "0101"),
        (b"\x00", "00"),
        (b"", "missing"),
    ):
        with pytest.raises(ValueError) as e:
            check_encapsulation(data, "UavState")
        assert str(e.value) == f"UavState: not XCDR1 little-endian CDR (encapsulation {shown})"


def test_a_string_is_skipped_by_its_length_and_must_fit():
    data = ENCAPSULATION + (4).to_bytes(4, "little") + b"map\x00"
    assert read_string_end(data, 4, "frame") == len(data)  # ending exactly at the end fits
    assert read_string_end(data + b"\x05", 4, "frame") == len(data)
    with pytest.raises(ValueError) as e:
        read_string_end(data[:-1], 4, "Imu header.frame_id")
    assert str(e.value) == "Imu header.frame_id length 4 does not fit in 11 bytes"
    with pytest.raises(ValueError) as e:  # a CDR string holds at least its NUL
        read_string_end(ENCAPSULATION + bytes(4), 4, "frame")
    assert str(e.value) == "frame length 0 does not fit in 8 bytes"
