"""The world simulation's error family: every error the package raises itself is a
:class:`WorldError`, raised early with a one-line message naming what is wrong.

Each subclass also derives from the builtin its callers have always caught (``ValueError``),
so an ``except ValueError`` written before the family existed still catches it.
"""

from __future__ import annotations

__all__ = ["ConfigError", "FireBehaviorError", "SequenceError", "WorldError"]


class WorldError(Exception):
    """Base of the world simulation's own errors."""


class ConfigError(WorldError, ValueError):
    """A world parameter or argument is invalid (bad uav_count, unknown fire model, ...)."""


class SequenceError(WorldError, ValueError):
    """A call out of order or repeated where it must be unique (time going back, two markers with
    one id): a bug in the caller, caught before it corrupts what the world reports."""


class FireBehaviorError(WorldError, ValueError):
    """A fire-behaviour input is invalid: an unknown fuel model code, a moisture or wind out of
    range, a malformed FMS moisture file."""
