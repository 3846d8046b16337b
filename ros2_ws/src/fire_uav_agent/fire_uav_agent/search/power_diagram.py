"""Power-diagram area division with area balancing (CP III-B, Eqs. 2-9).

Frames and units: all positions are [m; map frame] (x east, y north); areas [m^2]; power weights
``w_i`` [m^2] (they are subtracted from a squared distance, Eq. 2).

Structure
---------
* :class:`CoverageGrid` -- the coarse grid of square cells of edge ``Delta`` (CP II-A, III-B) over a
  rectangle, with an optional obstacle mask. Coverage paths are planned on it (see :mod:`.stc`).
* :func:`quadrature` -- a finer grid of sample points used to integrate the areas of Eq. 3. The paper
  balances continuous areas and only then grids them; we approximate the integrals by sub-dividing
  every free coarse cell into ``subdiv x subdiv`` equal squares (choice: the paper does not say how
  the integrals are evaluated).
* :class:`BalancerAgent` -- one agent's decentralised weight update (Eq. 4). Its only input is the
  peers' :class:`WeightReport` (seed, weight), which mirrors ``fire_uav_msgs/CoverageWeight``.
* :func:`balance_weights` -- a synchronous convenience loop over N :class:`BalancerAgent` (tests,
  benchmarks, single-process evaluation).
* :func:`assign_cells` -- exclusive assignment of the coarse cells (Eq. 9), then
  :func:`make_regions_connected` so every region can be covered by one spanning tree.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from .errors import PartitionError, SearchConfigError

_FOUR_CONNECTED = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], dtype=bool)


@dataclass(frozen=True)
class CoverageGrid:
    """Coarse coverage grid [m; map frame].

    Cell ``(iy, ix)`` spans ``x in [x_min_m + ix*cell_size_m, x_min_m + (ix+1)*cell_size_m)`` and likewise
    in y. ``free[iy, ix]`` is True when the cell must be covered (False = obstacle / no-fly).
    The free cells must be 4-connected (one spanning tree per region needs it), else
    :class:`PartitionError`.
    """

    x_min_m: float
    y_min_m: float
    cell_size_m: float
    free: np.ndarray = field(repr=False)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.cell_size_m) and self.cell_size_m > 0.0):
            raise SearchConfigError(f"cell_size_m must be > 0, got {self.cell_size_m}")
        free = np.array(self.free, dtype=bool)
        if free.ndim != 2 or free.size == 0:
            raise PartitionError(f"free mask must be a non-empty 2-D array, got shape {free.shape}")
        if not free.any():
            raise PartitionError("grid has no free cell")
        from scipy import ndimage  # imported when a search role needs it (docs/profile.md)

        _, n_components = ndimage.label(free, structure=_FOUR_CONNECTED)
        if n_components != 1:
            raise PartitionError(f"free cells must be 4-connected, found {n_components} components")
        free.setflags(write=False)
        object.__setattr__(self, "free", free)

    @classmethod
    def from_area(
        cls,
        x_min_m: float,
        x_max_m: float,
        y_min_m: float,
        y_max_m: float,
        *,
        cell_size_m: float,
        obstacle_mask: np.ndarray | None = None,
    ) -> CoverageGrid:
        """Grid covering the rectangle; the last row/column overhangs when the size is not a multiple.

        ``obstacle_mask`` (ny, nx) bool, True = not to be covered. Choice: ceil rather than floor so
        the whole rectangle is covered (the paper assumes an exact fit, CP II-C).
        """
        if not (x_max_m > x_min_m and y_max_m > y_min_m):
            raise SearchConfigError("area must have x_max_m > x_min_m and y_max_m > y_min_m")
        if not (math.isfinite(cell_size_m) and cell_size_m > 0.0):
            raise SearchConfigError(f"cell_size_m must be > 0, got {cell_size_m}")
        nx = max(1, math.ceil((x_max_m - x_min_m) / cell_size_m - 1e-9))
        ny = max(1, math.ceil((y_max_m - y_min_m) / cell_size_m - 1e-9))
        free = np.ones((ny, nx), dtype=bool)
        if obstacle_mask is not None:
            mask = np.asarray(obstacle_mask, dtype=bool)
            if mask.shape != (ny, nx):
                raise SearchConfigError(f"obstacle_mask must have shape {(ny, nx)}, got {mask.shape}")
            free &= ~mask
        return cls(x_min_m=float(x_min_m), y_min_m=float(y_min_m), cell_size_m=float(cell_size_m), free=free)

    @property
    def ny(self) -> int:
        return int(self.free.shape[0])

    @property
    def nx(self) -> int:
        return int(self.free.shape[1])

    @property
    def free_area_m2(self) -> float:
        """Total area to cover [m^2] (A_tot of Eq. 5)."""
        return float(self.free.sum()) * self.cell_size_m**2

    def cell_centers_m(self) -> np.ndarray:
        """Centres of all cells, shape (ny, nx, 2) [m; map frame]."""
        xs = self.x_min_m + (np.arange(self.nx) + 0.5) * self.cell_size_m
        ys = self.y_min_m + (np.arange(self.ny) + 0.5) * self.cell_size_m
        gx, gy = np.meshgrid(xs, ys)
        return np.stack([gx, gy], axis=-1)

    def bounds_m(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) of the gridded rectangle [m]."""
        return (
            self.x_min_m,
            self.x_min_m + self.nx * self.cell_size_m,
            self.y_min_m,
            self.y_min_m + self.ny * self.cell_size_m,
        )


