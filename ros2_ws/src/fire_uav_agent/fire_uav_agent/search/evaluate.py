"""Evaluation of one joint candidate (CP III-A, III-F): partition -> STC -> energy -> r_max -> cost.

A candidate ``x`` is the joint configuration of all agents: power-diagram seeds ``p_i`` [m; map frame]
and start offsets ``s_i`` in [0, 1) along each agent's tour. Its cost (CP III-F) is

    f(x) = lambda * sum_i E_i(x) + r_max(x)

with ``E_i`` from Eq. 10 and ``r_max`` from Eq. 11. ``lambda`` [m/J] is not given in the paper; the
default 1e-3 m/J makes both terms a few hundred metres on the benchmark area (choice).

Time bases (CP III-E b): ``r_max`` is sampled on the *normalised* time grid tau in [0, 1) (fraction
of each agent's own path already flown), as in the paper. The mission metrics (first detection of
a fire) use physical time at constant airspeed, so agents with longer paths lap more slowly.
Agents are assumed to start at their path start (no transit from the take-off point; not modelled
in the paper either).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from .energy import EnergyModel
from .errors import SearchConfigError
from .mst import mission_radius_m
from .power_diagram import (
    BalanceConfig,
    BalanceResult,
    CoverageGrid,
    assign_cells,
    balance_weights,
    make_regions_connected,
    quadrature,
)
from .stc import CoveragePath, loiter_path, stc_path


@dataclass(frozen=True)
class Candidate:
    """Joint configuration: seeds (N, 2) [m; map frame] and start offsets (N,) in [0, 1)."""

    seeds_m: np.ndarray
    start_offsets: np.ndarray

    def __post_init__(self) -> None:
        seeds = np.array(self.seeds_m, dtype=float)
        offs = np.array(self.start_offsets, dtype=float)
        if seeds.ndim != 2 or seeds.shape[1] != 2 or offs.shape != (len(seeds),):
            raise SearchConfigError(
                f"need seeds_m (N, 2) and start_offsets (N,), got {seeds.shape} and {offs.shape}"
            )
        if not (np.all(np.isfinite(seeds)) and np.all((offs >= 0.0) & (offs < 1.0))):
            raise SearchConfigError("seeds must be finite and start offsets in [0, 1)")
        seeds.setflags(write=False)
        offs.setflags(write=False)
        object.__setattr__(self, "seeds_m", seeds)
        object.__setattr__(self, "start_offsets", offs)

    @property
    def n_agents(self) -> int:
        return len(self.seeds_m)


@dataclass(frozen=True)
class SearchProblem:
    """Everything fixed during one optimisation: area, fleet size and model parameters."""

    grid: CoverageGrid
    n_agents: int
    turn_radius_m: float | None = None  # arc radius [m]; None = cell_size_m / 4 (CP III-C)
    min_turn_radius_m: float = 5.0  # vehicle limit v / omega_max [m] (50 m/s / 10 rad/s)
    energy: EnergyModel = field(default_factory=EnergyModel)
    lambda_m_per_j: float = 1e-3  # lambda of the cost [m/J]
    balance: BalanceConfig = field(default_factory=BalanceConfig)
    n_time_samples: int = 100  # sampled instants of Eq. 11
    sample_spacing_m: float = 10.0  # path sampling for coverage and detection [m]
    sensor_range_m: float = 70.0  # fire sensor range [m]
    coverage_subdiv: int = 8  # test points per coarse-cell side for the coverage fraction
    mst_backend: str = "distributed"  # or "centralised" (same value, faster for large N)

    def __post_init__(self) -> None:
        if self.n_agents < 1:
            raise SearchConfigError(f"n_agents must be >= 1, got {self.n_agents}")
        r = self.arc_radius_m
        if not self.min_turn_radius_m <= r <= self.grid.cell_size_m / 4 + 1e-9:
            raise SearchConfigError(
                f"turn radius {r} m must be in [min_turn_radius_m = {self.min_turn_radius_m}, "
                f"cell_size_m / 4 = {self.grid.cell_size_m / 4}] m"
            )
        if self.lambda_m_per_j < 0.0 or self.n_time_samples < 1 or self.sample_spacing_m <= 0.0:
            raise SearchConfigError("need lambda >= 0, n_time_samples >= 1, sample_spacing_m > 0")
        if self.sensor_range_m <= 0.0 or self.coverage_subdiv < 1:
            raise SearchConfigError("need sensor_range_m > 0 and coverage_subdiv >= 1")
        if self.mst_backend not in ("distributed", "centralised"):
            raise SearchConfigError(f"unknown mst_backend {self.mst_backend!r}")

    @property
    def arc_radius_m(self) -> float:
        return self.grid.cell_size_m / 4 if self.turn_radius_m is None else float(self.turn_radius_m)

    @property
    def dim(self) -> int:
        """Dimension of the unit-cube encoding: 2 seed coordinates + 1 offset per agent."""
        return 3 * self.n_agents

    def candidate_from_unit(self, u: np.ndarray) -> Candidate:
        """Map a point of [0, 1]^(3N) to a candidate: seeds in the grid's bounding box, offsets."""
        u = np.asarray(u, dtype=float)
        if u.shape != (self.dim,):
            raise SearchConfigError(f"unit vector must have shape ({self.dim},), got {u.shape}")
        x0, x1, y0, y1 = self.grid.bounds_m()
        n = self.n_agents
        seeds = np.stack([x0 + u[:n] * (x1 - x0), y0 + u[n : 2 * n] * (y1 - y0)], axis=1)
        offs = np.clip(u[2 * n :], 0.0, np.nextafter(1.0, 0.0))
        return Candidate(seeds, offs)

    def candidate_to_unit(self, c: Candidate) -> np.ndarray:
        x0, x1, y0, y1 = self.grid.bounds_m()
        return np.concatenate(
            [(c.seeds_m[:, 0] - x0) / (x1 - x0), (c.seeds_m[:, 1] - y0) / (y1 - y0), c.start_offsets]
        )


