"""Peer bookkeeping of one agent (docs/protocol.md "Peer link"; FF IV-B, IV-C).

On receipt, a message from peer j to this agent i for step s is

* *rejected* (counted per kind in ``reject_reasons``) if its sender id is outside 0..N-1 or is
  i's own id, if its step is implausible (negative, or outside the window
  ``[k - max_step_lag, k - 1]`` of the step k being run, when k is given), if its sequence is
  implausible (0, or more than ``step + 1``: one state per step from step 0 on), if it holds a
  NaN/inf, or if it is not newer than the last accepted one from j on that topic;
* *lost* (counted) if ``rng.bernoulli(loss_probability, seed, "loss", j, i, s, topic_index)`` (``topic_index``: the
  topic's ``fire_uav_common.topics.TopicSpec.loss_index``)
  (deterministic whatever the arrival order) or if link (j, i) is in a scheduled outage at the
  step's stamp ``(s + 1) * T``;
* otherwise *accepted*: it becomes j's last known state / fire picture (reused while j is not
  heard, FF IV-B).

Once per control step k, :meth:`PeerLink.end_step` updates each peer's ``missed`` counter:
reset to 0 if a valid state of step >= k-1 was accepted since the previous call, else +1.
At exactly ``crash_threshold_steps`` missed steps the peer is declared crashed (FF IV-C); a
crashed peer that is heard again rejoins. Id validity is checked before the loss draw (the
draw needs a valid sender id); the other checks come after it, so a lost message is never
also counted as rejected.

No single message can poison the bookkeeping: messages are ordered by
``(step, sequence)`` with the step first, and the step must lie in a window around the step being
run, so a forged ``sequence = 2**32 - 1`` is rejected as implausible instead of becoming the bar
every later genuine message fails. A message of a newer step whose sequence went *down* is a
restarted peer (its sequence starts again at 1): accepted and counted in ``restarts``. At most one
state per (peer, step) is accepted; a second one of the same step is a "duplicate". The paper says
nothing about message validation; these rules are our choice (docs/security.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum

from fire_uav_common import rng
from fire_uav_common.codecs.uav_state import FireEntry, PeerFires, PeerState  # re-exported
from fire_uav_common.constants import Objective
from fire_uav_common.scenario import LinkOutage
from fire_uav_common.topics import FLEET_FIRES_SPEC, FLEET_STATE_SPEC

from .errors import ConfigError

__all__ = [
    "FireEntry",
    "PeerFires",
    "PeerLink",
    "PeerState",
    "Verdict",
]

# loss-draw indices (``TopicSpec.loss_index``) of the two topics the lockstep wait holds out for
_STATE = int(FLEET_STATE_SPEC.loss_index)  # type: ignore[arg-type]
_FIRES = int(FLEET_FIRES_SPEC.loss_index)  # type: ignore[arg-type]
_OBJECTIVES = frozenset(int(o) for o in Objective)


class Verdict(IntEnum):
    ACCEPTED = 0
    LOST = 1
    REJECTED = 2


# the members, looked up once: receipt runs for ~60 messages per step at 30 UAVs
_ACCEPTED, _LOST, _REJECTED = Verdict.ACCEPTED, Verdict.LOST, Verdict.REJECTED


@dataclass
class _Peer:
    missed: int = 0
    crashed: bool = False
    heard_since_bookkeeping: bool = False
    # (step, sequence) of the last accepted message per topic; (-1, 0): none yet
    last_seq: dict[int, tuple[int, int]] = field(default_factory=lambda: {_STATE: (-1, 0), _FIRES: (-1, 0)})
    state: PeerState | None = None
    fires: PeerFires | None = None


@dataclass(frozen=True)
class LinkEvent:
    """PEER_CRASHED / PEER_REJOINED decision."""

    kind: str  # "crashed" | "rejoined"
    peer_id: int
    step: int


_BLOCK_STEPS = 64  # steps of loss draws computed at once by PeerLink.is_lost (rng.uniform_table)
_BLOCKS_KEPT = 16  # (block, topic) tables kept; a lookup needs at most two blocks per topic
_MAX_WORD = 0xFFFFFFFF  # rng.uniform_table takes 32-bit words only


class PeerLink:
    """Bookkeeping of agent ``uav_id`` about its ``uav_count - 1`` peers."""

    def __init__(
        self,
        uav_id: int,
        uav_count: int,
        seed: int,
        loss_probability: float,
        control_period_s: float,
        crash_threshold_steps: int = 10,
        outages: tuple[LinkOutage, ...] = (),
        max_step_lag: int | None = None,
    ) -> None:
        if not 0 <= uav_id < uav_count:
            raise ConfigError(f"uav_id {uav_id} outside 0..{uav_count - 1}")
        if not 0.0 <= loss_probability <= 1.0:
            raise ConfigError(f"loss_probability must be in [0, 1], got {loss_probability}")
        if crash_threshold_steps < 1:
            raise ConfigError(f"crash_threshold_steps must be >= 1, got {crash_threshold_steps}")
        if seed < 0:
            raise ConfigError(f"seed must be >= 0, got {seed}")
        self.uav_id = uav_id
        self.uav_count = uav_count
        self.seed = seed
        self.loss_probability = loss_probability
        self.period_s = control_period_s
        self.crash_threshold = crash_threshold_steps
        self.outages = tuple(outages)
        self.peers = {j: _Peer() for j in range(uav_count) if j != uav_id}
        self.received = 0
        self.lost = 0
        self.rejected = 0
        self.reject_reasons: dict[str, int] = {}
        self.restarts = 0  # accepted messages whose sequence went down at a newer step
        # oldest plausible step is k - max_step_lag (k: the step being run); older news is a missed step anyway
        self.max_step_lag = crash_threshold_steps if max_step_lag is None else int(max_step_lag)
        if self.max_step_lag < 1:
            raise ConfigError(f"max_step_lag must be >= 1, got {self.max_step_lag}")
        # loss draws by block of _BLOCK_STEPS steps and topic: {(block, topic_index): lost[step
        # in block][sender]}, each table one rng.uniform_table pass (the receipt and the lockstep
        # wait ask for every (sender, step, topic) of the fleet: ~5 us a draw one at a time)
        self._blocks: dict[tuple[int, int], list[list[bool]]] = {}

    # --- loss model ----------------------------------------------------------------------
    def in_outage(self, sender: int, step: int) -> bool:
        if not self.outages:  # the common case: no schedule, nothing to compute
            return False
        t = (step + 1) * self.period_s
        return any(
            o.from_id == sender and o.to_id == self.uav_id and o.start_s <= t < o.end_s for o in self.outages
        )

    def is_lost(self, sender: int, step: int, topic_index: int) -> bool:
        """True if message (sender -> me, step, topic) is dropped by injection (deterministic).

        The draw is :func:`fire_uav_common.rng.bernoulli` ``(loss_probability, seed, "loss",
        sender, uav_id, step, topic_index)``, a pure function of its arguments; the draws of a
        block of :data:`_BLOCK_STEPS` steps for every sender are computed together
        (:func:`fire_uav_common.rng.uniform_table`, the same doubles) and kept. Arguments outside
        such a table (an id outside the fleet, a negative or 33-bit step) take the single draw.
        """
        if self.outages and self.in_outage(sender, step):
            return True
        p = self.loss_probability
        if p == 0.0:
            return False
        block, row = divmod(step, _BLOCK_STEPS) if type(step) is int else (-1, 0)
        table = self._blocks.get((block, topic_index))
        if table is None:
            if not (
                type(sender) is int
                and 0 <= sender < self.uav_count
                and type(topic_index) is int
                and 0 <= topic_index <= _MAX_WORD
                and 0 <= block
                and (block + 1) * _BLOCK_STEPS - 1 <= _MAX_WORD
                and self.seed <= _MAX_WORD
                and self.uav_id <= _MAX_WORD
            ):
                return rng.bernoulli(p, self.seed, "loss", sender, self.uav_id, step, topic_index)
            if len(self._blocks) >= _BLOCKS_KEPT:
                del self._blocks[min(self._blocks)]
            u = rng.uniform_table(
                self.seed,
                "loss",
                range(self.uav_count),
                self.uav_id,
                range(block * _BLOCK_STEPS, (block + 1) * _BLOCK_STEPS),
                topic_index,
            )
            table = self._blocks[(block, topic_index)] = (u < p).tolist()
        elif not (type(sender) is int and 0 <= sender < self.uav_count):
            return rng.bernoulli(p, self.seed, "loss", sender, self.uav_id, step, topic_index)
        return table[row][sender]

    def expected(self, step: int) -> set[tuple[int, int]]:
        """(peer, topic_index) messages of ``step`` the lockstep wait should hold out for."""
        out = set()
        for j, p in self.peers.items():
            if p.crashed:
                continue
            for ti in (_STATE, _FIRES):
                if not self.is_lost(j, step, ti):
                    out.add((j, ti))
        return out

    # --- receipt ---------------------------------------------------------------------------
    def count_rejection(self, reason: str) -> Verdict:
        """Count one rejected peer message of kind ``reason`` (also used by the node's checks)."""
        self.rejected += 1
        self.reject_reasons[reason] = self.reject_reasons.get(reason, 0) + 1
        return _REJECTED

    def _check(
        self, sender: int, step: int, seq: int, finite: bool, ti: int, now_step: int | None
    ) -> Verdict:
        if not isinstance(sender, int) or not 0 <= sender < self.uav_count:
            return self.count_rejection("unknown id")
        if sender == self.uav_id:
            return self.count_rejection("own id")
        if not isinstance(step, int) or step < 0:
            return self.count_rejection("negative step")
        if now_step is not None and not now_step - self.max_step_lag <= step <= now_step - 1:
            return self.count_rejection("implausible step")
        if not isinstance(seq, int) or not 1 <= seq <= step + 1:
            return self.count_rejection("implausible sequence")
        if self.is_lost(sender, step, ti):
            self.lost += 1
            return _LOST
        if not finite:
            return self.count_rejection("nan/inf")
        last_step, last_seq = self.peers[sender].last_seq[ti]
        if step < last_step:
            return self.count_rejection("old step")
        if step == last_step:
            return self.count_rejection("duplicate")
        if seq <= last_seq:
            self.restarts += 1  # a newer step with a lower sequence: the peer restarted
        return _ACCEPTED

    def receive_state(self, msg: PeerState, now_step: int | None = None) -> Verdict:
        """Bookkeeping of a peer's state; ``now_step``: the step being run (enables the step window)."""
        if msg.objective not in _OBJECTIVES:
            return self.count_rejection("unknown objective")
        v = self._check(msg.uav_id, msg.step, msg.sequence, msg.finite(), _STATE, now_step)
        if v is _ACCEPTED:
            p = self.peers[msg.uav_id]
            p.last_seq[_STATE] = (msg.step, msg.sequence)
            p.state = msg
            p.heard_since_bookkeeping = True
            self.received += 1
        return v

    def receive_fires(self, msg: PeerFires, now_step: int | None = None) -> Verdict:
        v = self._check(msg.uav_id, msg.step, msg.sequence, msg.finite(), _FIRES, now_step)
        if v is _ACCEPTED:
            p = self.peers[msg.uav_id]
            p.last_seq[_FIRES] = (msg.step, msg.sequence)
            p.fires = msg
            self.received += 1
        return v

    # --- per-step bookkeeping --------------------------------------------------------------
    def end_step(self, step: int) -> list[LinkEvent]:
        """Missed counters, crash declaration and rejoin for control step ``step``."""
        events: list[LinkEvent] = []
        for j, p in self.peers.items():
            if p.heard_since_bookkeeping:
                p.missed = 0
                p.heard_since_bookkeeping = False
                if p.crashed:
                    p.crashed = False
                    events.append(LinkEvent("rejoined", j, step))
            else:
                p.missed += 1
                if p.missed == self.crash_threshold and not p.crashed:
                    p.crashed = True
                    events.append(LinkEvent("crashed", j, step))
        return events

    # --- views -----------------------------------------------------------------------------
    def alive_ids(self) -> list[int]:
        """Ids counted alive, this agent included, ascending."""
        return sorted([self.uav_id] + [j for j, p in self.peers.items() if not p.crashed])

    def crashed_ids(self) -> list[int]:
        return sorted(j for j, p in self.peers.items() if p.crashed)

    def alive_states(self) -> dict[int, PeerState]:
        """Last known state of every alive peer that has ever been heard (FF IV-B reuse)."""
        return {j: p.state for j, p in self.peers.items() if not p.crashed and p.state is not None}

    def alive_fires(self) -> dict[int, PeerFires]:
        return {j: p.fires for j, p in self.peers.items() if not p.crashed and p.fires is not None}

    def missed(self, peer: int) -> int:
        return self.peers[peer].missed