class Quadrature(NamedTuple):
    """Sample points for the integrals of Eq. 3."""

    points_m: np.ndarray  # (Q, 2) [m; map frame]
    area_m2: np.ndarray  # (Q,) [m^2] area each point stands for
    coarse_iy: np.ndarray  # (Q,) row of the coarse cell the point lies in
    coarse_ix: np.ndarray  # (Q,) column of the coarse cell the point lies in


def quadrature(grid: CoverageGrid, subdiv: int = 4) -> Quadrature:
    """Mid-point quadrature: each free coarse cell split into ``subdiv x subdiv`` squares."""
    if subdiv < 1:
        raise SearchConfigError(f"subdiv must be >= 1, got {subdiv}")
    h = grid.cell_size_m / subdiv
    iy, ix = np.nonzero(grid.free)
    off = (np.arange(subdiv) + 0.5) * h
    ox, oy = np.meshgrid(off, off)
    ox, oy = ox.ravel(), oy.ravel()
    px = (grid.x_min_m + ix[:, None] * grid.cell_size_m + ox[None, :]).ravel()
    py = (grid.y_min_m + iy[:, None] * grid.cell_size_m + oy[None, :]).ravel()
    k = subdiv * subdiv
    return Quadrature(
        points_m=np.stack([px, py], axis=1),
        area_m2=np.full(px.shape, h * h),
        coarse_iy=np.repeat(iy, k),
        coarse_ix=np.repeat(ix, k),
    )


def power_distance_m2(points_m: np.ndarray, seeds_m: np.ndarray, weights_m2: np.ndarray) -> np.ndarray:
    """Power distance ``||q - p_j||^2 - w_j`` of Eq. 2, shape (Q, N) [m^2]."""
    d = points_m[:, None, :] - np.asarray(seeds_m, dtype=float)[None, :, :]
    return np.einsum("qnk,qnk->qn", d, d) - np.asarray(weights_m2, dtype=float)[None, :]


def power_labels(points_m: np.ndarray, seeds_m: np.ndarray, weights_m2: np.ndarray) -> np.ndarray:
    """Index of the power cell (Eq. 2) containing each point; ties go to the lowest index."""
    return np.argmin(power_distance_m2(points_m, seeds_m, weights_m2), axis=1)


def power_cell_areas_m2(quad: Quadrature, seeds_m: np.ndarray, weights_m2: np.ndarray) -> np.ndarray:
    """Areas A_i of the power cells (Eq. 3, quadrature), shape (N,) [m^2]."""
    labels = power_labels(quad.points_m, seeds_m, weights_m2)
    return np.bincount(labels, weights=quad.area_m2, minlength=len(seeds_m))


