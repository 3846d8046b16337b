"""What an agent waits for before lockstep step k: every message its live peers sent at step k-1.

docs/protocol.md "Lockstep". The wait has no wall-clock timeout, so it must know exactly which
messages exist; it counts *physical* arrivals (the DDS transport is reliable), not what survives
the injected loss: the seeded loss draw is applied afterwards, on receipt, by the peer link, so
waiting for a message that the draw then drops changes nothing the agent decides.

- Each peer's ``UavState`` of step k-1 carries ``sent_per_topic``: how many messages it sent at
  that step on each peer topic (indexed by the topic's loss index, ``fire_uav_common.topics``).
  The state message is published first; once it is in, the agent knows what else to wait for.
- A peer is *live* at step s unless the fault schedule takes it offline at s
  (``fire_uav_common.lockstep``), it sent a ``final`` state at an earlier step (its vehicle
  crashed), or its process is gone (DDS graph, :meth:`PeerWait.mark_gone`: the only
  wall-clock-dependent input, for unscheduled deaths).

Every input is a step number or a message, so the set waited for, and so the fleet, is the same
on an idle machine and a loaded one. ROS-free.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

from fire_uav_common.lockstep import OfflineWindow, offline_uavs
from fire_uav_common.topics import FLEET_STATE_SPEC

from .errors import ConfigError

__all__ = ["PeerWait"]

STATE_INDEX = FLEET_STATE_SPEC.draw_index


@dataclass
class PeerWait:
    """Lockstep bookkeeping of one agent: which peer messages of which step have arrived."""

    uav_id: int
    uav_count: int
    period_s: float
    schedule: tuple[OfflineWindow, ...] = ()
    _sent: dict[tuple[int, int], tuple[int, ...]] = field(default_factory=dict)  # (step, j) -> counts
    _arrived: dict[tuple[int, int], dict[int, int]] = field(default_factory=lambda: defaultdict(dict))
    _final_step: dict[int, int] = field(default_factory=dict)  # j -> step of its final state
    # (step, j) -> messages still owed once its state is in: the sum over topics of what was sent
    # beyond what arrived, kept as messages come so ``missing`` needs no pass over the topics (it
    # runs at every arrival while a bundle waits: ~30 peers x ~10 topics at 30 UAVs)
    _owed: dict[tuple[int, int], int] = field(default_factory=dict)
    # step -> live_peers(step), kept until a final state, a peer gone or a prune changes it
    _live: dict[int, list[int]] = field(default_factory=dict)
    # step -> (its live list, i): live[:i] owe nothing, so ``ready`` resumes at i (it runs at every
    # arrival while a bundle waits: one lookup per call instead of a pass over ~30 peers). A count
    # only goes down, except when a second state of a (step, peer) sets it again (``on_state``
    # drops the entry); a new live list (``_live`` cleared) starts again at 0
    _ready_from: dict[int, tuple[list[int], int]] = field(default_factory=dict)
    _gone: set[int] = field(default_factory=set)

    def __post_init__(self) -> None:
        if not 0 <= self.uav_id < self.uav_count:
            raise ConfigError(f"uav_id {self.uav_id} outside 0..{self.uav_count - 1}")
        if not self.period_s > 0:
            raise ConfigError(f"control period must be > 0 s, got {self.period_s}")

    # --- inputs --------------------------------------------------------------------------------
    def on_state(
        self,
        sender: int,
        step: int,
        sent_per_topic: tuple[int, ...],
        final: bool,
        carried: tuple[int, ...] = (),
    ) -> None:
        """A peer's UavState of ``step`` arrived (before any loss draw), with the parts it carries
        on the topics of loss indexes ``carried`` (the fire picture): each counted after the state,
        as :meth:`on_message` counts it, without a call per part."""
        if not self._valid(sender, step):
            return
        key = (step, sender)
        if key in self._owed:  # a second state of (step, sender): its count is set again
            self._ready_from.pop(step, None)
        sent = self._sent[key] = tuple(map(int, sent_per_topic))
        got = self._arrived[key]
        if got:
            owed = sum(n - got.get(t, 0) for t, n in enumerate(sent) if got.get(t, 0) < n)
        else:  # the state first, as it is published: nothing arrived, every count sent is owed
            owed = sum(n for n in sent if n > 0) if sent and min(sent) < 0 else sum(sent)
        n_topics = len(sent)
        for t in (STATE_INDEX, *carried):  # on_message's count, inline (its checks hold already)
            c = got[t] = got.get(t, 0) + 1
            if 0 <= t < n_topics and c <= sent[t]:
                owed -= 1
        self._owed[key] = owed
        if final:
            self._final_step[sender] = min(step, self._final_step.get(sender, step))
            self._live.clear()

    def on_message(self, sender: int, step: int, loss_index: int) -> None:
        """Any other peer message of ``step`` on the topic with ``loss_index`` arrived."""
        if not (0 <= sender < self.uav_count and sender != self.uav_id and step >= 0):  # _valid, inline
            return
        key = (step, sender)
        counts = self._arrived[key]
        got = counts[loss_index] = counts.get(loss_index, 0) + 1
        sent = self._sent.get(key)
        if sent is not None and 0 <= loss_index < len(sent) and got <= sent[loss_index]:
            self._owed[key] -= 1  # one fewer owed on a topic still short (more than sent: none owed)

    def mark_gone(self, sender: int) -> None:
        """The peer's process left the DDS graph (unscheduled death): stop waiting for it."""
        self._gone.add(sender)
        self._live.clear()

    def prune(self, step: int) -> None:
        """Forget bookkeeping of steps before ``step - 1`` (call after running ``step``)."""
        for d in (self._sent, self._arrived, self._owed):
            for key in [k for k in d if k[0] < step - 1]:
                del d[key]
        self._live.clear()
        self._ready_from.clear()

    # --- queries -------------------------------------------------------------------------------
    def live_peers(self, step: int) -> list[int]:
        """Peers that send messages at ``step``, in id order (a new list)."""
        live = self._live.get(step)
        if live is None:
            live = self._live[step] = self._live_peers(step)
        return list(live)

    def _live_peers(self, step: int) -> list[int]:
        off = offline_uavs(self.schedule, step, self.period_s)
        return [
            j
            for j in range(self.uav_count)
            if j != self.uav_id
            and j not in off
            and j not in self._gone
            and not (j in self._final_step and self._final_step[j] < step)
        ]

    def missing(self, step: int) -> list[int]:
        """Peers whose step-(``step`` - 1) messages are not all in yet (empty: run step ``step``)."""
        if step < 1:
            return []
        prev = step - 1
        owed = self._owed
        # no entry: its state is not in yet; else a topic still short (the count above)
        live = self._live.get(prev)
        if live is None:
            live = self._live[prev] = self._live_peers(prev)
        return [j for j in live if owed.get((prev, j), 1) > 0]

    def describe(self, step: int) -> str:
        """What is still missing for ``step``, for a log line (``"uav 2: state; uav 3: 1/2 on topic 5"``)."""
        prev = step - 1
        parts = []
        for j in self.missing(step):
            sent = self._sent.get((prev, j))
            if sent is None:
                parts.append(f"uav {j}: state of step {prev}")
                continue
            got = self._arrived.get((prev, j), {})
            short = [f"{got.get(t, 0)}/{n} on topic {t}" for t, n in enumerate(sent) if got.get(t, 0) < n]
            parts.append(f"uav {j}: " + ", ".join(short))
        return "; ".join(parts)

    def ready(self, step: int) -> bool:
        """Whether every message the live peers sent at ``step - 1`` has arrived (``not
        missing(step)``, resumed where the last call stopped: see ``_ready_from``)."""
        if step < 1:
            return True
        prev = step - 1
        live = self._live.get(prev)
        if live is None:
            live = self._live[prev] = self._live_peers(prev)
        head = self._ready_from.get(prev)
        i = head[1] if head is not None and head[0] is live else 0
        owed, n = self._owed, len(live)
        while i < n and owed.get((prev, live[i]), 1) <= 0:  # no entry: its state is not in yet
            i += 1
        self._ready_from[prev] = (live, i)
        return i == n

    def _valid(self, sender: int, step: int) -> bool:
        return 0 <= sender < self.uav_count and sender != self.uav_id and step >= 0
