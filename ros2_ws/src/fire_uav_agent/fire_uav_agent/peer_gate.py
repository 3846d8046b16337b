"""The agent's peer gate: what it lets in, what it waits for, and when it runs a step. ROS-free.

docs/protocol.md "Agent, on SensorBundle k", "Lockstep" and "Resend". The node hands every
sensor bundle and every peer message to :class:`PeerGate` and acts on the decisions it returns;
the in-process harness drives the same gate, so the lockstep rules have one implementation.

- **Admission** (:meth:`PeerGate.on_state`, :meth:`PeerGate.on_perimeter`,
  :meth:`PeerGate.on_front`): the sender id must be another fleet member, the step plausible for
  the step this agent last ran (:func:`step_verdict`), and the tag valid (the check is passed in,
  ``check_tag``; None: unsigned; fronts are never signed). A rejected message never reaches the
  lockstep wait: a forged state cannot make this agent wait for messages its claimed sender did
  not send.
- **Duplicates**: the first copy of each (sender, topic, step) is taken, later copies (a resent
  message) dropped (:class:`~fire_uav_agent.resend.ResendBook`).
- **The pending bundle and the lockstep wait**: a bundle of step k waits until every message the
  live peers sent at step k - 1 has arrived (:class:`~fire_uav_agent.lockstep_wait.PeerWait`); in
  realtime mode, and at step 0, it runs at once. Only the newest bundle is answered.
- **One inbox order** (:func:`inbox_order`): the peer messages of earlier steps are handed to the
  agent sorted by (step, sender, kind, sequence), whatever order they arrived in, because fusion
  may depend on the order it sees messages in.
- **Resend**: while blocked, ask each missing peer again (every ``ResendBook.ask_every_ns``); keep
  what this agent published for its last steps, to publish again when asked.

Wall time (steady-clock nanoseconds handed in) decides only *when* something happens (a resend
request, noticing that a peer's process is gone), never what the agent decides.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Generic, TypeVar

from fire_uav_common.lockstep import OfflineWindow
from fire_uav_common.topics import FLEET_FIRES_SPEC, FLEET_FRONT_SPEC, FLEET_PERIMETER_SPEC, FLEET_STATE_SPEC

from .agent_types import PeerPerimeter
from .errors import ConfigError
from .front_consensus import PeerFront
from .lockstep_wait import PeerWait
from .peer_link import PeerFires, PeerState
from .resend import ResendBook

__all__ = [
    "AskResend",
    "PeerGate",
    "PeerGone",
    "PeerMessage",
    "Rejected",
    "RepeatAnswer",
    "RunStep",
    "StartWaiting",
    "SortedInbox",
    "StillWaiting",
    "inbox_order",
    "step_verdict",
]

PeerMessage = PeerState | PeerFires | PeerPerimeter | PeerFront
B = TypeVar("B")  # the bundle as the caller holds it (the node: its bytes' reading with the stamp)
K = TypeVar("K")  # what the caller keeps per published step for a resend

#: a blocked step is worth a log line and a resend request after this long [ns of steady time]
WAIT_REPORT_NS = 5 * 10**9

_KIND = {PeerState: 0, PeerFires: 1, PeerPerimeter: 2, PeerFront: 3}
# looked up once: on_state runs for every peer every step (``draw_index`` is a property)
_STATE_TOPIC, _STATE_INDEX = FLEET_STATE_SPEC.name, FLEET_STATE_SPEC.draw_index
_CARRIED = (FLEET_FIRES_SPEC.draw_index,)  # the part a state carries: its fire picture


def inbox_order(m: PeerMessage) -> tuple[int, int, int, int]:
    """(step, sender, kind, sequence): the one order peer messages are handed to the agent in.

    Kind: state, fire picture, perimeter, front. A field that is not an int (a fuzzed message)
    sorts as -1, so the order is total on anything the agent may be handed.
    """
    uid = m.uav_id if isinstance(m.uav_id, int) else -1
    seq = m.sequence if isinstance(m.sequence, int) else -1
    return (m.step, uid, _KIND.get(type(m), 4), seq)


class SortedInbox(tuple):  # type: ignore[type-arg]
    """Peer messages already in :func:`inbox_order`, as :meth:`PeerGate._run` hands them on.

    A plain tuple to everyone; the agent's peer stage skips its own sort for it (sorting a sorted
    sequence with the same key is the identity: ``sorted`` is stable), which at 30 UAVs is ~60
    messages and a key each per agent step."""

    __slots__ = ()


def step_verdict(step: int, last_step: int, lockstep: bool, slack_steps: int) -> str | None:
    """Whether a peer message of ``step`` can be genuine when this agent last ran ``last_step``.

    In lockstep a peer's message is of the step this agent last ran or the next one: a peer runs
    step s only after the world's bundle s, which needs this agent's command of s - 1; messages of
    older steps are never waited for again. ``slack_steps``: steps this agent itself is offline
    in the fault schedule (it falls behind by that many). Returns the rejection kind, or None.
    """
    if step < 0:
        return "negative step"
    if lockstep and step < last_step:
        return "stale step"
    if step > last_step + 1 + slack_steps:
        return "implausible step"
    return None


# --- decisions ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class RunStep(Generic[B]):
    """Run step ``step`` with ``bundle`` and the peer messages ``inbox`` (in :func:`inbox_order`)."""

    step: int
    bundle: B
    inbox: tuple[PeerMessage, ...]


@dataclass(frozen=True)
class RepeatAnswer:
    """The world re-sent the bundle of step ``step``, already answered: publish that answer again."""

    step: int


@dataclass(frozen=True)
class Rejected:
    """A peer message refused at admission; count it as a rejection of kind ``reason``."""

    topic: str
    sender: int
    step: int
    reason: str


@dataclass(frozen=True)
class StartWaiting:
    """Step ``step``'s bundle waits for peer messages: start the liveness checks."""

    step: int


