"""Asynchronous distributed Bayesian optimisation by Thompson sampling (CP III-F), and a baseline.

Search space: the unit cube [0, 1]^(3N) encoding a joint candidate (seeds and start offsets of all N
agents, see :meth:`SearchProblem.candidate_from_unit`). As in CP III-F a finite candidate set
``X`` (the *pool*) is generated once at the start from the shared scenario seed, so every agent
holds the same pool.

Each :class:`BoAgent` keeps its own data set of (candidate, cost) observations and its own GP
surrogate (scikit-learn ``GaussianProcessRegressor``, constant x Matern(nu = 5/2) + white noise,
normalised targets, hyper-parameters refitted by maximum likelihood at each proposal). When free, it
draws one joint sample ``f~`` of the posterior over the pool and proposes ``argmin f~`` (Thompson
sampling, Kandasamy et al. 2018); the first ``n_init`` proposals of an agent with too little data are
uniform draws from the pool. Proposals and costs are broadcast as :class:`CandidateMessage`
(field-for-field ``fire_uav_msgs/CoverageCandidate``).

Loss tolerance: nothing ever waits for a message. A lost COST only means the receiver's GP lacks
that point; a lost PROPOSAL only means the receiver may later propose the same pool point
(choices: an agent excludes pool points it knows were proposed or evaluated; the proposer always
evaluates its own candidate, because every stage of the pipeline is a deterministic function of
the candidate -- the paper instead spreads the evaluation over all agents, which would make a lost
proposal stall that candidate).

:func:`run_async_bo` is a seeded discrete-event simulation of the fleet (random evaluation times
and message delays, Bernoulli message loss); :func:`run_random_search` is the random-sampling
baseline of CP IV / Fig. 8 with the same evaluation budget and pool.
"""

from __future__ import annotations

import heapq
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from fire_uav_common.constants import CandidateKind

from .errors import OptimizationError, SearchConfigError
from .evaluate import Candidate, Evaluation, SearchProblem, evaluate_candidate

if TYPE_CHECKING:
    from sklearn.gaussian_process import GaussianProcessRegressor


class CandidateMessage(NamedTuple):
    """Field-for-field ``fire_uav_msgs/CoverageCandidate`` (header omitted)."""

    uav_id: int
    kind: CandidateKind
    candidate_id: int  # (sender id << 16) | local counter
    seeds_m: tuple[tuple[float, float], ...]  # one per agent, index = uav id [m; map frame]
    start_offsets: tuple[float, ...]  # [-] in [0, 1)
    energy_j: float  # sum_i E_i [J], COST only
    radio_radius_m: float  # r_max [m], COST only
    cost: float  # lambda * sum E_i + r_max, COST only


def make_candidate_id(uav_id: int, counter: int) -> int:
    """``(sender id << 16) | local counter`` as in CoverageCandidate.msg."""
    if not (0 <= uav_id < 256 and 0 <= counter < 1 << 16):
        raise SearchConfigError(f"uav_id must be < 256 and counter < 65536, got {uav_id}, {counter}")
    return (uav_id << 16) | counter


@dataclass(frozen=True)
class BoConfig:
    """Parameters of the asynchronous optimisation and of its simulated network."""

    budget: int = 40  # total candidate evaluations across the fleet
    pool_size: int = 1024  # size of the candidate set X
    n_init: int = 2  # an agent with fewer observations proposes uniformly from the pool
    length_scale: float = 0.5  # initial isotropic Matern length scale (unit cube)
    loss_probability: float = 0.0  # per message and receiver
    eval_time_s: tuple[float, float] = (0.5, 1.5)  # simulated evaluation duration, uniform
    delay_s: tuple[float, float] = (0.01, 0.2)  # simulated message delay, uniform
    ts_subset: int = 256  # pool points per Thompson draw (random subset of the free ones)
    local_points: int = 0  # extra Thompson points: Gaussian perturbations of the own incumbent
    local_sigma: float = 0.05  # their standard deviation in the unit cube
    jitter: float = 1e-6  # relative, added to the posterior covariance diagonal

    def __post_init__(self) -> None:
        if self.budget < 1 or self.pool_size < self.budget:
            raise SearchConfigError("need budget >= 1 and pool_size >= budget")
        if self.n_init < 1 or self.length_scale <= 0.0 or self.ts_subset < 1:
            raise SearchConfigError("need n_init >= 1 and length_scale > 0")
        if not 0.0 <= self.loss_probability < 1.0:
            raise SearchConfigError(f"loss_probability must be in [0, 1), got {self.loss_probability}")
        for lo, hi in (self.eval_time_s, self.delay_s):
            if not 0.0 <= lo <= hi:
                raise SearchConfigError("time ranges must satisfy 0 <= low <= high")


