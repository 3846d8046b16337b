"""The mission tools' error family: every error fire_mission raises itself is a
:class:`MissionError`, whose one-line message says what failed and why."""

from __future__ import annotations

__all__ = ["MissionError"]


class MissionError(RuntimeError):
    """A mission could not be started or supervised (message says what and why)."""
