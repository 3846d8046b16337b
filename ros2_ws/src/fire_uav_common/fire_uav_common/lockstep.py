"""The lockstep fault schedule: which agent is offline at which step, known to everyone in advance.

Why a schedule (docs/protocol.md "Lockstep"): in lockstep the world waits for every live agent's
command and every agent waits for its live peers' messages, with no wall-clock timeout, so a slow
agent only makes the run slower. A killed or frozen agent must then be taken out of those waits
at a step that does not depend on when the signal lands. The supervisor's faults (``--kill``,
``--freeze``) are therefore written as a schedule that the world and every agent receive as a
parameter; each converts it to steps with :func:`first_step_at` and stops waiting for agent K
exactly from the first step of its window. The supervisor delivers the signal later (two steps
into the window, when K has nothing left to send), so the signal changes nothing the fleet sees.

An agent that dies *unscheduled* is detected by DDS discovery (its publishers disappear once its
participant's lease expires); that step depends on wall time, so such a run is not reproducible,
and the world logs it.

Format: ``"K@T1:T2;K@T1"``: agent K offline from sim time T1 [s] to T2 [s] (a freeze; it resumes
at T2), or from T1 on (a kill). Offline from step ``first_step_at(T1)`` to ``first_step_at(T2) - 1``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import ScheduleError

__all__ = ["OfflineWindow", "first_step_at", "format_schedule", "offline_uavs", "parse_schedule"]


@dataclass(frozen=True)
class OfflineWindow:
    """Agent ``uav_id`` is offline from sim time ``start_s`` to ``end_s`` (``inf``: for good)."""

    uav_id: int
    start_s: float
    end_s: float = math.inf

    def steps(self, period_s: float) -> tuple[int, float]:
        """(first offline step, first step back online or ``inf``) for control period ``period_s``."""
        end = math.inf if math.isinf(self.end_s) else first_step_at(self.end_s, period_s)
        return first_step_at(self.start_s, period_s), end

    def offline_at(self, step: int, period_s: float) -> bool:
        """Whether the agent is offline during lockstep step ``step``."""
        s1, s2 = self.steps(period_s)
        return s1 <= step < s2


def first_step_at(t_s: float, period_s: float) -> int:
    """The first step ``k`` whose start time ``k * period_s`` is at or after ``t_s``."""
    if not period_s > 0:
        raise ScheduleError(f"control period must be > 0 s, got {period_s}")
    return max(0, math.ceil(t_s / period_s - 1e-9))


def parse_schedule(text: str) -> tuple[OfflineWindow, ...]:
    """Parse ``"K@T1:T2;K@T1"`` (see the module doc); ``""`` is the empty schedule.

    Raises ``ValueError`` naming the entry that is wrong.
    """
    out = []
    for raw in (p.strip() for p in text.split(";")):
        if not raw:
            continue
        try:
            uid_s, times = raw.split("@")
            uid = int(uid_s)
            if ":" in times:
                t1_s, t2_s = times.split(":")
                t1, t2 = float(t1_s), float(t2_s)
            else:
                t1, t2 = float(times), math.inf
        except ValueError:
            raise ScheduleError(f"offline schedule entry {raw!r}: expected K@T1:T2 or K@T1") from None
        if uid < 0 or not math.isfinite(t1) or t1 < 0 or not t2 > t1 or math.isnan(t2):
            raise ScheduleError(f"offline schedule entry {raw!r}: need K >= 0, 0 <= T1 < T2 (finite T1)")
        out.append(OfflineWindow(uid, t1, t2))
    return tuple(sorted(out, key=lambda w: (w.start_s, w.uav_id, w.end_s)))


def format_schedule(windows: tuple[OfflineWindow, ...] | list[OfflineWindow]) -> str:
    """The inverse of :func:`parse_schedule` (exact for the floats ``repr`` prints)."""
    parts = []
    for w in windows:
        parts.append(f"{w.uav_id}@{w.start_s!r}" + ("" if math.isinf(w.end_s) else f":{w.end_s!r}"))
    return ";".join(parts)


def offline_uavs(windows: tuple[OfflineWindow, ...], step: int, period_s: float) -> frozenset[int]:
    """Agents that the schedule takes offline during step ``step``."""
    return frozenset(w.uav_id for w in windows if w.offline_at(step, period_s))