def make_pool(problem: SearchProblem, size: int, rng: np.random.Generator) -> np.ndarray:
    """Candidate set X: ``size`` uniform points of the unit cube, shape (size, 3N)."""
    return rng.uniform(0.0, 1.0, size=(size, problem.dim))


def _gp(dim: int, length_scale: float) -> GaussianProcessRegressor:
    # scikit-learn (about 40 MiB and 1 s) is imported by the first search agent that fits a GP,
    # not by every agent at start (docs/profile.md)
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import ConstantKernel, Matern, WhiteKernel

    kernel = ConstantKernel(1.0, (1e-2, 1e2)) * Matern(
        length_scale=length_scale, length_scale_bounds=(1e-2, 1e1), nu=2.5
    ) + WhiteKernel(1e-2, (1e-6, 1e0))
    return GaussianProcessRegressor(kernel=kernel, normalize_y=True, n_restarts_optimizer=0)


class BoAgent:
    """One agent's optimiser: its observations, its GP, its proposals (CP III-F)."""

    def __init__(
        self,
        uav_id: int,
        problem: SearchProblem,
        pool: np.ndarray,
        rng: np.random.Generator,
        config: BoConfig | None = None,
    ) -> None:
        self.uav_id = int(uav_id)
        self.problem = problem
        self.pool = np.asarray(pool, dtype=float)
        if self.pool.ndim != 2 or self.pool.shape[1] != problem.dim:
            raise SearchConfigError(f"pool must have shape (M, {problem.dim}), got {self.pool.shape}")
        self.rng = rng
        self.config = config or BoConfig()
        self.counter = 0
        self.observations: dict[int, tuple[np.ndarray, float]] = {}  # candidate_id -> (x, cost)
        self._taken: set[int] = set()  # pool indices known proposed or evaluated

    def _pool_index(self, x: np.ndarray) -> int | None:
        d = np.abs(self.pool - x[None, :]).max(axis=1)
        k = int(np.argmin(d))
        return k if d[k] < 1e-9 else None

    def _message(self, kind: CandidateKind, cid: int, x: np.ndarray, **cost: float) -> CandidateMessage:
        c = self.problem.candidate_from_unit(x)
        return CandidateMessage(
            uav_id=self.uav_id,
            kind=kind,
            candidate_id=cid,
            seeds_m=tuple((float(a), float(b)) for a, b in c.seeds_m),
            start_offsets=tuple(float(s) for s in c.start_offsets),
            energy_j=cost.get("energy_j", math.nan),
            radio_radius_m=cost.get("radio_radius_m", math.nan),
            cost=cost.get("cost", math.nan),
        )

    def _x_of(self, msg: CandidateMessage) -> np.ndarray:
        return self.problem.candidate_to_unit(
            Candidate(np.array(msg.seeds_m, dtype=float), np.array(msg.start_offsets, dtype=float))
        )

    def propose(self) -> CandidateMessage:
        """Thompson-sampling proposal (or a uniform pool draw while data are scarce)."""
        free = np.setdiff1d(np.arange(len(self.pool)), np.fromiter(self._taken, int, len(self._taken)))
        if free.size == 0:
            raise OptimizationError(f"agent {self.uav_id}: candidate pool exhausted")
        if len(self.observations) < self.config.n_init:
            k = int(self.rng.choice(free))
        else:
            if free.size > self.config.ts_subset:
                free = self.rng.choice(free, size=self.config.ts_subset, replace=False)
            xs = self.pool[free]
            if self.config.local_points > 0:
                xs = np.vstack([xs, self._local_points()])
            j = int(np.argmin(self.thompson_sample(xs)))
            if j >= free.size:
                cid = make_candidate_id(self.uav_id, self.counter)
                self.counter += 1
                return self._message(CandidateKind.PROPOSAL, cid, xs[j])
            k = int(free[j])
        self._taken.add(k)
        cid = make_candidate_id(self.uav_id, self.counter)
        self.counter += 1
        return self._message(CandidateKind.PROPOSAL, cid, self.pool[k])

    def _local_points(self) -> np.ndarray:
        """Perturbations of the best known point: seeds clipped to the cube, offsets wrapped."""
        best = min(self.observations.values(), key=lambda d: d[1])[0]
        n = self.problem.n_agents
        pts = best[None, :] + self.config.local_sigma * self.rng.standard_normal(
            (self.config.local_points, len(best))
        )
        pts[:, : 2 * n] = np.clip(pts[:, : 2 * n], 0.0, 1.0)
        pts[:, 2 * n :] = np.mod(pts[:, 2 * n :], 1.0)
        return pts

    def thompson_sample(self, xs: np.ndarray) -> np.ndarray:
        """One joint draw of the GP posterior at ``xs`` (M, D), using this agent's generator."""
        data = list(self.observations.values())
        x = np.array([d[0] for d in data])
        y = np.array([d[1] for d in data])
        gp = _gp(self.problem.dim, self.config.length_scale)
        from sklearn.exceptions import ConvergenceWarning

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            gp.fit(x, y)
            mean, cov = gp.predict(xs, return_cov=True)
        cov = 0.5 * (cov + cov.T)
        jitter = self.config.jitter * max(1.0, float(np.mean(np.diag(cov))))
        for _ in range(6):
            try:
                chol = np.linalg.cholesky(cov + jitter * np.eye(len(xs)))
                break
            except np.linalg.LinAlgError:
                jitter *= 100.0
        else:  # pragma: no cover - covariance is PSD up to round-off
            w, v = np.linalg.eigh(cov)
            chol = v * np.sqrt(np.clip(w, 0.0, None))
        return mean + chol @ self.rng.standard_normal(len(xs))

    def on_proposal(self, msg: CandidateMessage) -> None:
        """A peer's proposal: remember the pool point as taken (avoids duplicate proposals)."""
        k = self._pool_index(self._x_of(msg))
        if k is not None:
            self._taken.add(k)

    def on_cost(self, msg: CandidateMessage) -> None:
        """An evaluated candidate (own or a peer's): add it to the GP data."""
        if not math.isfinite(msg.cost):
            raise OptimizationError(f"agent {self.uav_id}: non-finite cost for candidate {msg.candidate_id}")
        x = self._x_of(msg)
        self.observations[msg.candidate_id] = (x, float(msg.cost))
        k = self._pool_index(x)
        if k is not None:
            self._taken.add(k)

    def cost_message(self, proposal: CandidateMessage, evaluation: Evaluation) -> CandidateMessage:
        """The COST message for one of this agent's evaluated proposals."""
        return proposal._replace(
            kind=CandidateKind.COST,
            energy_j=float(evaluation.energy_j),
            radio_radius_m=float(evaluation.radius_m),
            cost=float(evaluation.cost),
        )

    def incumbent(self) -> tuple[int, float] | None:
        """(candidate_id, cost) of the best observation this agent knows, or None."""
        if not self.observations:
            return None
        cid = min(self.observations, key=lambda k: self.observations[k][1])
        return cid, self.observations[cid][1]


