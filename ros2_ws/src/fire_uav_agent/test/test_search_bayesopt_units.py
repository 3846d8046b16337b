"""Fast unit tests of the BO pieces (CP III-F) against independent references.

The GP surrogate against the closed-form posterior computed here with numpy.linalg, the
posterior interpolating noise-free data, Thompson draws' standardised residuals against
N(0, 1), the argmin of a known bowl, the candidate bookkeeping (pool points taken, ids,
messages) and the simulated network's message counts. Objectives are cheap stand-ins (no
coverage planning), so each test takes well under 0.5 s.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import pytest
from fire_uav_agent.search.bayesopt import (
    BoAgent,
    BoConfig,
    CandidateKind,
    _gp,
    make_candidate_id,
    make_pool,
    run_async_bo,
    run_random_search,
)
from fire_uav_agent.search.errors import OptimizationError, SearchConfigError
from fire_uav_agent.search.evaluate import SearchProblem
from fire_uav_agent.search.power_diagram import CoverageGrid
from threadpoolctl import threadpool_limits


@pytest.fixture(autouse=True)
def _single_thread_blas():
    with threadpool_limits(1):
        yield


@pytest.fixture(scope="module")
def one() -> SearchProblem:
    """One agent: the unit cube is 3-D (seed x, seed y, start offset)."""
    grid = CoverageGrid.from_area(0.0, 600.0, 0.0, 600.0, cell_size_m=120.0)
    return SearchProblem(grid=grid, n_agents=1, n_time_samples=10)


@pytest.fixture(scope="module")
def three() -> SearchProblem:
    grid = CoverageGrid.from_area(0.0, 600.0, 0.0, 600.0, cell_size_m=120.0)
    return SearchProblem(grid=grid, n_agents=3, n_time_samples=10)


class _Ev(NamedTuple):
    cost: float
    energy_j: float
    radius_m: float


def _bowl(problem: SearchProblem, cand) -> _Ev:
    u = problem.candidate_to_unit(cand)
    return _Ev(float(np.sum((u - 0.5) ** 2)), 1.0, 2.0)


def _observe(agent: BoAgent, xs: np.ndarray, ys: np.ndarray, first_id: int = 1000) -> None:
    """Feed (x, y) pairs to the agent as a peer's COST messages."""
    peer = BoAgent(1, agent.problem, agent.pool, np.random.default_rng(0), agent.config)
    for k, (x, y) in enumerate(zip(xs, ys, strict=True)):
        msg = peer._message(CandidateKind.COST, first_id + k, np.asarray(x, dtype=float))
        agent.on_cost(msg._replace(cost=float(y)))


# --- configuration errors: each names what is wrong, boundary values accepted --------------


def test_config_boundaries_are_accepted() -> None:
    BoConfig(budget=1, pool_size=1)  # budget >= 1, pool_size >= budget: equality allowed
    BoConfig(budget=5, pool_size=5, n_init=1, ts_subset=1)
    BoConfig(eval_time_s=(0.0, 0.0), delay_s=(0.0, 0.0))  # 0 <= low <= high


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"budget": 0, "pool_size": 4}, r"^need budget >= 1 and pool_size >= budget$"),
        ({"budget": 5, "pool_size": 4}, r"^need budget >= 1 and pool_size >= budget$"),
        ({"n_init": 0}, r"^need n_init >= 1 and length_scale > 0$"),
        ({"length_scale": 0.0}, r"^need n_init >= 1 and length_scale > 0$"),
        ({"ts_subset": 0}, r"^need n_init >= 1 and length_scale > 0$"),
        ({"eval_time_s": (2.0, 1.0)}, r"^time ranges must satisfy 0 <= low <= high$"),
        ({"delay_s": (-0.1, 0.2)}, r"^time ranges must satisfy 0 <= low <= high$"),
    ],
)
def test_config_errors_name_the_problem(kwargs: dict, match: str) -> None:
    with pytest.raises(SearchConfigError, match=match):
        BoConfig(**kwargs)


def test_candidate_id_range() -> None:
    assert make_candidate_id(255, (1 << 16) - 1) == (255 << 16) | 0xFFFF  # uint8 sender fits
    with pytest.raises(SearchConfigError, match=r"uav_id must be < 256 and counter < 65536, got 256, 0"):
        make_candidate_id(256, 0)


