"""The coverage search run inside one agent, over lossy fleet links, with no coordinator node.

:class:`SearchCoordinator` is one agent's step-driven state machine (pure: no clock, no ROS). The
node calls :meth:`SearchCoordinator.on_step` once per control step with the step, the ids it counts
alive and the coverage messages received since the previous call (as :class:`Envelope`); it returns
the messages to publish. Phases (all agents run the same step-indexed schedule):

1. **Optimise** (CP III-F), steps ``[bo_start_step, bo_end_step)``: the fleet budget is split into
   fixed per-agent shares (``budget // N`` plus one for the lowest ids), so no agent needs to count
   its peers' evaluations. Each step an agent with share left proposes one candidate (Thompson
   sampling, or uniform draws from the same pool in ``random`` mode), evaluates it itself and
   broadcasts PROPOSAL and COST. A lost message costs a data point, nothing waits.
2. **Agree**, steps ``[bo_end_step, agree_end_step)``: every agent rebroadcasts the lowest-cost COST
   it knows each step; at ``agree_end_step`` it adopts the minimum ``(cost, candidate_id)`` it has
   heard. Afterwards the adopted candidate is rebroadcast every ``rebroadcast_every_steps``, and an
   agent that hears a cheaper one switches (min-consensus): disagreement left by loss resolves.
3. **Balance** (CP Eqs. 2-8): the seeds of the adopted candidate for the alive ids; each agent
   publishes its :class:`~.power_diagram.WeightReport` for its current and previous iteration
   every step (a peer is at most one iteration behind, so a lost report is simply re-sent) and
   steps its :class:`~.power_diagram.BalancerAgent` when it holds the reports of all alive ids for
   its iteration. Reports of another candidate or alive set are ignored (their seed or target area
   differs). Stop at ``E_max < epsilon`` or ``balance_max_iterations`` (the same decision at every
   agent). If the exchange stalls for ``balance_timeout_steps`` (inconsistent alive views), the
   agent runs the same balancing locally: the lock-step loop gives the same weights.
4. **Fly**: exclusive cell assignment (Eq. 9), one STC path per alive agent; the own path goes to
   the :class:`SearchPlanner`, started at the candidate's start offset (first plan) or at the path
   point nearest the vehicle (re-partition).
5. **Re-partition**: when the alive set changes, phases 3-4 rerun for the new set.
6. **MST** (CP Algorithm 1, Eq. 11): for each plan, the fragment-merge protocol runs over MstFragment
   messages for the plan's sampled instants (all instants in parallel, keyed by ``sample_index``);
   each agent re-sends its messages of the current and previous round until done or
   ``mst_timeout_steps``. The result ``r_max`` is compared with the centralised value.

Message consumption: a message sent at step ``s`` is used at step ``>= s + consume_delay_steps``
(held back if it arrives earlier), so runs repeat whenever messages arrive within that delay.
Positions are [m; map frame], times [s], arc lengths [m].
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from enum import IntEnum
from typing import NamedTuple

import numpy as np
from fire_uav_common.constants import CandidateKind, MstKind
from fire_uav_common.topics import (
    COVERAGE_CANDIDATES_SPEC,
    COVERAGE_MST_SPEC,
    COVERAGE_WEIGHTS_SPEC,
    TopicSpec,
)

from .bayesopt import BoAgent, BoConfig, CandidateMessage, make_pool
from .energy import EnergyModel
from .errors import MstError, SearchConfigError
from .evaluate import Candidate, SearchProblem, evaluate_candidate, positions_normalised_time
from .mst import MstAgent, MstMessage, mission_radius_m
from .planner import MST_KEY_STRIDE, SearchConfig, SearchPlanner, default_cell_size_m  # re-exported
from .power_diagram import (
    BalanceConfig,
    BalancerAgent,
    CoverageGrid,
    WeightReport,
    assign_cells,
    balance_weights,
    equal_targets_m2,
    make_regions_connected,
    quadrature,
)
from .stc import CoveragePath, loiter_path, stc_path

try:  # keep BLAS single-threaded inside a control step (2-core hosts: 10x faster GP fits)
    from threadpoolctl import threadpool_limits
except ImportError:  # pragma: no cover
    threadpool_limits = None

__all__ = [
    "Envelope",
    "Phase",
    "SearchConfig",
    "SearchCoordinator",
    "SearchPlan",
    "SearchPlanner",
    "TOPIC_SPECS",
    "Topic",
    "default_cell_size_m",
]


class Topic(IntEnum):
    """Which coverage topic an :class:`Envelope` travels on."""

    WEIGHTS = 0  # CoverageWeight
    CANDIDATES = 1  # CoverageCandidate
    MST = 2  # MstFragment


#: the fleet topic of each coverage traffic kind (name, type, QoS, loss-draw index)
TOPIC_SPECS: dict[Topic, TopicSpec] = {
    Topic.WEIGHTS: COVERAGE_WEIGHTS_SPEC,
    Topic.CANDIDATES: COVERAGE_CANDIDATES_SPEC,
    Topic.MST: COVERAGE_MST_SPEC,
}


class Phase(IntEnum):
    OPTIMISE = 0
    AGREE = 1
    BALANCE = 2
    FLY = 3


@dataclass(frozen=True)
class Envelope:
    """One coverage message: sender, the control step it was published at, the payload."""

    topic: Topic
    sender: int
    step: int
    msg: WeightReport | CandidateMessage | MstMessage


class SearchPlan(NamedTuple):
    """An agreed partition and its paths (same at every agent that agreed on the inputs)."""

    candidate_id: int
    alive: tuple[int, ...]  # ids sharing the area, ascending
    seeds_m: np.ndarray  # (A, 2)
    weights_m2: np.ndarray  # (A,)
    labels: np.ndarray  # (ny, nx) uav id owning each coarse cell, -1 = not free
    paths: dict[int, CoveragePath]
    start_offsets: dict[int, float]
    e_max: float
    iterations: int
    via_messages: bool  # False: local fallback after a stalled exchange
    step: int  # control step the plan was ready


def _cost_key(m: CandidateMessage) -> tuple[float, int]:
    return (float(m.cost), int(m.candidate_id))


def _finite_candidate(m: CandidateMessage, n: int) -> bool:
    if len(m.seeds_m) != n or len(m.start_offsets) != n:
        return False
    vals = [v for s in m.seeds_m for v in s]
    if not all(math.isfinite(v) for v in vals):
        return False
    if not all(0.0 <= s < 1.0 for s in m.start_offsets):
        return False
    return m.kind != CandidateKind.COST or all(
        math.isfinite(v) for v in (m.cost, m.energy_j, m.radio_radius_m)
    )


# --- balancing and MST sessions -------------------------------------------------------------------
@dataclass
class _Balance:
    candidate: CandidateMessage
    alive: tuple[int, ...]
    seeds_m: np.ndarray
    target_m2: float
    agent: BalancerAgent
    start_step: int
    last_progress_step: int
    own_reports: dict[int, WeightReport] = field(default_factory=dict)
    reports: dict[tuple[int, int], WeightReport] = field(default_factory=dict)  # (iteration, uav)
    done_step: int | None = None
    final_iteration: int | None = None


@dataclass
class _Mst:
    key: int
    alive: tuple[int, ...]
    agents: dict[int, MstAgent]  # instant -> agent
    local_radii_m: np.ndarray  # centralised reference per instant
    start_step: int
    sent: dict[tuple[int, int, int], MstMessage] = field(default_factory=dict)  # (instant, round, kind)
    probes: dict[tuple[int, int], dict[int, MstMessage]] = field(default_factory=dict)  # (k, round)
    merges: dict[tuple[int, int], dict[int, MstMessage]] = field(default_factory=dict)
    finished_step: int | None = None
    failed: str = ""


class SearchCoordinator:
    """One agent's side of the distributed coverage search (see the module doc)."""

    def __init__(
        self,
        uav_id: int,
        uav_count: int,
        area_m: tuple[float, float, float, float],
        seed: int,
        config: SearchConfig | None = None,
        rng: np.random.Generator | None = None,
    ) -> None:
        """``area_m`` = (x_min, x_max, y_min, y_max) [m]; ``seed`` the scenario seed shared by the fleet
        (it draws the common candidate pool); ``rng`` this agent's generator for Thompson draws
        (default: seeded from ``seed`` and ``uav_id``)."""
        if not 0 <= uav_id < uav_count or uav_count > 255:
            raise SearchConfigError(f"need 0 <= uav_id < uav_count <= 255, got {uav_id}, {uav_count}")
        self.uav_id = int(uav_id)
        self.n = int(uav_count)
        self.config = cfg = config or SearchConfig()
        cell = cfg.cell_size_m or default_cell_size_m(area_m, cfg.sensor_range_m)
        self.grid = CoverageGrid.from_area(*area_m, cell_size_m=cell)
        self.problem = SearchProblem(
            grid=self.grid,
            n_agents=self.n,
            energy=EnergyModel(speed_mps=cfg.speed_mps),
            lambda_m_per_j=cfg.lambda_m_per_j,
            balance=BalanceConfig(epsilon=cfg.epsilon, max_iterations=cfg.balance_max_iterations),
            n_time_samples=cfg.n_time_samples,
            sensor_range_m=cfg.sensor_range_m,
            mst_backend="centralised",  # the distributed version runs over the wire (phase 6)
        )
        self.quad = quadrature(self.grid, self.problem.balance.subdiv)
        pool = make_pool(self.problem, cfg.pool_size, np.random.default_rng([int(seed), 0x5EA7C4]))
        n_init = 2 if cfg.mode == "bo" else cfg.budget + 1  # random: uniform pool draws only
        rng = rng if rng is not None else np.random.default_rng([int(seed), self.uav_id, 0x5EA7C4])
        self.bo = BoAgent(
            self.uav_id,
            self.problem,
            pool,
            rng,
            BoConfig(budget=cfg.budget, pool_size=cfg.pool_size, ts_subset=cfg.ts_subset, n_init=n_init),
        )
        self.share = cfg.budget // self.n + (1 if self.uav_id < cfg.budget % self.n else 0)
        max_share = math.ceil(cfg.budget / self.n)
        self.bo_end_step = cfg.bo_start_step + max_share + cfg.consume_delay_steps
        self.agree_end_step = self.bo_end_step + cfg.agree_steps
        self.planner = SearchPlanner(cfg)
        self.known: dict[int, CandidateMessage] = {}  # candidate id -> COST message
        self.adopted: CandidateMessage | None = None
        self.plan: SearchPlan | None = None
        self.plans: list[SearchPlan] = []
        self.own_evaluations = 0
        self.mst_results: list[dict] = []  # one per finished/failed MST session
        self.log: list[str] = []  # human-readable decisions; the node drains and logs them
        self._held: list[Envelope] = []
        self._balance: _Balance | None = None
        self._mst: _Mst | None = None
        self._alive: tuple[int, ...] = tuple(range(self.n))
        self.step = -1

    # --- public views ----------------------------------------------------------------------------
    @property
    def phase(self) -> Phase:
        if self.adopted is None:
            return Phase.OPTIMISE if self.step < self.bo_end_step else Phase.AGREE
        b = self._balance
        flying = self.plan is not None and (b is None or b.done_step is not None)
        return Phase.FLY if flying else Phase.BALANCE

    @property
    def mst_radius_m(self) -> float | None:
        """r_max of the newest finished message-passing MST, or None."""
        done = [r for r in self.mst_results if r["complete"]]
        return done[-1]["radius_m"] if done else None

    # --- the step ----------------------------------------------------------------------------------
    def on_step(
        self, t_s: float, step: int, alive_ids: Iterable[int], inbox: Iterable[Envelope] = ()
    ) -> list[Envelope]:
        """Consume ``inbox`` (coverage messages received since the last call), act, return what to publish."""
        cfg = self.config
        self.step = int(step)
        alive = tuple(sorted({int(a) for a in alive_ids if 0 <= int(a) < self.n} | {self.uav_id}))
        self._alive = alive
        self._held.extend(e for e in inbox if e.sender != self.uav_id and 0 <= e.sender < self.n)
        ready = [e for e in self._held if e.step <= step - cfg.consume_delay_steps]
        self._held = [e for e in self._held if e.step > step - cfg.consume_delay_steps]
        out: list[Envelope] = []
        for e in sorted(ready, key=lambda e: (e.step, int(e.topic), e.sender)):
            self._consume(e)
        if self.adopted is None:
            self._optimise(step, out)
            if step >= self.agree_end_step and self.known:
                best = min(self.known.values(), key=_cost_key)
                self._adopt(best, f"adopted candidate {best.candidate_id:#x} cost {best.cost:.1f}")
        if self.adopted is not None:
            if (step + self.uav_id) % cfg.rebroadcast_every_steps == 0:
                out.append(Envelope(Topic.CANDIDATES, self.uav_id, step, self.adopted))
            if self._needs_balance(alive):
                self._start_balance(step, "alive set " + str(list(alive)))
            self._balance_step(step, out)
        self._mst_step(step, out)
        return out

    def _needs_balance(self, alive: tuple[int, ...]) -> bool:
        assert self.adopted is not None
        cid = self.adopted.candidate_id
        if self._balance is not None:
            return self._balance.alive != alive or self._balance.candidate.candidate_id != cid
        return self.plan is None or self.plan.alive != alive or self.plan.candidate_id != cid

    # --- receipt ----------------------------------------------------------------------------------------
    def _consume(self, e: Envelope) -> None:
        m = e.msg
        if e.topic == Topic.CANDIDATES and isinstance(m, CandidateMessage):
            if not _finite_candidate(m, self.n):
                return
            if m.kind == CandidateKind.PROPOSAL:
                self.bo.on_proposal(m)
                return
            if m.candidate_id not in self.known:
                self.known[m.candidate_id] = m
                self.bo.on_cost(m)
            if self.adopted is not None and _cost_key(m) < _cost_key(self.adopted):
                self._adopt(m, f"switched to cheaper candidate {m.candidate_id:#x} cost {m.cost:.1f}")
        elif e.topic == Topic.WEIGHTS and isinstance(m, WeightReport):
            b = self._balance
            if b is None or m.uav_id != e.sender or e.sender not in b.alive:
                return
            idx = b.alive.index(e.sender)
            same_seed = np.allclose((m.seed_x_m, m.seed_y_m), b.seeds_m[idx], atol=1e-6)
            if (
                same_seed
                and math.isclose(m.target_area_m2, b.target_m2, rel_tol=1e-9)
                and math.isfinite(m.weight_m2)
            ):
                b.reports[(int(m.iteration), e.sender)] = m
        elif e.topic == Topic.MST and isinstance(m, MstMessage):
            s = self._mst
            if s is None or m.sample_index // MST_KEY_STRIDE != s.key or e.sender not in s.alive:
                return
            k = m.sample_index % MST_KEY_STRIDE
            if k not in s.agents:
                return
            if m.kind == MstKind.PROBE:
                s.probes.setdefault((k, m.round), {})[e.sender] = m
            elif m.kind == MstKind.MERGE:
                s.merges.setdefault((k, m.round), {})[m.fragment_id] = m

    # --- phase 1-2: optimisation and agreement ----------------------------------------------------------
    def _optimise(self, step: int, out: list[Envelope]) -> None:
        cfg = self.config
        if cfg.bo_start_step <= step < self.bo_end_step and self.own_evaluations < self.share:
            if threadpool_limits is not None:
                with threadpool_limits(1):
                    prop, cost = self._evaluate_one()
            else:  # pragma: no cover
                prop, cost = self._evaluate_one()
            out.append(Envelope(Topic.CANDIDATES, self.uav_id, step, prop))
            out.append(Envelope(Topic.CANDIDATES, self.uav_id, step, cost))
        if step >= self.bo_end_step and self.known:
            best = min(self.known.values(), key=_cost_key)
            out.append(Envelope(Topic.CANDIDATES, self.uav_id, step, best))

    def _evaluate_one(self) -> tuple[CandidateMessage, CandidateMessage]:
        prop = self.bo.propose()
        cand = Candidate(np.array(prop.seeds_m, dtype=float), np.array(prop.start_offsets, dtype=float))
        ev = evaluate_candidate(self.problem, cand)
        cost = self.bo.cost_message(prop, ev)
        self.bo.on_cost(cost)
        self.known[cost.candidate_id] = cost
        self.own_evaluations += 1
        return prop, cost

    def _adopt(self, m: CandidateMessage, why: str) -> None:
        self.adopted = m
        self.log.append(f"search: {why}")
        self._balance = None  # restart balancing with the new seeds

    # --- phase 3-5: balancing and plan ------------------------------------------------------------------
    def _start_balance(self, step: int, why: str) -> None:
        assert self.adopted is not None
        alive = self._alive
        seeds = np.array([self.adopted.seeds_m[i] for i in alive], dtype=float)
        target = float(equal_targets_m2(self.grid, len(alive))[0])
        agent = BalancerAgent(self.uav_id, seeds[alive.index(self.uav_id)], target, self.quad,
                              self.problem.balance, fleet_ids=alive)  # fmt: skip
        self._balance = _Balance(self.adopted, alive, seeds, target, agent, step, step)
        if self.plan is not None:
            self.log.append(f"search: re-partitioning ({why})")

    def _balance_step(self, step: int, out: list[Envelope]) -> None:
        b = self._balance
        if b is None:
            return
        cfg = self.config
        if b.done_step is None:
            for _ in range(cfg.balance_max_iterations + 1):  # advance while complete iterations are held
                it = b.agent.iteration
                b.own_reports[it] = b.agent.report()
                b.reports[(it, self.uav_id)] = b.own_reports[it]
                got = {u: b.reports.get((it, u)) for u in b.alive}
                if any(r is None for r in got.values()):
                    break
                converged = b.agent.step(got)  # type: ignore[arg-type]
                b.last_progress_step = step
                if converged or it >= cfg.balance_max_iterations:
                    b.final_iteration = it
                    b.done_step = step
                    self._finish_plan(
                        step,
                        np.array([r.weight_m2 for r in got.values() if r is not None]),
                        b.agent.e_max,
                        it,
                        True,
                    )
                    break
            else:  # pragma: no cover - bounded by max_iterations
                pass
            if b.done_step is None and step - b.last_progress_step >= cfg.balance_timeout_steps:
                res = balance_weights(self.grid, b.seeds_m, self.problem.balance, quad=self.quad)
                b.done_step = step
                b.final_iteration = b.agent.iteration
                self.log.append(
                    f"search: weight exchange stalled at iteration {b.agent.iteration}; balanced locally"
                )
                self._finish_plan(step, res.weights_m2, res.e_max, res.iterations, False)
        # (re-)send the current and previous iteration's own reports (a peer lags at most one)
        if b.done_step is None or step - b.done_step < cfg.linger_steps:
            it = b.final_iteration if b.final_iteration is not None else b.agent.iteration
            for k in (it - 1, it):
                r = b.own_reports.get(k)
                if r is not None:
                    out.append(Envelope(Topic.WEIGHTS, self.uav_id, step, r))
        if b.done_step is not None and step - b.done_step >= cfg.linger_steps:
            self._balance = None

    def _finish_plan(self, step: int, weights: np.ndarray, e_max: float, iterations: int, via: bool) -> None:
        b = self._balance
        assert b is not None and self.adopted is not None
        first = self.plan is None
        idx_labels = make_regions_connected(assign_cells(self.grid, b.seeds_m, weights, quad=self.quad))
        ids = np.array(b.alive)
        labels = np.where(idx_labels >= 0, ids[np.clip(idx_labels, 0, None)], -1)
        r = self.problem.arc_radius_m
        paths: dict[int, CoveragePath] = {}
        for i, u in enumerate(b.alive):
            region = labels == u
            if region.any():
                paths[u] = stc_path(region, x_min_m=self.grid.x_min_m, y_min_m=self.grid.y_min_m,
                                    cell_size_m=self.grid.cell_size_m, turn_radius_m=r)  # fmt: skip
            else:
                paths[u] = loiter_path(b.seeds_m[i], r)
        offsets = {u: float(b.candidate.start_offsets[u]) for u in b.alive}
        plan = SearchPlan(int(b.candidate.candidate_id), b.alive, b.seeds_m, np.asarray(weights, dtype=float),
                          labels, paths, offsets, float(e_max), int(iterations), via, step)  # fmt: skip
        self.plan = plan
        self.plans.append(plan)
        self.planner.set_path(paths[self.uav_id], offsets[self.uav_id] if first else None)
        own = int(np.count_nonzero(labels == self.uav_id))
        self.log.append(
            f"search: plan for uavs {list(b.alive)} ready ({'messages' if via else 'local fallback'}, "
            f"{iterations} iterations, E_max {e_max:.3f}); own region {own} cells, "
            f"path {paths[self.uav_id].length_m:.0f} m"
        )
        self._start_mst(step, plan)

    # --- phase 6: message-passing MST ----------------------------------------------------------------
    def _start_mst(self, step: int, plan: SearchPlan) -> None:
        if self._mst is not None and self._mst.finished_step is None:
            self._record_mst(self._mst, step, "superseded by a new plan")
        key = 1 + zlib.crc32(repr((plan.candidate_id, plan.alive)).encode()) % 4000
        paths = tuple(plan.paths[u] for u in plan.alive)
        offs = np.array([plan.start_offsets[u] for u in plan.alive])
        pos = positions_normalised_time(paths, offs, self.config.n_time_samples)  # (K, A, 2)
        _, local = mission_radius_m(pos, backend="centralised")
        me = plan.alive.index(self.uav_id)
        agents = {}
        for k in range(len(pos)):
            d = np.linalg.norm(pos[k] - pos[k, me][None, :], axis=1)
            agents[k] = MstAgent(self.uav_id, {u: float(d[j]) for j, u in enumerate(plan.alive) if u != self.uav_id},
                                 sample_index=key * MST_KEY_STRIDE + k)  # fmt: skip
        self._mst = _Mst(key, plan.alive, agents, local, step)

    def _mst_step(self, step: int, out: list[Envelope]) -> None:
        s = self._mst
        if s is None:
            return
        if s.finished_step is None:
            try:
                for k, a in s.agents.items():
                    self._mst_advance(s, k, a)
            except MstError as exc:  # inconsistent messages: give up on this session, never hang
                self._record_mst(s, step, f"error: {exc}")
            if s.finished_step is None and all(a.done for a in s.agents.values()):
                self._record_mst(s, step, "")
            elif s.finished_step is None and step - s.start_step >= self.config.mst_timeout_steps:
                self._record_mst(s, step, "timeout")
        if s.finished_step is not None and step - s.finished_step >= self.config.linger_steps // 4:
            return
        for k, a in s.agents.items():
            r = a.round
            for key in ((k, r - 1, MstKind.MERGE), (k, r, MstKind.PROBE), (k, r, MstKind.MERGE), (k, r, MstKind.DONE),
                        (k, r - 1, MstKind.DONE)):  # fmt: skip
                m = s.sent.get(key)
                if m is not None:
                    out.append(Envelope(Topic.MST, self.uav_id, step, m))

    def _mst_advance(self, s: _Mst, k: int, a: MstAgent) -> None:
        for _ in range(a.n_agents + 1):
            if a.done:
                return
            r = a.round
            if (k, r, MstKind.PROBE) not in s.sent:
                p = a.probe()
                s.sent[(k, r, MstKind.PROBE)] = p
                s.probes.setdefault((k, r), {})[self.uav_id] = p
            if a.is_root and (k, r, MstKind.MERGE) not in s.sent:
                held = s.probes.get((k, r), {})
                members = a.members(a.fragment_id)
                if not all(v in held for v in members):
                    return
                m = a.on_probes([held[v] for v in members])
                if m is not None:
                    s.sent[(k, r, MstKind.MERGE)] = m
                    s.merges.setdefault((k, r), {})[m.fragment_id] = m
            roots = {a.fragment_of[v] for v in a.agent_ids}
            got = s.merges.get((k, r), {})
            if not roots <= set(got):
                return
            done = a.on_merges([got[f] for f in sorted(roots)])
            if done is not None:
                s.sent[(k, r, MstKind.DONE)] = done

    def _record_mst(self, s: _Mst, step: int, failure: str) -> None:
        s.finished_step = step
        s.failed = failure
        radii = np.array([a.radius_m if a.done else math.nan for a in s.agents.values()])
        complete = not failure and bool(np.all(np.isfinite(radii)))
        r_msg = float(np.nanmax(radii)) if np.any(np.isfinite(radii)) else math.nan
        r_local = float(np.max(s.local_radii_m))
        res = {
            "key": s.key,
            "alive": s.alive,
            "complete": complete,
            "radius_m": r_msg,
            "local_radius_m": r_local,
            "instants_done": int(np.sum(np.isfinite(radii))),
            "instants": len(radii),
            "steps": step - s.start_step,
            "failure": failure,
        }
        self.mst_results.append(res)
        if complete:
            self.log.append(
                f"search: MST over messages: r_max {r_msg:.1f} m (centralised {r_local:.1f} m) "
                f"after {res['steps']} steps"
            )
        else:
            self.log.append(
                f"search: MST over messages incomplete ({failure or 'missing'}; {res['instants_done']}/"
                f"{res['instants']} instants, r_max so far {r_msg:.1f} m, centralised {r_local:.1f} m)"
            )


def plan_is_partition(plan: SearchPlan, grid: CoverageGrid) -> bool:
    """Every free cell owned by exactly one alive uav, no non-free cell owned (Eq. 9)."""
    lab = plan.labels
    return bool(np.all((lab >= 0) == grid.free) and set(np.unique(lab[lab >= 0])) <= set(plan.alive))


def agreed(coordinators: Sequence[SearchCoordinator]) -> bool:
    """All given coordinators fly plans of the same candidate and alive set."""
    keys = {(c.plan.candidate_id, c.plan.alive) if c.plan else None for c in coordinators}
    return len(keys) == 1 and None not in keys