class OptimisationTrace(NamedTuple):
    """History of one optimisation run, in evaluation-completion order."""

    costs: np.ndarray  # (budget,) cost of each evaluation
    best_so_far: np.ndarray  # (budget,) running minimum
    proposers: np.ndarray  # (budget,) uav id of the proposer
    candidates: tuple[Candidate, ...]
    best_candidate: Candidate
    observations_per_agent: np.ndarray  # (N,) size of each agent's data set at the end
    messages_sent: int
    messages_lost: int


def _trace(
    costs: list[float],
    proposers: list[int],
    cands: list[Candidate],
    obs: list[int],
    sent: int,
    lost: int,
) -> OptimisationTrace:
    c = np.array(costs)
    return OptimisationTrace(
        costs=c,
        best_so_far=np.minimum.accumulate(c),
        proposers=np.array(proposers, dtype=int),
        candidates=tuple(cands),
        best_candidate=cands[int(np.argmin(c))],
        observations_per_agent=np.array(obs, dtype=int),
        messages_sent=sent,
        messages_lost=lost,
    )


Objective = Callable[
    [SearchProblem, Candidate], Any
]  # returns an Evaluation-like .cost, .energy_j, .radius_m


def _pool(
    problem: SearchProblem, config: BoConfig, rng: np.random.Generator, pool: np.ndarray | None
) -> np.ndarray:
    """The candidate pool in unit coordinates: the given one, else ``config.pool_size`` draws from ``rng``."""
    return make_pool(problem, config.pool_size, rng) if pool is None else np.asarray(pool, dtype=float)


