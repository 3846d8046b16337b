"""The one exception of the recording package."""

from __future__ import annotations

__all__ = ["BagError"]


class BagError(Exception):
    """A bag cannot be written or read; the message names the path and the problem (one line)."""


def one_line(text: object) -> str:
    """``text`` with every run of whitespace (newlines too) folded into one space."""
    return " ".join(str(text).split())
