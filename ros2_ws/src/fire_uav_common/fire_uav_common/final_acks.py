"""A publisher's last messages reach its readers: the wait before a node exits (no rclpy).

A reliable DDS writer repairs a lost sample only while it lives, and notices the loss of its
*last* sample only at its next heartbeat (3 s in Fast DDS). A process that exits right after its
last publish can so take messages with it that a reader held up (a recorder on a busy machine)
has not got yet, and nothing in the reader brings them back (docs/recording.md, "Stopping").
So the world, at the end of its mission, and an agent, when it is signalled, exit only once
every matched reader has acknowledged every message of their publishers
(``rclpy.publisher.Publisher.wait_for_all_acked``, which waits only for readers still matched:
a reader whose process is gone stops counting when DDS drops it at the end of its lease), or
after a cap, with one warning naming the topics still waited for.

- :class:`FinalAckWait` is that rule, asked again and again (the world asks from a steady timer,
  so its node keeps spinning meanwhile); :func:`wait_for_final_acks` asks it in a loop (an
  agent, after its spin has ended). Both take what is pending as topic names and the wall clock
  as numbers, so the rule is tested without ROS and without timing; the rclpy side is
  ``fire_uav_common.ros_io.unacked_topics``.
- :func:`published_line` is the agent's exit line: how many messages it published per topic
  (what a reader such as the recorder should have, for the topics only it publishes on).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass

from .errors import ArgumentError

__all__ = [
    "FINAL_ACK_CAP_WALL_S",
    "FINAL_ACK_POLL_WALL_S",
    "AckOutcome",
    "FinalAckWait",
    "published_line",
    "wait_for_final_acks",
]

#: [s wall] the longest a node waits at its end for every reader to acknowledge its messages (a
#: recorder held up at the end, at load ~40 on 2 cores, acknowledged after 6-7.5 s: repairs go at
#: the writer's heartbeat, every 3 s)
FINAL_ACK_CAP_WALL_S = 20.0
#: [s wall] how often it asks meanwhile (the acknowledgements come on DDS threads)
FINAL_ACK_POLL_WALL_S = 0.02


@dataclass(frozen=True)
class AckOutcome:
    """How a final wait ended: ``pending`` names the topics whose messages some matched reader had
    not acknowledged (sorted; empty: all were), after ``waited_wall_s`` [s wall]; ``cut_short``:
    ended by a second signal, not by the acknowledgements or the cap."""

    pending: tuple[str, ...]
    waited_wall_s: float
    cut_short: bool = False

    @property
    def acked(self) -> bool:
        """Whether every reader acknowledged every message."""
        return not self.pending

    def line(self) -> str:
        """One log line: a warning's text when something is pending, else an info's."""
        if self.acked:
            return f"exiting: every reader has acknowledged every message ({self.waited_wall_s:.2f} s)"
        when = "at a second signal " if self.cut_short else ""
        return (
            f"exiting {when}with messages not acknowledged after {self.waited_wall_s:.1f} s on "
            f"{list(self.pending)}: a reader of those topics (a frozen or killed process?) may lack "
            "the last of them"
        )


class FinalAckWait:
    """The rule of the final wait, started at ``start_wall_s`` [s wall]: go on while a topic is
    pending, for at most ``cap_wall_s`` [s wall]."""

    def __init__(self, start_wall_s: float, cap_wall_s: float = FINAL_ACK_CAP_WALL_S) -> None:
        if not cap_wall_s >= 0.0:  # NaN too
            raise ArgumentError(f"cap_wall_s must be >= 0, not {cap_wall_s!r}")
        self.start_wall_s = float(start_wall_s)
        self.cap_wall_s = float(cap_wall_s)

    def check(
        self, pending: Iterable[str], now_wall_s: float, *, cut_short: bool = False
    ) -> AckOutcome | None:
        """None: wait on (something is ``pending`` and the cap is not reached, nor ``cut_short``);
        else how the wait ended."""
        topics = tuple(sorted(set(pending)))
        waited = max(0.0, now_wall_s - self.start_wall_s)
        if topics and waited < self.cap_wall_s and not cut_short:
            return None
        return AckOutcome(topics, waited, cut_short=bool(topics) and cut_short and waited < self.cap_wall_s)


def wait_for_final_acks(
    pending: Callable[[], Iterable[str]],
    *,
    cap_wall_s: float = FINAL_ACK_CAP_WALL_S,
    poll_wall_s: float = FINAL_ACK_POLL_WALL_S,
    cancelled: Callable[[], bool] = lambda: False,
    clock: Callable[[], float] = time.monotonic,
    sleep: Callable[[float], object] = time.sleep,
) -> AckOutcome:
    """Ask ``pending()`` (the topics not acknowledged yet) every ``poll_wall_s`` until nothing is
    pending, ``cap_wall_s`` has passed or ``cancelled()`` (e.g. a second signal); never sleeps past
    the cap. ``clock()`` and ``sleep(s)`` [s wall]."""
    if not poll_wall_s > 0.0:
        raise ArgumentError(f"poll_wall_s must be > 0, not {poll_wall_s!r}")
    rule = FinalAckWait(clock(), cap_wall_s)
    while True:
        now = clock()
        outcome = rule.check(pending(), now, cut_short=cancelled())
        if outcome is not None:
            return outcome
        sleep(min(poll_wall_s, max(0.0, rule.start_wall_s + rule.cap_wall_s - now)))


def published_line(counts: Mapping[str, int]) -> str:
    """``published: /a 3, /b 0`` (topics sorted; ``published: nothing`` without publishers): the
    messages a node published per topic, as it logs them at its exit."""
    if not counts:
        return "published: nothing"
    return "published: " + ", ".join(f"{t} {int(n)}" for t, n in sorted(counts.items()))
