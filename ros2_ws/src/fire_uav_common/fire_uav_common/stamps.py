"""Stamp conversions, the one place: sim time as integer nanoseconds, seconds, control steps.

Sim time is carried as integer nanoseconds wherever stamps are compared (exact), and as float
seconds in the algorithms. A message stamp (``builtin_interfaces/Time``) is any object with
``sec`` and ``nanosec``; :func:`to_time_msg` builds one when given the class, so this module
stays free of ROS imports. Step ``k`` of a lockstep mission is stamped ``(k + 1) * period``:
the stamp is the end of the control period the step covers (docs/protocol.md).
"""

from __future__ import annotations

from typing import Any, Protocol, TypeVar

from .errors import ArgumentError

__all__ = [
    "NS_PER_S",
    "ns_to_s",
    "s_to_ns",
    "stamp_to_ns",
    "stamp_to_s",
    "stamp_to_step",
    "step_to_ns",
    "to_time_msg",
]

NS_PER_S = 1_000_000_000


class _Stamp(Protocol):
    sec: int
    nanosec: int


T = TypeVar("T")


def s_to_ns(t_s: float) -> int:
    """Seconds -> integer nanoseconds, rounded to the nearest nanosecond."""
    return int(round(t_s * NS_PER_S))


def ns_to_s(t_ns: int) -> float:
    """Integer nanoseconds -> seconds."""
    return t_ns / NS_PER_S


def stamp_to_ns(stamp: _Stamp | Any) -> int:
    """``builtin_interfaces/Time`` -> integer nanoseconds (exact)."""
    return int(stamp.sec) * NS_PER_S + int(stamp.nanosec)


def stamp_to_s(stamp: _Stamp | Any) -> float:
    """``builtin_interfaces/Time`` -> seconds."""
    return ns_to_s(stamp_to_ns(stamp))


def to_time_msg(t_ns: int, time_cls: type[T]) -> T:
    """Integer nanoseconds -> a ``time_cls(sec=..., nanosec=...)`` (``builtin_interfaces.msg.Time``).

    Negative times are refused: ROS stamps are unsigned in their nanoseconds part and a
    negative sim time means a caller mixed up an offset.
    """
    t_ns = int(t_ns)
    if t_ns < 0:
        raise ArgumentError(f"stamp must be >= 0 ns, got {t_ns}")
    sec, nanosec = divmod(t_ns, NS_PER_S)
    return time_cls(sec=sec, nanosec=nanosec)  # type: ignore[call-arg]


def step_to_ns(step: int, period_ns: int) -> int:
    """Stamp [ns] of lockstep step ``step`` (the end of its control period)."""
    return (int(step) + 1) * int(period_ns)


def stamp_to_step(stamp_ns: int, period_ns: int) -> int:
    """Lockstep step whose stamp is ``stamp_ns``, with control period ``period_ns``.

    Rounds to the nearest step, so a stamp a few nanoseconds off (a float round trip) still maps
    to its step. Raises ``ValueError`` for a period that is not positive.
    """
    if period_ns <= 0:
        raise ArgumentError(f"control period must be > 0 ns, got {period_ns}")
    return int(round(stamp_ns / period_ns)) - 1
