"""The recording package's error family: every error it raises itself is a
:class:`RecordingError`, with a one-line message naming the path or the parameter."""

from __future__ import annotations

__all__ = ["EXIT_BAD_PARAMETER", "EXIT_BAG_ERROR", "BagError", "ConfigError", "RecordingError"]

EXIT_BAD_PARAMETER = 2  # a node's exit status on a bad parameter (the project's rule for bad input)
EXIT_BAG_ERROR = 1  # a node's exit status when a bag cannot be written or read (the output exists, ...)


class RecordingError(Exception):
    """Base of the recording package's own errors."""


class BagError(RecordingError):
    """A bag cannot be written or read; the message names the path and the problem (one line)."""


class ConfigError(RecordingError, ValueError):
    """A parameter of the recorder, the replay or the Foxglove bridge is invalid (the message
    names the parameter)."""


def one_line(text: object) -> str:
    """``text`` with every run of whitespace (newlines too) folded into one space."""
    return " ".join(str(text).split())
