"""Resend bookkeeping of one agent (docs/protocol.md "Resend"): what to ask for, what to send again,
which copies to drop. ROS-free; times are steady-clock nanoseconds handed in by the node.

The lockstep wait (:mod:`fire_uav_agent.lockstep_wait`) has no timeout, so that wall time never
decides what the fleet does. A message the transport loses for good (a reader history overrun by
a flood on the topic) would then block the fleet forever. So:

- an agent blocked on step k asks each peer still missing for its step-(k-1) messages, at most
  once per :attr:`ResendBook.ask_every_ns` per (peer, step);
- a peer keeps what it published on the single-message topics (state, fires, perimeter, front)
  for its last :attr:`ResendBook.keep_steps` steps and publishes that again when asked, at most
  once per :attr:`ResendBook.resend_every_ns` per step;
- a receiver takes the first copy of each (sender, topic, step) and drops the others. A resent
  copy is the same message object as the first, so taking whichever arrives first changes
  nothing the agent decides: wall time decides only *when* the fleet resumes.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Generic, TypeVar

from .errors import ConfigError

__all__ = ["ResendBook"]

T = TypeVar("T")  # what the node keeps per step (its (publisher, message) pairs)


@dataclass
class ResendBook(Generic[T]):
    """The resend protocol's state: kept messages, copies taken, requests asked and served."""

    ask_every_ns: int = 5 * 10**9
    resend_every_ns: int = 2 * 10**9
    keep_steps: int = 4
    copies_dropped: int = 0  # resent (or duplicated) copies received and dropped
    resends_served: int = 0  # requests this agent answered by publishing again
    _kept: dict[int, list[T]] = field(default_factory=dict)  # step -> what was published
    _taken: set[tuple[int, int, int]] = field(default_factory=set)  # (sender, loss index, step)
    _asked_ns: dict[tuple[int, int], int] = field(default_factory=dict)  # (peer, step) -> when
    _served_ns: dict[int, int] = field(default_factory=dict)  # step -> when last resent

    def __post_init__(self) -> None:
        if self.keep_steps < 1:
            raise ConfigError(f"keep_steps must be >= 1, got {self.keep_steps}")
        if self.ask_every_ns < 0 or self.resend_every_ns < 0:
            raise ConfigError(
                f"ask_every_ns and resend_every_ns must be >= 0, got {self.ask_every_ns}, {self.resend_every_ns}"
            )

    # --- receiving ------------------------------------------------------------------------------
    def duplicate(self, sender: int, loss_index: int, step: int) -> bool:
        """Whether this (sender, topic, step) was taken already (then the copy is dropped).

        Only for topics that carry at most one message per sender and step."""
        key = (int(sender), int(loss_index), int(step))
        if key in self._taken:
            self.copies_dropped += 1
            return True
        self._taken.add(key)
        return False

    def peers_to_ask(self, missing: Iterable[int], k: int, now_ns: int) -> list[int]:
        """Of the peers still ``missing`` for step ``k``, those to ask now for their step-(k-1)
        messages (not asked for that step within :attr:`ask_every_ns`); marks them asked."""
        out = []
        for j in missing:
            last = self._asked_ns.get((j, k - 1))
            if last is not None and now_ns - last < self.ask_every_ns:
                continue
            self._asked_ns[(j, k - 1)] = now_ns
            out.append(j)
        return out

    def ran(self, k: int) -> None:
        """Step ``k`` ran: forget copies and requests of steps before k-1 (none can matter now)."""
        self._taken = {key for key in self._taken if key[2] >= k - 1}
        self._asked_ns = {key: t for key, t in self._asked_ns.items() if key[1] >= k - 1}

    # --- sending --------------------------------------------------------------------------------
    def keep(self, step: int, published: list[T]) -> None:
        """What this agent published at ``step``; only the last :attr:`keep_steps` steps stay."""
        self._kept[step] = published
        for old in [s for s in self._kept if s <= step - self.keep_steps]:
            del self._kept[old]
        for old in [s for s in self._served_ns if s not in self._kept]:
            del self._served_ns[old]

    def to_resend(self, step: int, now_ns: int) -> list[T] | None:
        """What to publish again for a peer's request for ``step``: None when it is not kept (too
        old, never sent) or was resent within :attr:`resend_every_ns` (one copy serves every
        peer that asked meanwhile)."""
        kept = self._kept.get(step)
        last = self._served_ns.get(step)
        if kept is None or (last is not None and now_ns - last < self.resend_every_ns):
            return None
        self._served_ns[step] = now_ns
        self.resends_served += 1
        return kept