def run_async_bo(
    problem: SearchProblem,
    rng: np.random.Generator,
    config: BoConfig | None = None,
    *,
    objective: Objective = evaluate_candidate,
    pool: np.ndarray | None = None,
) -> OptimisationTrace:
    """Discrete-event simulation of N agents running asynchronous Thompson sampling.

    One generator ``rng`` seeds the pool, one child generator per agent, and the network (delays,
    losses). Stops after ``config.budget`` evaluations in total; in-flight messages are delivered.
    """
    config = config or BoConfig()
    n = problem.n_agents
    pool = _pool(problem, config, rng, pool)
    agent_rngs = rng.spawn(n)
    net_rng = rng.spawn(1)[0]
    agents = [BoAgent(i, problem, pool, agent_rngs[i], config) for i in range(n)]
    events: list[tuple[float, int, str, int, Any]] = []
    seq = 0

    def push(t: float, kind: str, who: int, payload: Any) -> None:
        nonlocal seq
        heapq.heappush(events, (t, seq, kind, who, payload))
        seq += 1

    sent = lost = 0

    def broadcast(t: float, sender: int, msg: CandidateMessage) -> None:
        nonlocal sent, lost
        for b in range(n):
            if b == sender:
                continue
            sent += 1
            if net_rng.uniform() < config.loss_probability:
                lost += 1
                continue
            push(t + net_rng.uniform(*config.delay_s), "deliver", b, msg)

    for i in range(n):
        push(net_rng.uniform(0.0, config.eval_time_s[0]), "free", i, None)
    started = 0
    costs, proposers, cands = [], [], []
    while events:
        t, _, kind, who, payload = heapq.heappop(events)
        agent = agents[who]
        if kind == "free":
            if started >= config.budget:
                continue
            started += 1
            prop = agent.propose()
            broadcast(t, who, prop)
            push(t + net_rng.uniform(*config.eval_time_s), "done", who, prop)
        elif kind == "done":
            prop = payload
            cand = Candidate(np.array(prop.seeds_m), np.array(prop.start_offsets))
            ev = objective(problem, cand)
            msg = agent.cost_message(prop, ev)
            agent.on_cost(msg)
            broadcast(t, who, msg)
            costs.append(msg.cost)
            proposers.append(who)
            cands.append(cand)
            push(t, "free", who, None)
        else:  # deliver
            if payload.kind == CandidateKind.PROPOSAL:
                agent.on_proposal(payload)
            else:
                agent.on_cost(payload)
    return _trace(costs, proposers, cands, [len(a.observations) for a in agents], sent, lost)


def run_random_search(
    problem: SearchProblem,
    rng: np.random.Generator,
    config: BoConfig | None = None,
    *,
    objective: Objective = evaluate_candidate,
    pool: np.ndarray | None = None,
) -> OptimisationTrace:
    """Random-sampling baseline: ``budget`` distinct uniform draws from the same kind of pool."""
    config = config or BoConfig()
    pool = _pool(problem, config, rng, pool)
    idx = rng.choice(len(pool), size=config.budget, replace=False)
    cands = [problem.candidate_from_unit(pool[k]) for k in idx]
    costs = [float(objective(problem, c).cost) for c in cands]
    return _trace(costs, [-1] * len(cands), cands, [len(cands)] * problem.n_agents, 0, 0)
