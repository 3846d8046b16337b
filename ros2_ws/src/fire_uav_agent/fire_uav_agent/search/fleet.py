"""In-process fleet of :class:`SearchCoordinator` s over a simulated lossy broadcast network.

For tests and benchmarks: the same loss rule as the peer link (docs/protocol.md "Peer link"):
a message from ``j`` to ``i`` published at step ``s`` on coverage topic ``t`` is lost when
``fire_uav_common.rng.bernoulli(p, seed, "loss", j, i, s, TOPIC_SPECS[t].loss_index)``. Delivery takes
``1 + delay`` steps, ``delay`` drawn uniformly in ``[0, max_extra_delay_steps]`` from a seeded
generator (to exercise out-of-order arrival). Crashed agents stop stepping; the survivors learn it
``detect_steps`` later (the peer link's crash threshold).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from fire_uav_common import rng as fleet_rng

from .coordinator import TOPIC_SPECS, Envelope, SearchConfig, SearchCoordinator

__all__ = ["FleetSim"]


@dataclass
class FleetSim:
    """N coordinators, a lossy network and crash injection. Step with :meth:`step`."""

    uav_count: int
    area_m: tuple[float, float, float, float]
    seed: int = 0
    config: SearchConfig = field(default_factory=SearchConfig)
    loss_probability: float = 0.0
    max_extra_delay_steps: int = 0
    detect_steps: int = 10
    control_period_s: float = 0.1

    def __post_init__(self) -> None:
        self.coordinators = [
            SearchCoordinator(i, self.uav_count, self.area_m, self.seed, self.config)
            for i in range(self.uav_count)
        ]
        self._queue: list[tuple[int, int, Envelope]] = []  # (arrival step, receiver, envelope)
        self._net = np.random.default_rng([self.seed, 0xDE1A])
        self.crashed_at: dict[int, int] = {}
        self.step_index = 0
        self.sent = 0
        self.lost = 0

    def crash(self, uav_id: int) -> None:
        """The agent stops now; the others count it dead ``detect_steps`` later."""
        self.crashed_at[uav_id] = self.step_index

    def alive_view(self, step: int) -> tuple[int, ...]:
        return tuple(
            u
            for u in range(self.uav_count)
            if u not in self.crashed_at or step - self.crashed_at[u] < self.detect_steps
        )

    def step(self) -> None:
        k = self.step_index
        view = self.alive_view(k)
        deliver = [q for q in self._queue if q[0] <= k]
        self._queue = [q for q in self._queue if q[0] > k]
        for c in self.coordinators:
            if c.uav_id in self.crashed_at:
                continue
            inbox = [e for (_, r, e) in deliver if r == c.uav_id]
            out = c.on_step((k + 1) * self.control_period_s, k, view, inbox)
            for e in out:
                for r in range(self.uav_count):
                    if r == c.uav_id or r in self.crashed_at:
                        continue
                    self.sent += 1
                    if fleet_rng.bernoulli(self.loss_probability, self.seed, "loss", c.uav_id, r, e.step,
                                           TOPIC_SPECS[e.topic].draw_index):  # fmt: skip
                        self.lost += 1
                        continue
                    extra = int(self._net.integers(0, self.max_extra_delay_steps + 1))
                    self._queue.append((k + 1 + extra, r, e))
        self.step_index += 1

    def run(self, steps: int) -> None:
        for _ in range(steps):
            self.step()

    def run_until_planned(self, max_steps: int, ids: Sequence[int] | None = None) -> int:
        """Step until every listed (default: every non-crashed) agent flies a plan; return the step count."""
        for _ in range(max_steps):
            live = [c for c in self.coordinators if c.uav_id not in self.crashed_at]
            if ids is not None:
                live = [c for c in live if c.uav_id in ids]
            if all(c.plan is not None and c.phase.name == "FLY" for c in live):
                return self.step_index
            self.step()
        return self.step_index
