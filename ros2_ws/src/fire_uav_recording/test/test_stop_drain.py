"""The recorder's stop rule (``fire_uav_recording.stop_drain``), with no ROS and no timing: the
queues, the clock and the wait are simulated, and the world's messages are real CDR bytes.

The case that lost a bag's last ``/world/truth``: the world's final truth reaches the recorder
after a gap longer than the old quiet period (a held-up recorder, a repaired sample). Once the
world has announced its end (MISSION_COMPLETE), the drain must wait for that truth, and only up
to its cap; without an announced end it keeps the quiet rule.
"""

from __future__ import annotations

import struct

import pytest
from fire_uav_common.cdr import CdrError
from fire_uav_common.constants import EventType
from fire_uav_recording.stop_drain import MissionEndWatch, drain, header_stamp_ns

QUIET_S = 0.1
CAP_S = 2.0


def _header(stamp_ns: int, frame_id: str = "map") -> bytes:
    sec, nanosec = divmod(stamp_ns, 1_000_000_000)
    name = frame_id.encode() + b"\0"
    return b"\x00\x01\x00\x00" + struct.pack("<iI", sec, nanosec) + struct.pack("<I", len(name)) + name


def event_cdr(kind: int, stamp_ns: int, frame_id: str = "map") -> bytes:
    """A MissionEvent's CDR up to and past its type (the watch reads no further)."""
    return _header(stamp_ns, frame_id) + bytes([kind]) + b"\0" * 40


def truth_cdr(stamp_ns: int) -> bytes:
    return _header(stamp_ns) + b"\0" * 32


class Line:
    """A simulated subscription side: messages due at simulated wall times, a clock, and a wait
    that returns at the first arrival (as a wait set does) or at its timeout."""

    def __init__(self, arrivals: list[tuple[float, str, bytes]], wait_works: bool = True) -> None:
        self.now = 0.0
        self.pending = sorted(arrivals, key=lambda a: a[0])
        self.handed: list[tuple[str, bytes]] = []
        self.watch = MissionEndWatch()
        self.waits: list[float] = []
        self.wait_works = wait_works

    def clock(self) -> float:
        return self.now

    def take_all(self, stop) -> bool:
        while self.pending and self.pending[0][0] <= self.now:
            if stop():
                return True
            _, topic, data = self.pending.pop(0)
            self.handed.append((topic, data))
            if topic == "/world/events":
                self.watch.on_event(data)
            elif topic == "/world/truth":
                self.watch.on_truth(data)
        return False

    def wait(self, timeout_s: float) -> bool:
        self.waits.append(timeout_s)
        if not self.wait_works:
            return False
        due = self.pending[0][0] if self.pending else float("inf")
        # a real clock moves on even for a wait of 0 (float sums here may not: 0.6 - 0.5 < 0.1)
        self.now = min(self.now + max(timeout_s, 1e-9), max(self.now, due))
        return True

    def run(self, **kw) -> bool:
        return drain(
            self.take_all,
            lambda: len(self.handed),
            kw.pop("cap_wall_s", CAP_S),
            quiet_wall_s=QUIET_S,
            wait=kw.pop("wait", self.wait),
            expecting=self.watch.missing,
            clock=self.clock,
            **kw,
        )


S = 1_000_000_000
END = 60 * S  # the final step's stamp


