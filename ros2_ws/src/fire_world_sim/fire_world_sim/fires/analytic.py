"""FF IV-A analytic fires: isotropic Gaussians whose centres drift linearly in time.

Fire i has centre ``c_i(t) = c_i(start) + v_i * (t - start_s)`` with v in m/s of sim time
(FF gives the drift per simulation instant t of unspecified length; the shipped
ff_two_fires.yaml takes one FF instant = 10 s). A fire is active from ``start_s``. Each drop
whose footprint contains the centre divides the fire's AREA by four (FF V-B), i.e. halves
sigma; a fire whose sigma falls below ``extinction_sigma_m`` is out. Area = pi sigma^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from fire_uav_common.constants import FireStatus
from fire_uav_common.scenario import AnalyticFire

from ..drop_pattern import DropPattern
from ..sensors import CellsSample
from .base import FireGrid, FireTruthRecord

__all__ = ["AnalyticFireModel"]


@dataclass
class _Fire:
    spec: AnalyticFire
    sigma_m: float
    x_m: float
    y_m: float
    out: bool = False
    started: bool = False
    drops: int = 0


class AnalyticFireModel:
    """FF Gaussian fires. ``drop_radius_m`` None = a drop hits a fire within its own sigma."""

    #: Gaussian fires do not spread cell by cell: they count as contained only once all are out
    last_ignition_s = math.inf
    last_drop_cells: tuple[int, int] | None = None  # no cells

    def __init__(
        self, fires: tuple[AnalyticFire, ...], extinction_sigma_m: float, drop_radius_m: float | None = None
    ) -> None:
        self.extinction_sigma_m = extinction_sigma_m
        self.drop_radius_m = drop_radius_m
        self._fires = [_Fire(f, f.sigma_m, f.x_m, f.y_m) for f in fires]
        self._t_s = 0.0
        self._update_started(0.0)

    def _update_started(self, t_s: float) -> list[int]:
        new = []
        for i, f in enumerate(self._fires):
            if not f.started and t_s >= f.spec.start_s - 1e-9:
                f.started = True
                new.append(i)
        return new

    def step(self, t_s: float, dt_s: float) -> list[tuple[int, str]]:
        t1 = t_s + dt_s
        self._t_s = t1
        for f in self._fires:
            if f.out:
                continue
            tau = max(0.0, t1 - f.spec.start_s)
            f.x_m = f.spec.x_m + f.spec.vx_mps * tau
            f.y_m = f.spec.y_m + f.spec.vy_mps * tau
        return [(i, "ignition") for i in self._update_started(t1) if self._fires[i].spec.start_s > 0]

    def apply_drop(self, x_m: float, y_m: float, radius_m: float | None = None) -> list[int]:
        hit = []
        for i, f in enumerate(self._fires):
            if f.out or not f.started:
                continue
            # the water reaches the fire if the footprint overlaps its core: within the larger of
            # the drop footprint and the fire's sigma (a big fire is hit anywhere in its core)
            r = radius_m if radius_m is not None else max(self.drop_radius_m or 0.0, f.sigma_m)
            if math.hypot(x_m - f.x_m, y_m - f.y_m) <= r:
                f.sigma_m /= 2.0  # area / 4
                f.drops += 1
                if f.sigma_m < self.extinction_sigma_m:
                    f.out = True
                hit.append(i)
        return hit

    def apply_pattern(self, pattern: DropPattern) -> list[int]:
        """FF's fires keep the paper's rule with a pattern too: the drop is one hit at the release
        point (a hit halves sigma, FF V-B); the pattern's coverage plays no part."""
        return self.apply_drop(pattern.release.x_m, pattern.release.y_m, None)

    def drop_extinctions(self, hit: list[int]) -> list[int]:
        """A drop that brings sigma under ``extinction_sigma_m`` puts the fire out at once (FF V-B);
        :meth:`step` never reports it, so the drop does."""
        return [i for i in hit if self._fires[i].out]

    def truth(self) -> list[FireTruthRecord]:
        return [
            FireTruthRecord(
                fire_id=i,
                status=FireStatus.EXTINGUISHED if f.out else FireStatus.ACTIVE,
                x_m=f.x_m,
                y_m=f.y_m,
                extent_m=0.0 if f.out else f.sigma_m,
                area_m2=0.0 if f.out else math.pi * f.sigma_m**2,
                drops_received=f.drops,
                started=f.started,
            )
            for i, f in enumerate(self._fires)
        ]

    def detections_near(
        self, x_m: float, y_m: float, range_m: float
    ) -> list[tuple[int, float, float, float]]:
        return [
            (i, f.x_m, f.y_m, f.sigma_m)
            for i, f in enumerate(self._fires)
            if f.started and not f.out and math.hypot(x_m - f.x_m, y_m - f.y_m) <= range_m
        ]

    def cells_near(self, x_m: float, y_m: float, range_m: float, stamp_ns: int) -> CellsSample | None:
        return None

    @property
    def has_cells(self) -> bool:
        return False

    def cell_grid(self) -> FireGrid | None:
        return None

    def fire_type_grid(self) -> np.ndarray | None:
        return None

    @property
    def all_out(self) -> bool:
        return all(f.out for f in self._fires)
