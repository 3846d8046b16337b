"""The perimeter monitor's error family: every error the package raises itself is a
:class:`MonitorError`, with a one-line message naming what is wrong.

Each subclass also derives from the builtin its callers have always caught (``ValueError``,
``RuntimeError``), so an ``except ValueError`` written before the family existed still catches it.
"""

from __future__ import annotations

__all__ = ["ConfigError", "InputError", "MonitorError", "SequenceError"]


class MonitorError(Exception):
    """Base of the perimeter monitor's own errors."""


class ConfigError(MonitorError, ValueError):
    """A monitor, map or synthetic-fire setting is out of range (cell size, speed, alpha, ...)."""


class InputError(MonitorError, ValueError):
    """Data handed to the monitor is malformed: non-finite positions, arrays of unequal length,
    a peer's perimeter summary missing a field."""


class SequenceError(MonitorError, RuntimeError):
    """A call out of order (a waypoint asked for before any update)."""