def power_cell_centroids_m(quad: Quadrature, seeds_m: np.ndarray, weights_m2: np.ndarray) -> np.ndarray:
    """Centroids c_i of the power cells (Eq. 3), shape (N, 2) [m]; the seed for an empty cell."""
    seeds = np.asarray(seeds_m, dtype=float)
    labels = power_labels(quad.points_m, seeds, weights_m2)
    n = len(seeds)
    area = np.bincount(labels, weights=quad.area_m2, minlength=n)
    cx = np.bincount(labels, weights=quad.area_m2 * quad.points_m[:, 0], minlength=n)
    cy = np.bincount(labels, weights=quad.area_m2 * quad.points_m[:, 1], minlength=n)
    out = seeds.copy()
    nz = area > 0
    out[nz, 0] = cx[nz] / area[nz]
    out[nz, 1] = cy[nz] / area[nz]
    return out


def relative_area_errors(areas_m2: np.ndarray, targets_m2: np.ndarray) -> np.ndarray:
    """e_i = |A_i - A_i^*| / A_i^* (Eq. 6)."""
    return np.abs(np.asarray(areas_m2) - np.asarray(targets_m2)) / np.asarray(targets_m2)


def worst_area_error(areas_m2: np.ndarray, targets_m2: np.ndarray) -> float:
    """E_max = max_i e_i (Eq. 7)."""
    return float(np.max(relative_area_errors(areas_m2, targets_m2)))


def equal_targets_m2(grid: CoverageGrid, n_agents: int) -> np.ndarray:
    """A_i^* = A_tot / n_agents for homogeneous robots (Eq. 5)."""
    if n_agents < 1:
        raise SearchConfigError(f"n_agents must be >= 1, got {n_agents}")
    return np.full(n_agents, grid.free_area_m2 / n_agents)


@dataclass(frozen=True)
class BalanceConfig:
    """Parameters of the weight balancing (Eqs. 4, 8).

    ``gamma`` is the learning rate of Eq. 4 [-] (w and A are both m^2). The paper uses a fixed gamma;
    a fixed value is either slow for far-apart seeds or oscillates for close seeds (dA_i/dw_i grows as
    1/seed distance), so (choice) each agent adapts its own gamma locally, Rprop-like: it halves it
    when its own area error changes sign and grows it by ``gamma_growth`` otherwise, within
    [gamma_min, gamma_max]. Set ``gamma_growth=1`` and ``gamma_shrink=1`` for the paper's fixed step.
    """

    epsilon: float = 0.02  # tolerance of Eq. 8 [-]
    gamma: float = 0.5
    gamma_growth: float = 1.2
    gamma_shrink: float = 0.5
    gamma_min: float = 1e-4
    gamma_max: float = 20.0
    max_iterations: int = 500
    subdiv: int = 4  # quadrature points per coarse-cell side

    def __post_init__(self) -> None:
        if not 0.0 < self.epsilon < 1.0:
            raise SearchConfigError(f"epsilon must be in (0, 1), got {self.epsilon}")
        if not 0.0 < self.gamma_min <= self.gamma <= self.gamma_max:
            raise SearchConfigError("need 0 < gamma_min <= gamma <= gamma_max")
        if self.gamma_growth < 1.0 or not 0.0 < self.gamma_shrink <= 1.0:
            raise SearchConfigError("need gamma_growth >= 1 and 0 < gamma_shrink <= 1")
        if self.max_iterations < 1 or self.subdiv < 1:
            raise SearchConfigError("max_iterations and subdiv must be >= 1")


class WeightReport(NamedTuple):
    """One agent's power-diagram state; field-for-field ``fire_uav_msgs/CoverageWeight``.

    ``area_m2`` is the sender's area at the weights of the *previous* iteration (the newest it could
    compute before choosing ``weight_m2``); at iteration 0 it is NaN. Receivers recompute every area
    from all (seed, weight) pairs, so the field is informational.
    """

    uav_id: int
    iteration: int
    seed_x_m: float
    seed_y_m: float
    weight_m2: float
    area_m2: float
    target_area_m2: float