class Evaluation(NamedTuple):
    """Cost and intermediate products of one candidate."""

    candidate: Candidate
    cost: float  # lambda * sum(E_i) + r_max [m]
    energy_j: float  # sum_i E_i [J]
    energies_j: np.ndarray  # (N,) Eq. 10 per agent [J]
    radius_m: float  # r_max, Eq. 11 [m]
    radii_m: np.ndarray  # (K,) longest MST edge per sampled instant [m]
    balance: BalanceResult
    labels: np.ndarray  # (ny, nx) owner of each coarse cell (Eq. 9), -1 = not free
    paths: tuple[CoveragePath, ...]


def plan_paths(problem: SearchProblem, candidate: Candidate) -> tuple[BalanceResult, np.ndarray, tuple]:
    """Area division (Eqs. 2-9) and one STC path per agent (CP III-C)."""
    if candidate.n_agents != problem.n_agents:
        raise SearchConfigError(f"candidate has {candidate.n_agents} agents, problem {problem.n_agents}")
    grid = problem.grid
    quad = quadrature(grid, problem.balance.subdiv)
    bal = balance_weights(grid, candidate.seeds_m, problem.balance, quad=quad)
    labels = make_regions_connected(assign_cells(grid, candidate.seeds_m, bal.weights_m2, quad=quad))
    paths = []
    for i in range(problem.n_agents):
        region = labels == i
        if region.any():
            paths.append(
                stc_path(
                    region,
                    x_min_m=grid.x_min_m,
                    y_min_m=grid.y_min_m,
                    cell_size_m=grid.cell_size_m,
                    turn_radius_m=problem.arc_radius_m,
                )
            )
        else:  # empty region: the fixed-wing loiters over its seed
            paths.append(loiter_path(candidate.seeds_m[i], problem.arc_radius_m))
    return bal, labels, tuple(paths)


def positions_normalised_time(
    paths: tuple[CoveragePath, ...], start_offsets: np.ndarray, n_samples: int
) -> np.ndarray:
    """Positions (K, N, 2) [m] at tau_k = k / K: agent i at arc length (s_i + tau_k) * L_i (CP III-E b)."""
    tau = np.arange(n_samples) / n_samples
    return np.stack(
        [p.positions_at((s + tau) * p.length_m) for p, s in zip(paths, start_offsets, strict=True)], axis=1
    )


def evaluate_candidate(problem: SearchProblem, candidate: Candidate) -> Evaluation:
    """Cost of one candidate: f(x) = lambda * sum_i E_i + r_max (CP III-F)."""
    bal, labels, paths = plan_paths(problem, candidate)
    energies = np.array([problem.energy.path_energy_j(p) for p in paths])
    pos = positions_normalised_time(paths, candidate.start_offsets, problem.n_time_samples)
    r_max, radii = mission_radius_m(pos, backend=problem.mst_backend)
    total = float(energies.sum())
    return Evaluation(
        candidate=candidate,
        cost=problem.lambda_m_per_j * total + r_max,
        energy_j=total,
        energies_j=energies,
        radius_m=r_max,
        radii_m=radii,
        balance=bal,
        labels=labels,
        paths=paths,
    )


def coverage_test_points(problem: SearchProblem) -> np.ndarray:
    """Points (P, 2) [m] evenly filling the free cells, for the coverage fraction."""
    return quadrature(problem.grid, problem.coverage_subdiv).points_m


def coverage_fraction(problem: SearchProblem, paths: tuple[CoveragePath, ...]) -> float:
    """Fraction of the free area within sensor range of some path sample during one lap."""
    from scipy.spatial import cKDTree  # imported when a search role needs it (docs/profile.md)

    samples = np.concatenate([p.sample(problem.sample_spacing_m).pos_m for p in paths])
    d, _ = cKDTree(samples).query(coverage_test_points(problem))
    return float(np.mean(d <= problem.sensor_range_m))


def first_detection_time_s(
    problem: SearchProblem,
    paths: tuple[CoveragePath, ...],
    start_offsets: np.ndarray,
    fires_m: np.ndarray,
) -> np.ndarray:
    """Time [s] until a fire at each point (F, 2) [m] is first within sensor range of some agent.

    Each agent starts at ``s_i * L_i`` along its tour at t = 0 and flies at ``energy.speed_mps``;
    time resolution is ``sample_spacing_m / speed``. ``inf`` if no agent ever passes within range.
    """
    fires = np.atleast_2d(np.asarray(fires_m, dtype=float))
    best = np.full(len(fires), math.inf)
    v = problem.energy.speed_mps
    for path, s in zip(paths, start_offsets, strict=True):
        smp = path.sample(problem.sample_spacing_m, float(s))
        t = np.arange(len(smp.pos_m)) * smp.spacing_m / v
        d = np.linalg.norm(fires[:, None, :] - smp.pos_m[None, :, :], axis=-1)
        hit = d <= problem.sensor_range_m
        first = np.where(hit.any(axis=1), t[np.argmax(hit, axis=1)], math.inf)
        best = np.minimum(best, first)
    return best