def test_pool_is_uniform_on_the_unit_cube(one: SearchProblem) -> None:
    pool = make_pool(one, 4000, np.random.default_rng(1))
    assert pool.shape == (4000, 3)
    assert pool.min() >= 0.0 and pool.max() < 1.0
    # U(0, 1): mean 1/2, variance 1/12 (3 sigma of the estimate: 0.014 and 0.004)
    np.testing.assert_allclose(pool.mean(axis=0), 0.5, atol=0.015)
    np.testing.assert_allclose(pool.var(axis=0), 1 / 12, atol=0.005)


def test_pool_of_the_wrong_width_is_refused(one: SearchProblem) -> None:
    with pytest.raises(SearchConfigError, match=r"pool must have shape \(M, 3\), got \(4, 2\)"):
        BoAgent(0, one, np.zeros((4, 2)), np.random.default_rng(0))


# --- the GP surrogate: closed form, interpolation -------------------------------------------


def _matern52(a: np.ndarray, b: np.ndarray, ell: float) -> np.ndarray:
    """Matern nu = 5/2 correlation (Rasmussen & Williams Eq. 4.17), typed from the book."""
    r = np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1)) / ell
    return (1.0 + math.sqrt(5) * r + 5.0 * r**2 / 3.0) * np.exp(-math.sqrt(5) * r)


