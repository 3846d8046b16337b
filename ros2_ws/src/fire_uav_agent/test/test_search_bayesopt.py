"""Asynchronous Thompson-sampling BO (CP III-F) and the random baseline."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pytest
from fire_uav_agent.search.bayesopt import (
    BoConfig,
    CandidateKind,
    make_candidate_id,
    make_pool,
    run_async_bo,
    run_random_search,
)
from fire_uav_agent.search.errors import SearchConfigError
from fire_uav_agent.search.evaluate import SearchProblem
from fire_uav_agent.search.power_diagram import CoverageGrid
from scipy.stats import combine_pvalues
from threadpoolctl import threadpool_limits

MSG_DIR = Path(__file__).resolve().parents[2] / "fire_uav_msgs" / "msg"


@pytest.fixture(autouse=True)
def _single_thread_blas():
    """Small GP matrices: BLAS threads only contend on a shared host."""
    with threadpool_limits(1):
        yield


@pytest.fixture(scope="module")
def problem() -> SearchProblem:
    grid = CoverageGrid.from_area(0.0, 600.0, 0.0, 600.0, cell_size_m=120.0)
    return SearchProblem(grid=grid, n_agents=3, n_time_samples=40)


def test_bo_runs_and_improves_over_first_sample(problem: SearchProblem) -> None:
    cfg = BoConfig(budget=14, pool_size=128, n_init=2)
    # seed 0: in a seeded sweep, 9 of 10 seeds improve on the first sample (seed 8 drew its best first)
    tr = run_async_bo(problem, np.random.default_rng(0), cfg)
    assert len(tr.costs) == cfg.budget
    assert np.all(np.isfinite(tr.costs))
    assert tr.best_so_far[-1] < tr.costs[0]
    assert np.all(np.diff(tr.best_so_far) <= 0)
    assert set(tr.proposers.tolist()) == {0, 1, 2}  # every agent proposed
    assert tr.observations_per_agent.tolist() == [cfg.budget] * 3  # lossless: all share all data
    assert tr.messages_lost == 0


def test_bo_is_deterministic_for_a_seed(problem: SearchProblem) -> None:
    cfg = BoConfig(budget=6, pool_size=64)
    a = run_async_bo(problem, np.random.default_rng(5), cfg)
    b = run_async_bo(problem, np.random.default_rng(5), cfg)
    np.testing.assert_array_equal(a.costs, b.costs)
    np.testing.assert_array_equal(a.proposers, b.proposers)


def test_thirty_percent_loss_does_not_stall(problem: SearchProblem) -> None:
    cfg = BoConfig(budget=14, pool_size=128, loss_probability=0.3)
    tr = run_async_bo(problem, np.random.default_rng(3), cfg)
    assert len(tr.costs) == cfg.budget  # the budget is spent; nobody waited for a lost message
    assert tr.messages_lost > 0
    assert 0.15 < tr.messages_lost / tr.messages_sent < 0.45
    # lost COST messages simply never reach some data sets
    assert tr.observations_per_agent.min() < cfg.budget
    assert tr.best_so_far[-1] < tr.costs[0]


class _Bowl(NamedTuple):
    cost: float
    energy_j: float
    radius_m: float


def _bowl(problem: SearchProblem, cand) -> _Bowl:
    """A smooth objective on the unit cube (minimum at 0.3): checks the GP actually learns."""
    u = problem.candidate_to_unit(cand)
    return _Bowl(float(np.sum((u - 0.3) ** 2)), 0.0, 0.0)


@pytest.mark.slow  # 4 BO runs of 30 GP fits: ~40 s on a loaded 2-core host
def test_thompson_sampling_beats_random_on_a_smooth_objective(problem: SearchProblem) -> None:
    """On a 9-D bowl, 30 BO evaluations find pool points that random search rarely finds.

    Random search draws ``B`` distinct points of the ``M``-point pool, so the probability that
    its best is at least as good as BO's best -- whose rank in the pool is ``m`` -- is exactly
    ``p = 1 - C(M - m, B) / C(M, B)`` (hypergeometric; independent of the implementation). Four
    seeds (own pools) give four such p-values; Fisher's combination must be significant at 5 %,
    which random search itself passes at most 5 % of the time. (Measured: ranks 4, 3, 20, 1 of
    1024, combined p ~ 0.02; random search's typical rank is M / (B + 1) ~ 33.)
    """
    cfg = BoConfig(budget=30, pool_size=1024)
    p_random_as_good = []
    for seed in range(4):
        pool = make_pool(problem, cfg.pool_size, np.random.default_rng([seed, 0]))
        bo = run_async_bo(problem, np.random.default_rng([seed, 1]), cfg, objective=_bowl, pool=pool)
        assert bo.best_so_far[-1] < bo.costs[0]
        pool_costs = np.sum((pool - 0.3) ** 2, axis=1)
        rank = int(np.sum(pool_costs <= bo.best_so_far[-1] + 1e-12))
        m_pool, b = cfg.pool_size, cfg.budget
        p_random_as_good.append(1.0 - math.comb(m_pool - rank, b) / math.comb(m_pool, b))
    combined = combine_pvalues(p_random_as_good, method="fisher").pvalue
    assert combined < 0.05, p_random_as_good


def test_random_baseline_same_budget(problem: SearchProblem) -> None:
    cfg = BoConfig(budget=8, pool_size=32)
    pool = make_pool(problem, cfg.pool_size, np.random.default_rng(0))
    tr = run_random_search(problem, np.random.default_rng(1), cfg, pool=pool)
    assert len(tr.costs) == 8
    units = np.array([problem.candidate_to_unit(c) for c in tr.candidates])
    assert len(np.unique(units.round(9), axis=0)) == 8  # distinct pool points


def test_candidate_ids_and_wire_constants() -> None:
    assert make_candidate_id(3, 7) == (3 << 16) | 7
    with pytest.raises(SearchConfigError):
        make_candidate_id(3, 1 << 16)
    text = (MSG_DIR / "CoverageCandidate.msg").read_text()
    consts = {k: int(v) for k, v in re.findall(r"uint8 KIND_(\w+) = (\d+)", text)}
    assert consts == {k.name: int(k) for k in CandidateKind}


def test_config_errors() -> None:
    with pytest.raises(SearchConfigError, match="loss_probability"):
        BoConfig(loss_probability=1.0)
    with pytest.raises(SearchConfigError, match="pool_size"):
        BoConfig(budget=10, pool_size=5)
