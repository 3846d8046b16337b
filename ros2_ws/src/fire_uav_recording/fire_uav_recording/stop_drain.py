"""The recorder's stop: what it still waits for, and when it is done waiting (no rclpy).

- :func:`drain` is the loop of
  :meth:`fire_uav_recording.raw_topics.RawTopicFollower.take_queued`: passes over the
  subscriptions, between them a wait that returns when a message may have come, until nothing
  is expected and nothing came for a quiet gap, or a cap. Pure: the passes, the wait and the
  clock are given, so its rule is tested without ROS and without timing.
- :class:`MissionEndWatch` says what is still expected: the world's final ``/world/truth``.

The world ends a mission with a ``MISSION_COMPLETE`` event on ``/world/events`` stamped with the
sim time of its final step, the step whose ``/world/truth`` it published just before
(``fire_world_sim.world``: the event is one of that step's). A recorder that has the event knows
the last truth message to expect, so at a stop it can wait for that message (it arrives by a
reliable topic, ``fire_uav_common.topics``) rather than for a quiet gap, and name it if it
never comes. Without the event (a run interrupted, a recorder stopped mid-mission) nothing is
known to be missing and the stop falls back on the quiet gap
(:meth:`fire_uav_recording.raw_topics.RawTopicFollower.take_queued`).

Both topics are read from their raw CDR bytes (``fire_uav_common.cdr``: XCDR1 little-endian,
``std_msgs/Header`` first: int32 sec, uint32 nanosec, the frame id string), only as far as
needed: the header stamp, and for an event the ``type`` byte after the frame id. Bytes that do
not read so are counted (``unreadable``) and otherwise ignored: a malformed message must not stop
a recording.
"""

from __future__ import annotations

import struct
import time
from collections.abc import Callable

from fire_uav_common.cdr import CdrError, check_encapsulation, read_string_end
from fire_uav_common.constants import EventType
from fire_uav_common.stamps import NS_PER_S

__all__ = ["MissionEndWatch", "drain", "header_stamp_ns"]

_STAMP = struct.Struct("<iI")  # builtin_interfaces/Time: int32 sec, uint32 nanosec, at index 4


def header_stamp_ns(data: bytes | bytearray | memoryview, what: str) -> int:
    """The ``header.stamp`` [ns, sim] of a message whose first field is a ``std_msgs/Header``
    (:class:`~fire_uav_common.cdr.CdrError` naming ``what`` if the bytes are too short or not CDR)."""
    check_encapsulation(data, what)
    if len(data) < 4 + _STAMP.size:
        raise CdrError(f"{what}: {len(data)} bytes, too short for a header stamp")
    sec, nanosec = _STAMP.unpack_from(data, 4)
    return sec * NS_PER_S + nanosec


def _event_type(data: bytes | bytearray | memoryview, what: str) -> int:
    """The ``type`` of a ``fire_uav_msgs/MissionEvent`` (the uint8 right after the header's frame id)."""
    end = read_string_end(data, 4 + _STAMP.size, f"{what} header.frame_id")
    if end >= len(data):
        raise CdrError(f"{what}: ends before its type field")
    return int(data[end])


class MissionEndWatch:
    """Follows ``/world/events`` and ``/world/truth`` as the recorder writes them.

    ``end_stamp_ns`` is the stamp of the ``MISSION_COMPLETE`` event (None until one came),
    ``last_truth_ns`` the latest ``/world/truth`` stamp written. :meth:`missing` says what is
    still expected: the final truth, once the end is announced and until a truth at or after it
    came.
    """

    def __init__(self) -> None:
        self.end_stamp_ns: int | None = None  # [ns, sim]
        self.last_truth_ns: int | None = None  # [ns, sim]
        self.unreadable = 0  # messages of either topic whose bytes did not read

    def on_event(self, data: bytes | bytearray | memoryview) -> None:
        """A ``/world/events`` message as written (raw CDR)."""
        try:
            stamp = header_stamp_ns(data, "MissionEvent")
            kind = _event_type(data, "MissionEvent")
        except (CdrError, struct.error):
            self.unreadable += 1
            return
        if kind == EventType.MISSION_COMPLETE:
            self.end_stamp_ns = stamp

    def on_truth(self, data: bytes | bytearray | memoryview) -> None:
        """A ``/world/truth`` message as written (raw CDR)."""
        try:
            stamp = header_stamp_ns(data, "WorldTruth")
        except CdrError:
            self.unreadable += 1
            return
        if self.last_truth_ns is None or stamp > self.last_truth_ns:
            self.last_truth_ns = stamp

    @property
    def ended(self) -> bool:
        """Whether the world has announced the end of its mission."""
        return self.end_stamp_ns is not None

    def missing(self) -> str | None:
        """What the recorder still expects (one line), or None: nothing known to be missing."""
        if self.end_stamp_ns is None:
            return None
        if self.last_truth_ns is not None and self.last_truth_ns >= self.end_stamp_ns:
            return None
        last = "none" if self.last_truth_ns is None else f"t = {self.last_truth_ns / NS_PER_S:.3f} s"
        return (
            f"the world's final /world/truth (t = {self.end_stamp_ns / NS_PER_S:.3f} s, announced by "
            f"MISSION_COMPLETE on /world/events); the last one written: {last}"
        )


def drain(
    take_all: Callable[[Callable[[], bool]], bool],
    handed: Callable[[], int],
    cap_wall_s: float,
    *,
    cancelled: Callable[[], bool] = lambda: False,
    quiet_wall_s: float,
    wait: Callable[[float], bool] | None = None,
    expecting: Callable[[], str | None] = lambda: None,
    clock: Callable[[], float] = time.monotonic,
) -> bool:
    """Take what is queued until nothing is expected and the subscriptions are quiet; whether it
    ended so (True) rather than cut short by ``cap_wall_s`` or ``cancelled()`` (False).

    ``take_all(stop)`` takes every queue until it is empty, asking ``stop()`` before each message
    (True: it was stopped). ``handed()`` counts the messages handed over so far, however taken.
    ``wait(timeout_s)`` blocks until a message may have come or ``timeout_s`` [s, wall] passed
    (False: it cannot wait any more, e.g. the ROS context is gone). ``expecting()`` names what
    is still expected (:meth:`MissionEndWatch.missing`) or None. ``clock()`` [s, wall].

    The rule: after each pass, done if nothing is expected and nothing has come for
    ``quiet_wall_s`` (a message sent just before its publisher stopped may be on its way); while
    something is expected, wait for it (any arrival wakes the wait) up to the cap. Without a wait
    a single pass decides: done if nothing is expected.
    """
    t0 = clock()
    end = t0 + cap_wall_s
    last, seen = t0, handed()

    def stop() -> bool:
        return clock() >= end or cancelled()

    while True:
        if take_all(stop):
            return False
        now = clock()
        if handed() != seen:
            seen, last = handed(), now
        if now >= end or cancelled():
            return False
        quiet_left = quiet_wall_s - (now - last)
        expected = expecting()
        if expected is None and (wait is None or quiet_left <= 0):
            return True
        if wait is None:
            return False  # something is expected and nothing can wait for it
        # nothing expected: wait out the quiet gap; else wait until it comes (any arrival wakes)
        if not wait(end - now if expected is not None else min(end - now, quiet_left)):
            wait = None  # it cannot wait any more: one more pass decides
