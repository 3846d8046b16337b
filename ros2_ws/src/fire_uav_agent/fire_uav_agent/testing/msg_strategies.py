"""Hypothesis strategies for the message fields of the codec tests (``test/test_*codec*.py``).

Floats of both widths with NaN and infinities (the codecs must carry every bit pattern), the
integer widths of the message fields, ``builtin_interfaces/Time`` stamps, and frame ids of every
length mod 8 up to ``max_size`` so that every CDR alignment rule after a string is exercised.
Test support only (hypothesis is a test dependency): the node never imports it.
"""

from __future__ import annotations

from builtin_interfaces.msg import Time
from hypothesis import strategies as st

__all__ = ["f32", "f64", "frame_ids", "i32", "stamps", "u8", "u16", "u32"]

f64 = st.floats(allow_nan=True, allow_infinity=True)
f32 = st.floats(width=32, allow_nan=True, allow_infinity=True)
u8, u16, u32 = st.integers(0, 255), st.integers(0, 65535), st.integers(0, 2**32 - 1)
i32 = st.integers(-(2**31), 2**31 - 1)
#: header stamps: ``sec`` over the whole int32 range (the codecs read it signed)
stamps = st.builds(Time, sec=i32, nanosec=st.integers(0, 999_999_999))


def frame_ids(max_size: int) -> st.SearchStrategy[str]:
    """ASCII frame ids without NUL, 0..max_size characters."""
    return st.text(st.characters(codec="ascii", exclude_characters="\x00"), max_size=max_size)