def test_the_final_truth_after_a_long_gap_is_waited_for():
    """MISSION_COMPLETE is in, its truth comes 0.5 s later (five quiet periods): it is taken."""
    line = Line(
        [
            (0.0, "/world/truth", truth_cdr(END - S // 10)),
            (0.0, "/world/events", event_cdr(EventType.MISSION_COMPLETE, END)),
            (0.5, "/world/truth", truth_cdr(END)),
        ]
    )
    assert line.run() is True
    assert [t for t, _ in line.handed].count("/world/truth") == 2
    assert line.watch.missing() is None
    assert line.now == pytest.approx(0.5 + QUIET_S)  # then the quiet gap after it, no more


def test_the_old_quiet_rule_alone_would_have_ended_before_it():
    """The same arrivals with no announced end (the event not recorded): the quiet rule ends the
    drain at 0.1 s and the final truth is left behind -- what the announcement fixes."""
    line = Line([(0.0, "/world/truth", truth_cdr(END - S // 10)), (0.5, "/world/truth", truth_cdr(END))])
    assert line.run() is True
    assert len(line.handed) == 1 and line.now == pytest.approx(QUIET_S)


def test_a_final_truth_that_never_comes_ends_at_the_cap_and_is_named():
    line = Line(
        [
            (0.0, "/world/truth", truth_cdr(END - S // 10)),
            (0.0, "/world/events", event_cdr(EventType.MISSION_COMPLETE, END)),
        ]
    )
    assert line.run() is False
    assert line.now == pytest.approx(CAP_S)
    missing = line.watch.missing()
    assert missing is not None and "t = 60.000 s" in missing and "t = 59.900 s" in missing


def test_other_arrivals_wake_the_wait_but_do_not_end_it():
    """/fleet/state keeps trickling in every 0.05 s after the end; the drain goes on until the
    final truth, woken by each arrival (no fixed-period poll)."""
    trickle = [(0.05 * k, "/fleet/state", b"\x00\x01\x00\x00") for k in range(1, 20)]
    line = Line(
        [
            (0.0, "/world/events", event_cdr(EventType.MISSION_COMPLETE, END)),
            (1.2, "/world/truth", truth_cdr(END)),
        ]
        + trickle
    )
    assert line.run() is True
    assert ("/world/truth", truth_cdr(END)) in line.handed
    assert all(w <= CAP_S for w in line.waits)
    assert len(line.waits) >= 19  # one wake per arrival


def test_with_nothing_announced_it_ends_after_the_quiet_gap():
    line = Line([(0.0, "/fleet/state", b"\x00\x01\x00\x00"), (0.05, "/fleet/state", b"\x00\x01\x00\x00")])
    assert line.run() is True
    assert len(line.handed) == 2 and line.now == pytest.approx(0.05 + QUIET_S)


def test_publishers_that_go_on_are_cut_at_the_cap():
    line = Line([(0.01 * k, "/tf", b"\x00\x01\x00\x00") for k in range(1000)])
    assert line.run() is False
    assert line.now == pytest.approx(CAP_S, abs=0.011)


def test_cancelled_cuts_it_short():
    line = Line(
        [
            (0.0, "/world/events", event_cdr(EventType.MISSION_COMPLETE, END)),
            (1.0, "/world/truth", truth_cdr(END)),
        ]
    )
    assert line.run(cancelled=lambda: line.now >= 0.3) is False
    assert line.watch.missing() is not None


def test_without_a_wait_one_pass_decides():
    """After the context is shut down nothing can wait: one pass, done unless something is expected."""
    line = Line([(0.0, "/fleet/state", b"\x00\x01\x00\x00")])
    assert line.run(wait=None) is True and len(line.handed) == 1 and line.now == 0.0
    line = Line([(0.0, "/world/events", event_cdr(EventType.MISSION_COMPLETE, END))])
    assert line.run(wait=None) is False and line.now == 0.0
    line = Line([(0.0, "/world/events", event_cdr(EventType.MISSION_COMPLETE, END))], wait_works=False)
    assert line.run() is False and line.waits == [CAP_S]  # it tried once, then gave up


def test_the_watch_reads_the_event_type_after_any_frame_id():
    w = MissionEndWatch()
    w.on_event(event_cdr(EventType.DROP, END, frame_id="a_longer_frame"))
    assert not w.ended
    w.on_event(event_cdr(EventType.MISSION_COMPLETE, END, frame_id="a_longer_frame"))
    assert w.end_stamp_ns == END
    w.on_truth(truth_cdr(END + S))  # a later truth also settles it
    assert w.missing() is None


def test_the_watch_reads_rclpys_bytes():
    """The bytes rclpy serialises for a MissionEvent and a WorldTruth read as their fields say."""
    pytest.importorskip("rclpy")
    from builtin_interfaces.msg import Time
    from fire_uav_msgs.msg import MissionEvent, WorldTruth
    from rclpy.serialization import serialize_message
    from std_msgs.msg import Header

    stamp = Time(sec=61, nanosec=250_000_000)
    ev = MissionEvent(header=Header(stamp=stamp, frame_id="map"), type=EventType.MISSION_COMPLETE, detail="x")
    w = MissionEndWatch()
    w.on_event(serialize_message(ev))
    assert w.end_stamp_ns == 61_250_000_000
    assert w.missing() is not None
    w.on_truth(serialize_message(WorldTruth(header=Header(stamp=stamp, frame_id="map"), step=612)))
    assert w.last_truth_ns == 61_250_000_000 and w.missing() is None


def test_bad_bytes_are_counted_not_raised():
    w = MissionEndWatch()
    w.on_event(b"\x00\x01\x00\x00\x01")
    w.on_truth(b"")
    w.on_event(b"\x01\x00\x00\x00" + b"\0" * 30)  # big-endian: not the CDR the fleet writes
    assert w.unreadable == 3 and not w.ended
    with pytest.raises(CdrError, match="WorldTruth"):
        header_stamp_ns(b"\x00\x01\x00\x00\x00", "WorldTruth")


# --- edges named by the mutation run (docs/testing.md) ----------------------------------------------
def test_the_stamp_needs_only_the_encapsulation_and_the_stamp_and_names_the_message():
    assert header_stamp_ns(_header(END)[:12], "WorldTruth") == END  # 4 + int32 sec + uint32 nanosec
    with pytest.raises(CdrError, match="^WorldTruth: 11 bytes, too short for a header stamp$"):
        header_stamp_ns(_header(END)[:11], "WorldTruth")
    with pytest.raises(CdrError, match="^MissionEvent: not XCDR1 little-endian"):
        header_stamp_ns(b"\x01\x00\x00\x00" + _header(END)[4:], "MissionEvent")


def test_an_event_cut_right_after_its_frame_id_is_counted_not_raised():
    w = MissionEndWatch()
    w.on_event(_header(END))  # no type byte
    assert w.unreadable == 1 and not w.ended


def test_the_missing_line_says_when_no_truth_was_written_at_all():
    w = MissionEndWatch()
    w.on_event(event_cdr(EventType.MISSION_COMPLETE, END))
    assert w.missing() == (
        "the world's final /world/truth (t = 60.000 s, announced by MISSION_COMPLETE on /world/events); "
        "the last one written: none"
    )


def test_the_quiet_wait_never_runs_past_the_cap():
    """A cap shorter than the quiet gap: the last wait is cut to what is left of the cap."""
    line = Line([(0.0, "/fleet/state", b"\x00\x01\x00\x00"), (0.03, "/fleet/state", b"\x00\x01\x00\x00")])
    assert line.run(cap_wall_s=0.05) is False
    assert len(line.handed) == 2 and line.now == pytest.approx(0.05)
    assert line.waits == [pytest.approx(0.05), pytest.approx(0.02)]
