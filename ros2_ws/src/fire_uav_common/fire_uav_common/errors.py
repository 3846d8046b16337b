"""The shared package's error family: every error fire_uav_common raises itself is a
:class:`CommonError`, raised early with a one-line message naming what is wrong.

Each subclass also derives from the builtin its callers have always caught (``ValueError``,
``KeyError``, ``RuntimeError``), so code written before the family existed still catches it.
"""

from __future__ import annotations

__all__ = [
    "ArgumentError",
    "CommonError",
    "ExecutorAwaitError",
    "ExecutorError",
    "FleetKeyError",
    "ScenarioError",
    "ScheduleError",
    "TopicError",
    "UnknownTopicError",
]


class CommonError(Exception):
    """Base of fire_uav_common's own errors."""


class ScenarioError(CommonError, ValueError):
    """A scenario file is missing, unreadable or invalid; the message names file and field."""


class ArgumentError(CommonError, ValueError):
    """A value outside what a function accepts (a negative stamp, seed or count, a zero sigma)."""


class FleetKeyError(CommonError, ValueError):
    """A fleet key, or the bytes given to sign, are not what the HMAC scheme needs."""


class ScheduleError(CommonError, ValueError):
    """A lockstep offline schedule entry or a control period is malformed."""


class TopicError(CommonError, ValueError):
    """A topic spec, QoS kind or per-vehicle name used wrongly."""


class UnknownTopicError(CommonError, KeyError):
    """A topic name that no spec of :mod:`fire_uav_common.topics` matches."""


class ExecutorError(CommonError, ValueError):
    """The lean executor asked for something it does not do (several nodes, service clients, an
    unknown ``FIRE_UAV_EXECUTOR``); rclpy's executor does it."""


class ExecutorAwaitError(CommonError, RuntimeError):
    """A callback coroutine awaited something on the lean executor, where nothing would wake it."""