@dataclass(frozen=True)
class StillWaiting:
    """Step ``step`` has waited ``waited_s`` [s wall]; ``missing`` says for what."""

    step: int
    waited_s: float
    missing: str


@dataclass(frozen=True)
class AskResend:
    """Ask ``peer`` to send its messages of step ``step`` again (this agent waits on them for ``step + 1``)."""

    peer: int
    step: int
    waited_s: float


@dataclass(frozen=True)
class PeerGone:
    """``peer``'s process left the DDS graph while step ``step`` waited for it (not in the fault
    schedule): no longer waited for, so the run is not reproducible."""

    peer: int
    step: int


Decision = RunStep | RepeatAnswer | Rejected | StartWaiting | StillWaiting | AskResend | PeerGone


@dataclass
class _Pending(Generic[B]):
    step: int
    bundle: B
    since_ns: int


# --- the gate ----------------------------------------------------------------------------------
@dataclass
class PeerGate(Generic[B, K]):
    """One agent's peer gate (see the module doc). ``check_tag(data, topic, sender, auth_step)``:
    the tag check of a signed message's bytes (None: messages are unsigned)."""

    uav_id: int
    uav_count: int
    control_period_s: float
    lockstep: bool = True
    schedule: tuple[OfflineWindow, ...] = ()
    crash_threshold_steps: int = 10
    check_tag: Callable[[bytes, str, int, int], bool] | None = None
    resend: ResendBook = field(default_factory=ResendBook)
    last_step: int = -1  # the last step run
    _pending: _Pending[B] | None = None
    _inbox: list[PeerMessage] = field(default_factory=list)

    def __post_init__(self) -> None:
        if not 0 <= self.uav_id < self.uav_count:
            raise ConfigError(f"uav_id {self.uav_id} outside 0..{self.uav_count - 1}")
        if self.crash_threshold_steps < 1:
            raise ConfigError(f"crash_threshold_steps must be >= 1, got {self.crash_threshold_steps}")
        self.wait = PeerWait(self.uav_id, self.uav_count, self.control_period_s, self.schedule)
        own_offline = sum(
            w.steps(self.control_period_s)[1] - w.steps(self.control_period_s)[0] + 1
            for w in self.schedule
            if w.uav_id == self.uav_id and math.isfinite(w.end_s)
        )
        # how far ahead of this agent a genuine peer can be: the steps it is itself offline in the
        # schedule, and in realtime mode (no wait) the missed steps before a peer counts as crashed
        self._slack = int(own_offline) + (0 if self.lockstep else self.crash_threshold_steps)

    @property
    def pending_step(self) -> int | None:
        """The step of the bundle waiting for peer messages (None: none waits)."""
        return None if self._pending is None else self._pending.step

    # --- the world's bundle ---------------------------------------------------------------------
    def on_bundle(self, step: int, bundle: B, now_ns: int = 0) -> list[Decision]:
        """The sensor bundle of ``step`` arrived (``now_ns``: steady time, for the wait report)."""
        k = step
        if self.lockstep and self.last_step >= 0 and k == self.last_step:
            # our answer did not reach the world (it re-sends only to agents it still waits for)
            return [RepeatAnswer(k)]
        if k <= self.last_step or (self._pending is not None and k <= self._pending.step):
            return []  # answer only the newest bundle
        out: list[Decision] = []
        if self._pending is not None:
            out.append(self._run())  # a newer bundle overtook the one we were waiting on (realtime)
        self._pending = _Pending(k, bundle, now_ns)
        if not self.lockstep or k == 0:
            out.append(self._run())
        elif self.wait.ready(k):
            out.append(self._run())
        else:
            out.append(StartWaiting(k))
        return out

    # --- peer messages ----------------------------------------------------------------------------
    def on_state(
        self,
        data: bytes,
        state: PeerState,
        fires: PeerFires,
        sent_per_topic: tuple[int, ...],
        final: bool,
    ) -> list[Decision]:
        """A peer's UavState (its bytes ``data`` as received, read into ``state`` and ``fires``)."""
        sender, step = int(state.uav_id), int(state.step)
        rejected = self._admit(data, _STATE_TOPIC, sender, step, step)
        if rejected is not None:
            return [rejected]
        if self.resend.duplicate(sender, _STATE_INDEX, step):
            return []  # a resent copy: dropped with the fire picture it carries
        # the fire picture it carries is counted and kept as the part it is (its own loss draw)
        self.wait.on_state(sender, step, sent_per_topic, final, _CARRIED)
        self._inbox.append(state)
        self._inbox.append(fires)
        return self._maybe_run()

    def on_perimeter(self, data: bytes, pm: PeerPerimeter) -> list[Decision]:
        """A peer's PerimeterMap (bytes as received, read into ``pm``)."""
        rejected = self._admit(data, FLEET_PERIMETER_SPEC.name, pm.uav_id, pm.step, pm.step)
        if rejected is not None:
            return [rejected]
        if self.resend.duplicate(pm.uav_id, FLEET_PERIMETER_SPEC.draw_index, pm.step):
            return []
        self.wait.on_message(pm.uav_id, pm.step, FLEET_PERIMETER_SPEC.draw_index)
        self._inbox.append(pm)
        return self._maybe_run()

    def on_front(self, sender: int, step: int, front: PeerFront | None) -> list[Decision]:
        """A peer's FireFront of ``step`` (unsigned); ``front`` None: malformed, counted as arrived
        (the sender sent it) but its content dropped.

        Admitted as a state or a map is, but for the tag: a front of an old step (lockstep), of an
        implausible step or from an unknown id is a :class:`Rejected` of that kind. Before, it was
        let in unchecked: an old one was merged a step late, one of a far step sat in the inbox
        for good, never handed on and never counted."""
        rejected = self._admit(b"", FLEET_FRONT_SPEC.name, sender, step, step, signed=False)
        if rejected is not None:
            return [rejected]
        if self.resend.duplicate(sender, FLEET_FRONT_SPEC.draw_index, step):
            return []
        self.wait.on_message(sender, step, FLEET_FRONT_SPEC.draw_index)
        if front is not None:
            self._inbox.append(front)
        return self._maybe_run()

    def on_arrival(self, sender: int, step: int, loss_index: int) -> list[Decision]:
        """Another peer message the wait counts (coverage topics; kept by their own link)."""
        self.wait.on_message(sender, step, loss_index)
        return self._maybe_run()

    # --- while blocked -----------------------------------------------------------------------------
    def on_liveness(self, now_ns: int, alive: Callable[[], set[int]]) -> list[Decision]:
        """The periodic check while a bundle waits: report a long wait and ask for resends; stop
        waiting for a missing peer whose process is gone (``alive()``: peer ids with a process)."""
        if self._pending is None:
            return []
        k = self._pending.step
        out: list[Decision] = []
        waited_ns = now_ns - self._pending.since_ns
        if waited_ns > WAIT_REPORT_NS:
            waited_s = waited_ns / 1e9
            out.append(StillWaiting(k, waited_s, self.wait.describe(k)))
            for j in self.resend.peers_to_ask(self.wait.missing(k), k, now_ns):
                out.append(AskResend(j, k - 1, waited_s))
        missing = self.wait.missing(k)
        if missing:
            live = alive()
            for j in missing:
                if j not in live:
                    self.wait.mark_gone(j)
                    out.append(PeerGone(j, k))
        return out + self._maybe_run()

    def mark_gone(self, peer: int) -> None:
        """``peer`` sends nothing more (its process ended): not waited for from now on."""
        self.wait.mark_gone(peer)

    # --- this agent's own messages -----------------------------------------------------------------
    def keep(self, step: int, published: list[K]) -> None:
        """What this agent published at ``step`` (for a peer's resend request)."""
        self.resend.keep(step, published)

    def to_resend(self, step: int, now_ns: int) -> list[K] | None:
        """What to publish again for a peer's request for ``step`` (None: nothing, or just did)."""
        return self.resend.to_resend(step, now_ns)

    # --- inside ---------------------------------------------------------------------------------------
    def _admit(
        self, data: bytes, topic: str, sender: int, step: int, auth_step: int, signed: bool = True
    ) -> Rejected | None:
        if not 0 <= sender < self.uav_count:
            reason: str | None = "unknown id"
        else:
            reason = step_verdict(step, self.last_step, self.lockstep, self._slack)
        if (
            reason is None
            and signed
            and self.check_tag is not None
            and not self.check_tag(data, topic, sender, auth_step)
        ):
            reason = "bad auth"
        return None if reason is None else Rejected(topic, sender, step, reason)

    def _maybe_run(self) -> list[Decision]:
        if self._pending is not None and self.wait.ready(self._pending.step):
            return [self._run()]
        return []

    def _run(self) -> RunStep:
        p = self._pending
        assert p is not None
        self._pending = None
        k = p.step
        take = sorted((m for m in self._inbox if m.step < k), key=inbox_order)
        self._inbox = [m for m in self._inbox if m.step >= k]
        self.last_step = k
        self.wait.prune(k)
        self.resend.ran(k)
        return RunStep(k, p.bundle, SortedInbox(take))

    def inbox(self) -> Iterable[PeerMessage]:
        """Peer messages not yet handed to the agent (for tests)."""
        return tuple(self._inbox)