class BalancerAgent:
    """One agent's side of the decentralised area balancing (Eq. 4).

    Each iteration the agent broadcasts its :class:`WeightReport`; when it holds the reports of all
    agents for the same iteration it calls :meth:`step`, which computes every power-cell area from the
    shared (seed, weight) pairs (all agents share with all, CP III-B, so no Delaunay graph is needed),
    tests convergence E_max < epsilon (Eqs. 6-8) and, if not converged, updates its own weight.
    Because all agents evaluate the same deterministic function on the same reports, they agree on
    convergence without an extra round.
    """

    def __init__(
        self,
        uav_id: int,
        seed_m: Sequence[float],
        target_area_m2: float,
        quad: Quadrature,
        config: BalanceConfig | None = None,
        *,
        weight_m2: float = 0.0,
        fleet_ids: Sequence[int] | None = None,
    ) -> None:
        """``fleet_ids``: all uav ids expected in every step (own included); None = trust the caller."""
        if target_area_m2 <= 0.0:
            raise SearchConfigError(f"target_area_m2 must be > 0, got {target_area_m2}")
        self.uav_id = int(uav_id)
        self.seed_m = (float(seed_m[0]), float(seed_m[1]))
        self.target_area_m2 = float(target_area_m2)
        self.quad = quad
        self.config = config or BalanceConfig()
        self.weight_m2 = float(weight_m2)
        self.fleet_ids = None if fleet_ids is None else frozenset(int(k) for k in fleet_ids)
        self.iteration = 0
        self.converged = False
        self.e_max = math.inf
        self._gamma = self.config.gamma
        self._prev_error_m2: float | None = None
        self._last_area_m2 = math.nan

    def report(self) -> WeightReport:
        """The message to broadcast for the current iteration."""
        return WeightReport(
            uav_id=self.uav_id,
            iteration=self.iteration,
            seed_x_m=self.seed_m[0],
            seed_y_m=self.seed_m[1],
            weight_m2=self.weight_m2,
            area_m2=self._last_area_m2,
            target_area_m2=self.target_area_m2,
        )

    def step(self, reports: Mapping[int, WeightReport]) -> bool:
        """Consume all agents' reports of the current iteration (own included); return converged.

        Raises :class:`PartitionError` when a report is missing or from another iteration: the caller
        waits (or re-requests) rather than stepping on partial data.
        """
        if self.converged:
            return True
        if self.uav_id not in reports:
            raise PartitionError(f"agent {self.uav_id}: own report missing")
        if self.fleet_ids is not None and set(reports) != self.fleet_ids:
            missing = sorted(self.fleet_ids - set(reports))
            raise PartitionError(f"agent {self.uav_id}: reports missing from uavs {missing}")
        ids = sorted(reports)
        for k in ids:
            if reports[k].iteration != self.iteration:
                raise PartitionError(
                    f"agent {self.uav_id}: report of uav {k} is for iteration "
                    f"{reports[k].iteration}, expected {self.iteration}"
                )
        seeds = np.array([[reports[k].seed_x_m, reports[k].seed_y_m] for k in ids])
        weights = np.array([reports[k].weight_m2 for k in ids])
        targets = np.array([reports[k].target_area_m2 for k in ids])
        areas = power_cell_areas_m2(self.quad, seeds, weights)
        self.e_max = worst_area_error(areas, targets)  # Eqs. 6-7
        own = ids.index(self.uav_id)
        self._last_area_m2 = float(areas[own])
        if self.e_max < self.config.epsilon:  # Eq. 8
            self.converged = True
            return True
        error = float(areas[own]) - self.target_area_m2
        if self._prev_error_m2 is not None and error * self._prev_error_m2 < 0.0:
            self._gamma = max(self.config.gamma_min, self._gamma * self.config.gamma_shrink)
        else:
            self._gamma = min(self.config.gamma_max, self._gamma * self.config.gamma_growth)
        self._prev_error_m2 = error
        self.weight_m2 -= self._gamma * error  # Eq. 4
        self.iteration += 1
        return False


class BalanceResult(NamedTuple):
    """Outcome of :func:`balance_weights`."""

    weights_m2: np.ndarray  # (N,)
    areas_m2: np.ndarray  # (N,) at the final weights
    targets_m2: np.ndarray  # (N,)
    e_max: float  # Eq. 7 at the final weights
    iterations: int
    converged: bool
    e_max_history: np.ndarray  # (iterations + 1,)


