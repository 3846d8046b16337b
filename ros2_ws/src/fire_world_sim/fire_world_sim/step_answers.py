"""The world's side of the lockstep (docs/protocol.md): which agents' answers a step waits for,
which answers are taken, and when bundles are sent again. Pure: no rclpy, no clock of its own.

The node publishes step k's bundles, then :meth:`AnswerGate.await_answers` names the agents it
waits for; each command and payload request that arrives goes through
:meth:`AnswerGate.admit_command` / :meth:`AnswerGate.admit_payload`, which return a
:class:`AnswerVerdict` (take it, drop it quietly, or reject it with a reason to count). The step runs
once :attr:`AnswerGate.complete`; :meth:`AnswerGate.take_inputs` hands over what was taken.

An agent whose process is gone is dropped from the wait (:meth:`AnswerGate.mark_lost`); an
answer that does not come within a while makes :meth:`AnswerGate.resend_due` name the agents
whose bundle is sent again. A copy of an answer the world asked for again is dropped quietly,
not counted as a rejection (:meth:`AnswerGate.second_answer`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from fire_uav_common.constants import PayloadAction
from fire_uav_common.stamps import NS_PER_S

from .vehicle import Command

__all__ = ["IGNORE", "TAKE", "AnswerGate", "AnswerVerdict"]

STAMP_OUT_OF_RANGE = "stamp out of range"
DUPLICATE = "duplicate"


@dataclass(frozen=True)
class AnswerVerdict:
    """What to do with one answer: ``take`` it, or drop it; ``rejection`` names why a dropped
    answer counts as rejected (None: dropped quietly, e.g. a copy the world asked for)."""

    take: bool
    rejection: str | None = None


TAKE = AnswerVerdict(True)
IGNORE = AnswerVerdict(False)


@dataclass
class AnswerGate:
    """Bookkeeping of the answers to one step at a time; ``lockstep`` False = realtime mode."""

    lockstep: bool
    started: bool = False  # step 0 ran (before it nothing is awaited, so nothing is rejected)
    finished: bool = False  # the mission is over: answers to its last bundle are not awaited
    awaited_ns: int = 0  # stamp the answers must carry (t_k of the next step)
    waiting: set[int] = field(default_factory=set)  # agents whose command is not in yet
    waiting_payload: set[int] = field(default_factory=set)  # ... whose payload request is not in yet
    lost: set[int] = field(default_factory=set)  # agents whose process is gone (not scheduled)
    commands: dict[int, Command | None] = field(default_factory=dict)  # taken this step
    payload: dict[int, list[int]] = field(default_factory=dict)  # actions taken this step
    seen_tags: set[bytes] = field(default_factory=set)  # tags taken this step: a replay is a duplicate
    sent: dict[int, bytes] = field(default_factory=dict)  # this step's bundles (serialised), to re-send
    sent_step: int = 0
    wait_since_ns: int = 0  # [steady ns] when this step's wait began
    resent_ns: int = 0  # [steady ns] when bundles were last re-sent
    asked_again: dict[int, int] = field(default_factory=dict)  # uav -> stamp whose bundle it got twice

    # --- the step's life cycle -------------------------------------------------------------------
    def take_inputs(self) -> tuple[dict[int, Command | None], dict[int, list[int]]]:
        """The commands and payload actions taken for the step about to run; starts the next."""
        taken = (self.commands, self.payload)
        self.commands, self.payload = {}, {}
        self.seen_tags.clear()
        return taken

    def start_sending(self, step: int) -> None:
        """Bundles of ``step`` are about to be published (:meth:`record_sent` each)."""
        self.sent, self.sent_step = {}, step

    def record_sent(self, uid: int, data: bytes) -> None:
        self.sent[uid] = data

    def await_answers(self, stamp_ns: int, awaited: set[int], now_ns: int) -> None:
        """Wait for the command and the payload request stamped ``stamp_ns`` of every agent in
        ``awaited`` whose process is not lost. Every awaited agent sends exactly one payload
        request per step (ACTION_NONE if nothing): a request on its own topic may arrive after
        the command, so it is waited for too."""
        self.awaited_ns = stamp_ns
        self.waiting = set(awaited) - self.lost
        self.waiting_payload = set(self.waiting)
        self.wait_since_ns = self.resent_ns = now_ns

    @property
    def complete(self) -> bool:
        """Every awaited command and payload request of this step is in."""
        return not self.waiting and not self.waiting_payload

    # --- admission ----------------------------------------------------------------------------
    def stamp_problem(self, crashed: bool, ns: int, world_t_ns: int) -> str | None:
        """Why an answer stamped ``ns`` for a vehicle (``crashed`` or not) cannot be taken now,
        or None; realtime takes any stamp up to the world's time ``world_t_ns``."""
        if crashed:
            return "crashed vehicle"
        if self.lockstep:
            if not self.started or ns != self.awaited_ns:
                return STAMP_OUT_OF_RANGE
        elif not 0 <= ns <= world_t_ns:
            return STAMP_OUT_OF_RANGE
        return None

    def second_answer(self, uid: int, ns: int, problem: str) -> bool:
        """True for the spare copy of an answer the world asked for again (not a rejection)."""
        return problem in (STAMP_OUT_OF_RANGE, DUPLICATE) and self.asked_again.get(uid) == ns

    def _refused(self, uid: int, ns: int, problem: str) -> AnswerVerdict:
        # before step 0 nothing is awaited yet, so nothing is a rejection
        if self.started and not self.second_answer(uid, ns, problem):
            return AnswerVerdict(False, problem)
        return IGNORE

    def admit_command(self, uid: int, ns: int, crashed: bool, world_t_ns: int) -> AnswerVerdict:
        """An unsigned command of vehicle ``uid`` stamped ``ns``."""
        if self.finished:
            return IGNORE  # the agents answer the mission's last bundle too: nothing waits for that
        problem = self.stamp_problem(crashed, ns, world_t_ns)
        return TAKE if problem is None else self._refused(uid, ns, problem)

    def admit_payload(
        self, uid: int, ns: int, crashed: bool, world_t_ns: int, tag: bytes | None
    ) -> AnswerVerdict:
        """A payload request of vehicle ``uid`` stamped ``ns`` that decoded and, if signed, carries
        the valid ``tag`` (None when unsigned)."""
        if self.finished:
            return IGNORE
        problem = self.stamp_problem(crashed, ns, world_t_ns)
        if problem is not None:
            return self._refused(uid, ns, problem)
        if uid not in self.waiting_payload and self.second_answer(uid, ns, DUPLICATE):
            return IGNORE  # a copy of requests already taken (the agent re-sends its step's answer)
        if tag is not None:
            if tag in self.seen_tags:
                return IGNORE if self.second_answer(uid, ns, DUPLICATE) else AnswerVerdict(False, DUPLICATE)
            self.seen_tags.add(tag)
        return TAKE

    def has_command(self, uid: int) -> bool:
        return uid in self.commands

    def record_command(self, uid: int, cmd: Command | None) -> None:
        """Take ``uid``'s command for this step (None: it was not finite, counted as missed)."""
        self.commands[uid] = cmd
        self.waiting.discard(uid)

    def record_payload(self, uid: int, action: int) -> None:
        """Take ``uid``'s payload request for this step (ACTION_NONE adds no action)."""
        if action != PayloadAction.NONE:
            self.payload.setdefault(uid, []).append(int(action))
        if self.lockstep:
            self.waiting_payload.discard(uid)

    # --- supervision ---------------------------------------------------------------------------
    def mark_lost(self, uid: int) -> None:
        """``uid``'s process is gone: no longer waited for, this step or any later one."""
        self.lost.add(uid)
        self.waiting.discard(uid)
        self.waiting_payload.discard(uid)

    def late(self) -> list[int]:
        """Agents sent a bundle this step whose command or payload request is not in."""
        return sorted((self.waiting | self.waiting_payload) & set(self.sent))

    def resend_due(self, now_ns: int, after_wall_s: float) -> list[int] | None:
        """None until ``after_wall_s`` [s wall] passed since the wait began or the last re-send;
        then the agents whose bundle is to be sent again (:meth:`late`), each remembered as asked
        again for this step's stamp."""
        if (now_ns - self.resent_ns) / NS_PER_S < after_wall_s:
            return None
        self.resent_ns = now_ns
        late = self.late()
        for uid in late:
            self.asked_again[uid] = self.awaited_ns
        return late