def test_gp_posterior_matches_the_closed_form() -> None:
    """Mean and covariance of constant x Matern(5/2) + white noise, normalised targets (module doc),
    by hand (R&W Eqs. 2.23-2.24) at the hyper-parameters the fit chose."""
    x = np.array([[0.1], [0.45], [0.9]])
    y = np.array([7.0, 5.5, 6.8])  # mean far from 0: the normalisation shows
    gp = _gp(1, 0.5).fit(x, y)
    c = gp.kernel_.k1.k1.constant_value
    ell = float(gp.kernel_.k1.k2.length_scale)
    noise = gp.kernel_.k2.noise_level
    xs = np.array([[0.0], [0.3], [0.7]])
    mean, cov = gp.predict(xs, return_cov=True)
    mu, sd = y.mean(), y.std()
    k = c * _matern52(x, x, ell) + noise * np.eye(3)
    ks = c * _matern52(xs, x, ell)
    kss = c * _matern52(xs, xs, ell) + noise * np.eye(3)
    want_mean = mu + sd * ks @ np.linalg.solve(k, (y - mu) / sd)
    want_cov = sd**2 * (kss - ks @ np.linalg.solve(k, ks.T))
    np.testing.assert_allclose(mean, want_mean, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(cov, want_cov, rtol=1e-7, atol=1e-9)


def test_gp_interpolates_noise_free_data() -> None:
    """Noise-free smooth data: the posterior passes through every point and is sure there
    (std < 0.5 % of the data's spread); between the points it predicts the function."""
    x = np.linspace(0.0, 1.0, 8)[:, None]
    f = lambda u: np.sin(2.0 * np.pi * u[:, 0])  # noqa: E731
    gp = _gp(1, 0.5).fit(x, f(x))
    m, s = gp.predict(x, return_std=True)
    np.testing.assert_allclose(m, f(x), atol=5e-3)
    assert s.max() < 5e-3 * f(x).std()
    mid = (x[:-1] + x[1:]) / 2
    np.testing.assert_allclose(gp.predict(mid), f(mid), atol=0.03)


def test_gp_fits_a_short_length_scale() -> None:
    """Four periods on [0, 1] need a length scale well below 1: held-out points still predicted."""
    x = np.linspace(0.0, 1.0, 33)[:, None]
    f = lambda u: np.sin(8.0 * np.pi * u[:, 0])  # noqa: E731
    gp = _gp(1, 0.5).fit(x, f(x))
    mid = (x[:-1] + x[1:]) / 2
    np.testing.assert_allclose(gp.predict(mid), f(mid), atol=0.05)


# --- Thompson draws -------------------------------------------------------------------------


def _agent_with_data(one: SearchProblem, cfg: BoConfig | None = None, seed: int = 0) -> BoAgent:
    pool = make_pool(one, 16, np.random.default_rng(7))
    agent = BoAgent(0, one, pool, np.random.default_rng(seed), cfg or BoConfig(budget=4, pool_size=16))
    xs = np.array([[0.2, 0.3, 0.4], [0.7, 0.6, 0.1], [0.5, 0.9, 0.8], [0.3, 0.2, 0.9]])
    _observe(agent, xs, np.array([1.0, 2.0, 0.5, 1.5]))
    return agent


def _standardised_draws(agent: BoAgent, xs: np.ndarray, n_draws: int) -> np.ndarray:
    """Thompson draws whitened by the posterior of an independently fitted GP: N(0, I) if right."""
    data = list(agent.observations.values())
    gp = _gp(3, agent.config.length_scale).fit(np.array([d[0] for d in data]), [d[1] for d in data])
    mean, cov = gp.predict(xs, return_cov=True)
    chol = np.linalg.cholesky(cov + 1e-12 * np.eye(len(xs)))
    return np.array([np.linalg.solve(chol, agent.thompson_sample(xs) - mean) for _ in range(n_draws)])


# on a data point, between data points, far from them
XS_PROBE = np.array(
    [
        [0.2, 0.3, 0.4],
        [0.45, 0.5, 0.5],
        [0.95, 0.05, 0.5],
        [0.05, 0.95, 0.05],
        [0.9, 0.9, 0.9],
        [0.1, 0.1, 0.9],
        [0.6, 0.2, 0.7],
        [0.3, 0.7, 0.2],
    ]
)


def test_thompson_draws_follow_the_posterior(one: SearchProblem) -> None:
    """Whitened draws are N(0, 1): 12 draws x 8 points, mean within 0.4 (4 sigma of the
    estimate), variance in [0.6, 1.6] (about 3 and 4 sigma)."""
    z = _standardised_draws(_agent_with_data(one), XS_PROBE, 12).ravel()
    assert abs(z.mean()) < 0.4
    assert 0.6 < z.var() < 1.6


def test_thompson_falls_back_when_cholesky_fails(one: SearchProblem, monkeypatch) -> None:
    """If no jittered Cholesky factor exists, the eigen-decomposition still draws from the posterior."""

    def no_cholesky(_a):
        raise np.linalg.LinAlgError("forced")

    agent = _agent_with_data(one)
    ref = _agent_with_data(one)
    data = list(ref.observations.values())
    gp = _gp(3, 0.5).fit(np.array([d[0] for d in data]), [d[1] for d in data])
    mean, cov = gp.predict(XS_PROBE, return_cov=True)
    chol = np.linalg.cholesky(cov + 1e-12 * np.eye(len(XS_PROBE)))
    monkeypatch.setattr(np.linalg, "cholesky", no_cholesky)
    draws = np.array([agent.thompson_sample(XS_PROBE) for _ in range(12)])
    monkeypatch.undo()
    z = np.linalg.solve(chol, (draws - mean).T).ravel()
    assert np.all(np.isfinite(z))
    assert abs(z.mean()) < 0.4  # as in test_thompson_draws_follow_the_posterior
    assert 0.6 < z.var() < 1.6


def test_thompson_proposes_the_clear_minimum_of_a_bowl(one: SearchProblem) -> None:
    """Bowl data on the 3 x 3 x 3 grid {0.2, 0.5, 0.8}^3 without its centre; of five free pool
    points one is the centre (cost 0), the others next to grid corners (cost ~0.27): every draw
    picks the centre (a uniform pick would, 1 time in 5)."""
    g = np.array([0.2, 0.5, 0.8])
    grid = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    centre = np.array([0.5, 0.5, 0.5])
    obs = grid[np.abs(grid - centre).max(axis=1) > 0.1]
    corners = grid[np.abs(grid - centre).min(axis=1) > 0.1][:4] + 0.01
    pool = np.vstack([obs, centre, corners])
    for seed in range(3):
        cfg = BoConfig(budget=4, pool_size=len(pool), n_init=len(obs))
        agent = BoAgent(0, one, pool, np.random.default_rng(seed), cfg)
        _observe(agent, obs, np.sum((obs - 0.5) ** 2, axis=1))
        msg = agent.propose()
        np.testing.assert_allclose(agent._x_of(msg), centre, atol=1e-9)


def test_thompson_with_a_subset_still_proposes_a_free_pool_point(one: SearchProblem) -> None:
    pool = make_pool(one, 40, np.random.default_rng(2))
    cfg = BoConfig(budget=4, pool_size=40, n_init=2, ts_subset=5)
    agent = BoAgent(0, one, pool, np.random.default_rng(1), cfg)
    _observe(agent, pool[:6], np.sum((pool[:6] - 0.5) ** 2, axis=1))
    seen = set()
    for _ in range(3):
        k = agent._pool_index(agent._x_of(agent.propose()))
        assert k is not None and k >= 6 and k not in seen
        seen.add(k)


# --- local points ----------------------------------------------------------------------------


def test_local_points_perturb_the_incumbent(one: SearchProblem) -> None:
    """N(best, sigma^2) per coordinate; seeds clipped to [0, 1], offsets wrapped into [0, 1)."""
    cfg = BoConfig(budget=4, pool_size=16, local_points=4000, local_sigma=0.05)
    agent = BoAgent(0, one, make_pool(one, 16, np.random.default_rng(0)), np.random.default_rng(4), cfg)
    best = np.array([0.5, 0.01, 0.98])
    _observe(agent, np.array([[0.1, 0.9, 0.3], best, [0.8, 0.2, 0.6]]), np.array([3.0, 1.0, 2.0]))
    pts = agent._local_points()
    assert pts.shape == (4000, 3)
    # interior seed coordinate: unclipped normal
    assert abs(pts[:, 0].mean() - 0.5) < 0.005 and abs(pts[:, 0].std() - 0.05) < 0.005
    # seed near 0: clipped, P(N(0.01, 0.05^2) < 0) = Phi(-0.2) = 0.421
    assert pts[:, 1].min() == 0.0 and pts[:, 1].max() <= 1.0
    assert abs(np.mean(pts[:, 1] == 0.0) - 0.421) < 0.03
    assert abs(np.median(pts[:, 1]) - 0.01) < 0.005
    # offset near 1: wrapped, P(N(0.98, 0.05^2) >= 1) = 1 - Phi(0.4) = 0.345 of them near 0
    off = pts[:, 2]
    assert off.min() >= 0.0 and off.max() < 1.0
    assert abs(np.mean(off < 0.5) - 0.345) < 0.03


def test_a_local_point_can_win_and_is_sent_off_pool(one: SearchProblem) -> None:
    """Free pool points all far from the incumbent at the bowl's bottom, a local point next to it:
    Thompson picks the local point; it is proposed as is, takes no pool point, and gets the next id."""
    centre = np.array([0.5, 0.5, 0.5])
    ring = np.array([[0.1, 0.1, 0.1], [0.9, 0.1, 0.9], [0.1, 0.9, 0.9], [0.9, 0.9, 0.1], [0.5, 0.1, 0.9]])
    obs = np.vstack([ring, centre + 0.02, [[0.2, 0.5, 0.5], [0.8, 0.5, 0.5], [0.5, 0.2, 0.5]]])
    far = np.array([[0.05, 0.95, 0.05], [0.95, 0.05, 0.05]])
    pool = np.vstack([obs, far])
    cfg = BoConfig(budget=4, pool_size=len(pool), n_init=1, local_points=1, local_sigma=0.01)
    agent = BoAgent(2, one, pool, np.random.default_rng(0), cfg)
    _observe(agent, obs, np.sum((obs - 0.5) ** 2, axis=1))
    taken = set(agent._taken)
    first = agent.propose()
    assert first.kind == CandidateKind.PROPOSAL and first.uav_id == 2
    assert first.candidate_id == make_candidate_id(2, 0)
    x = agent._x_of(first)
    assert agent._pool_index(x) is None  # not a pool point
    assert np.abs(x - (centre + 0.02)).max() < 0.06  # next to the incumbent
    assert agent._taken == taken
    second = agent.propose()
    assert second.candidate_id == make_candidate_id(2, 1)


# --- bookkeeping: taken pool points, ids, messages, incumbent --------------------------------


def test_proposals_skip_taken_points_until_the_pool_is_exhausted(one: SearchProblem) -> None:
    pool = make_pool(one, 4, np.random.default_rng(5))
    cfg = BoConfig(budget=4, pool_size=4, n_init=100)  # uniform proposals throughout
    agent = BoAgent(3, one, pool, np.random.default_rng(0), cfg)
    peer = BoAgent(1, one, pool, np.random.default_rng(1), cfg)
    agent.on_proposal(peer._message(CandidateKind.PROPOSAL, 7, pool[0]))
    agent.on_cost(peer._message(CandidateKind.COST, 8, pool[1])._replace(cost=1.0))
    # a point off the pool (a peer's local point) takes no pool point, not even the nearest
    agent.on_proposal(peer._message(CandidateKind.PROPOSAL, 9, pool[2] + 1e-3))
    got = {agent._pool_index(agent._x_of(agent.propose())) for _ in range(2)}
    assert got == {2, 3}  # each free point once, the last one too
    with pytest.raises(OptimizationError, match=r"agent 3: candidate pool exhausted"):
        agent.propose()


def test_messages_carry_the_candidate_and_the_cost(one: SearchProblem) -> None:
    pool = make_pool(one, 4, np.random.default_rng(5))
    agent = BoAgent(4, one, pool, np.random.default_rng(0), BoConfig(budget=2, pool_size=4))
    assert agent.config.pool_size == 4  # the given config, not the default
    a, b = agent.propose(), agent.propose()
    assert (a.candidate_id, b.candidate_id) == (make_candidate_id(4, 0), make_candidate_id(4, 1))
    assert a.uav_id == 4 and a.kind == CandidateKind.PROPOSAL
    assert math.isnan(a.energy_j) and math.isnan(a.radio_radius_m) and math.isnan(a.cost)
    k = agent._pool_index(agent._x_of(a))
    assert k is not None
    ev = _bowl(one, one.candidate_from_unit(pool[k]))
    c = agent.cost_message(a, ev)
    assert c.kind == CandidateKind.COST and c.candidate_id == a.candidate_id
    assert (c.energy_j, c.radio_radius_m, c.cost) == (1.0, 2.0, ev.cost)
    assert c.seeds_m == a.seeds_m


def test_incumbent_and_non_finite_cost(one: SearchProblem) -> None:
    pool = make_pool(one, 8, np.random.default_rng(5))
    agent = BoAgent(0, one, pool, np.random.default_rng(0), BoConfig(budget=2, pool_size=8))
    assert agent.incumbent() is None
    _observe(agent, pool[:3], np.array([2.0, 0.5, 1.0]), first_id=50)
    assert agent.incumbent() == (51, 0.5)
    bad = agent._message(CandidateKind.COST, 99, pool[4])
    with pytest.raises(OptimizationError, match=r"agent 0: non-finite cost for candidate 99"):
        agent.on_cost(bad)


# --- the simulated fleet and the baseline --------------------------------------------------


def test_message_counts_and_candidates_of_a_lossy_run(three: SearchProblem) -> None:
    """Every proposal and every cost goes to the N - 1 peers: 2 B (N - 1) sends, lost or not."""
    pool = make_pool(three, 30, np.random.default_rng(0))
    cfg = BoConfig(budget=9, pool_size=30, n_init=100, loss_probability=0.5)
    tr = run_async_bo(three, np.random.default_rng(2), cfg, objective=_bowl, pool=pool)
    assert tr.messages_sent == 2 * cfg.budget * (three.n_agents - 1)
    assert 0 < tr.messages_lost < tr.messages_sent
    units = np.array([three.candidate_to_unit(c) for c in tr.candidates])
    assert all(np.abs(pool - u).max(axis=1).min() < 1e-9 for u in units)  # the given pool's points
    np.testing.assert_allclose(tr.costs, np.sum((units - 0.5) ** 2, axis=1), atol=1e-12)
    best = three.candidate_to_unit(tr.best_candidate)
    np.testing.assert_allclose(best, units[int(np.argmin(tr.costs))], atol=1e-12)


def test_with_delays_longer_than_the_run_peers_duplicate_proposals(three: SearchProblem) -> None:
    """No proposal reaches a peer before the run ends, so agents pick from the whole pool on their
    own and repeat each other's points; with instant delivery every point is proposed once."""
    pool = make_pool(three, 6, np.random.default_rng(0))

    def dupes(delay: float) -> int:
        cfg = BoConfig(budget=6, pool_size=6, n_init=100, delay_s=(delay, delay))
        tr = run_async_bo(three, np.random.default_rng(1), cfg, objective=_bowl, pool=pool)
        units = np.array([three.candidate_to_unit(c) for c in tr.candidates]).round(9)
        return len(units) - len(np.unique(units, axis=0))

    assert dupes(1e6) > 0
    assert dupes(0.0) == 0


def test_random_baseline_draws_from_the_given_pool(one: SearchProblem) -> None:
    pool = make_pool(one, 12, np.random.default_rng(0))
    cfg = BoConfig(budget=5, pool_size=12)
    tr = run_random_search(one, np.random.default_rng(1), cfg, objective=_bowl, pool=pool)
    units = np.array([one.candidate_to_unit(c) for c in tr.candidates])
    assert all(np.abs(pool - u).max(axis=1).min() < 1e-9 for u in units)
    np.testing.assert_allclose(one.candidate_to_unit(tr.best_candidate), units[int(np.argmin(tr.costs))])
    assert (tr.proposers == -1).all()  # no UAV proposed these
    assert (tr.messages_sent, tr.messages_lost) == (0, 0)
    own = run_random_search(one, np.random.default_rng(1), cfg, objective=_bowl)  # its own pool
    assert len(own.costs) == 5 and np.all(np.isfinite(own.costs))