def balance_weights(
    grid: CoverageGrid,
    seeds_m: np.ndarray,
    config: BalanceConfig | None = None,
    *,
    targets_m2: np.ndarray | None = None,
    quad: Quadrature | None = None,
) -> BalanceResult:
    """Run N :class:`BalancerAgent` in lock-step until E_max < epsilon (Eq. 8) or max_iterations.

    Non-convergence is reported in the result, not raised: a candidate that cannot be balanced is
    still a valid (if poor) candidate for the optimiser.
    """
    config = config or BalanceConfig()
    seeds = np.asarray(seeds_m, dtype=float)
    if seeds.ndim != 2 or seeds.shape[1] != 2 or len(seeds) < 1:
        raise PartitionError(f"seeds_m must have shape (N, 2), got {seeds.shape}")
    if not np.all(np.isfinite(seeds)):
        raise PartitionError("seeds_m must be finite")
    n = len(seeds)
    targets = equal_targets_m2(grid, n) if targets_m2 is None else np.asarray(targets_m2, dtype=float)
    if targets.shape != (n,) or np.any(targets <= 0):
        raise SearchConfigError("targets_m2 must be N positive values")
    quad = quad or quadrature(grid, config.subdiv)
    agents = [
        BalancerAgent(i, seeds[i], float(targets[i]), quad, config, fleet_ids=range(n)) for i in range(n)
    ]
    history = []
    for _ in range(config.max_iterations + 1):
        reports = {a.uav_id: a.report() for a in agents}
        done = [a.step(reports) for a in agents]
        history.append(agents[0].e_max)
        if all(done):
            break
    weights = np.array([a.weight_m2 for a in agents])
    areas = power_cell_areas_m2(quad, seeds, weights)
    e_max = worst_area_error(areas, targets)
    return BalanceResult(
        weights_m2=weights,
        areas_m2=areas,
        targets_m2=targets,
        e_max=e_max,
        iterations=len(history) - 1,
        converged=bool(e_max < config.epsilon),
        e_max_history=np.array(history),
    )


def assign_cells(
    grid: CoverageGrid,
    seeds_m: np.ndarray,
    weights_m2: np.ndarray,
    *,
    subdiv: int = 4,
    quad: Quadrature | None = None,
) -> np.ndarray:
    """Exclusive assignment of the coarse cells (Eq. 9): labels (ny, nx), -1 for non-free cells.

    A coarse cell goes to the agent owning most of its quadrature points under the power diagram
    (Eq. 2); ties go to the lowest index. Choice: majority vote instead of the cell centre keeps the
    gridded areas close to the balanced continuous ones. Every free cell gets exactly one label.
    """
    quad = quad or quadrature(grid, subdiv)
    n = len(seeds_m)
    labels = power_labels(quad.points_m, seeds_m, weights_m2)
    flat = quad.coarse_iy * grid.nx + quad.coarse_ix
    votes = np.zeros((grid.ny * grid.nx, n))
    np.add.at(votes, (flat, labels), quad.area_m2)
    out = np.argmax(votes, axis=1).reshape(grid.ny, grid.nx)
    return np.where(grid.free, out, -1)


def make_regions_connected(labels: np.ndarray) -> np.ndarray:
    """Reassign stray pieces so every agent's region is 4-connected (needed for one STC tree).

    A power cell is convex, but its grid image can split into pieces along a thin diagonal. Each
    agent keeps its largest piece; every other piece goes to the neighbouring agent sharing the
    longest border with it. Each move lowers the total piece count, so this terminates; Eq. 9 still
    holds (each cell keeps exactly one owner). Requires 4-connected free space (see
    :class:`CoverageGrid`).
    """
    from scipy import ndimage  # imported when a search role needs it (docs/profile.md)

    out = np.array(labels, copy=True)
    ny, nx = out.shape
    for _ in range(out.size):
        moved = False
        for agent in np.unique(out[out >= 0]):
            comp, n_comp = ndimage.label(out == agent, structure=_FOUR_CONNECTED)
            if n_comp <= 1:
                continue
            sizes = np.bincount(comp.ravel())[1:]
            keep = int(np.argmax(sizes)) + 1
            for c in range(1, n_comp + 1):
                if c == keep:
                    continue
                piece = comp == c
                border = ndimage.binary_dilation(piece, structure=_FOUR_CONNECTED) & ~piece
                neigh = out[border]
                neigh = neigh[(neigh >= 0) & (neigh != agent)]
                if neigh.size == 0:
                    continue
                out[piece] = int(np.argmax(np.bincount(neigh)))
                moved = True
                break
            if moved:
                break
        if not moved:
            return out
    raise PartitionError("could not make regions connected")  # pragma: no cover - bounded by size
