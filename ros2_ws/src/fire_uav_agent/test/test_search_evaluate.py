"""Candidate evaluation (CP III-A, III-F): cost, coverage, time to first detection."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.search.errors import SearchConfigError
from fire_uav_agent.search.evaluate import (
    Candidate,
    SearchProblem,
    coverage_fraction,
    evaluate_candidate,
    first_detection_time_s,
)
from fire_uav_agent.search.power_diagram import CoverageGrid


@pytest.fixture(scope="module")
def problem() -> SearchProblem:
    grid = CoverageGrid.from_area(0.0, 720.0, 0.0, 600.0, cell_size_m=120.0)
    return SearchProblem(grid=grid, n_agents=3, n_time_samples=50)


def test_cost_is_lambda_energy_plus_radius(problem: SearchProblem) -> None:
    cand = problem.candidate_from_unit(np.random.default_rng(0).uniform(size=problem.dim))
    ev = evaluate_candidate(problem, cand)
    assert ev.cost == pytest.approx(problem.lambda_m_per_j * ev.energies_j.sum() + ev.radius_m)
    assert ev.radius_m == pytest.approx(ev.radii_m.max())
    assert ev.balance.converged
    # all cells flown exactly once: total path = sum over agents of 4 sub-cells per cell minus fillets
    n_cells = problem.grid.free.sum()
    total = sum(p.length_m for p in ev.paths)
    r = problem.arc_radius_m
    n_turns = sum(p.n_turns for p in ev.paths)
    assert total == pytest.approx(n_cells * 4 * 60.0 - n_turns * (2 * r - math.pi * r / 2))


def test_full_coverage_and_detection(problem: SearchProblem) -> None:
    cand = problem.candidate_from_unit(np.random.default_rng(1).uniform(size=problem.dim))
    ev = evaluate_candidate(problem, cand)
    assert coverage_fraction(problem, ev.paths) == pytest.approx(1.0)
    start = ev.paths[0].positions_at(np.array([cand.start_offsets[0] * ev.paths[0].length_m]))
    fires = np.vstack([start, [[5000.0, 5000.0]], np.random.default_rng(2).uniform(0, 600, (20, 2))])
    t = first_detection_time_s(problem, ev.paths, cand.start_offsets, fires)
    assert t[0] == 0.0
    assert math.isinf(t[1])
    longest = max(p.length_m for p in ev.paths) / problem.energy.speed_mps
    assert np.all(t[2:] <= longest)


def test_unit_cube_round_trip(problem: SearchProblem) -> None:
    u = np.random.default_rng(3).uniform(size=problem.dim)
    np.testing.assert_allclose(problem.candidate_to_unit(problem.candidate_from_unit(u)), u)


def test_bad_candidates_and_problems(problem: SearchProblem) -> None:
    with pytest.raises(SearchConfigError, match="start offsets"):
        Candidate(np.zeros((2, 2)), np.array([0.0, 1.0]))
    with pytest.raises(SearchConfigError, match="agents"):
        evaluate_candidate(problem, Candidate(np.zeros((2, 2)), np.zeros(2)))
    with pytest.raises(SearchConfigError, match="turn radius"):
        SearchProblem(grid=problem.grid, n_agents=2, min_turn_radius_m=40.0)
