"""The one small interface both fire models implement (crazyswarm2-style swappable backend).

Everything the world and its node need of a fire model is here, so neither asks which model
it holds: what a drop did (:meth:`FireModel.apply_drop`, ``last_drop_cells``,
:meth:`FireModel.drop_extinctions`), when the last cell ignited (containment), and whether the
model has a cell grid to show (:meth:`FireModel.cell_grid`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ..drop_pattern import DropPattern
from ..sensors import CellsSample

__all__ = ["FireGrid", "FireModel", "FireTruthRecord"]


@dataclass(frozen=True)
class FireTruthRecord:
    """True state of one fire (mirrors fire_uav_msgs/FireTruth)."""

    fire_id: int
    status: int
    x_m: float  # [m] centre east (raster: centroid of burning + burnt cells of this fire)
    y_m: float  # [m] centre north
    extent_m: float  # [m] Gaussian sigma (analytic) or equivalent radius sqrt(A/pi) (raster)
    area_m2: float  # [m^2] analytic: pi sigma^2; raster: burning + burnt area
    drops_received: int
    started: bool = True  # False before start_s / ignition time


@dataclass(frozen=True)
class FireGrid:
    """The cells of a fire model at its current time, row 0 the southern row (map frame).

    ``state``: (ny, nx) uint8 of ``CellState``; ``wet``: (ny, nx) bool, unburned cells
    currently wet. ``origin_*_m``: south-west corner of cell (0, 0) [m; map].
    """

    origin_x_m: float
    origin_y_m: float
    cell_size_m: float
    state: np.ndarray
    wet: np.ndarray

    @property
    def nx(self) -> int:
        return int(self.state.shape[1])

    @property
    def ny(self) -> int:
        return int(self.state.shape[0])


class FireModel(Protocol):
    """Fires advance in sim time; drops suppress them; sensors query them."""

    @property
    def last_ignition_s(self) -> float:
        """[s] latest ignition time of any cell (-inf before the first); a model whose fires do
        not spread cell by cell gives +inf, so they count as contained only once all are out."""
        ...

    @property
    def last_drop_cells(self) -> tuple[int, int] | None:
        """(burning cells wetted, cells in the footprint) of the last drop; None for a model
        without cells."""
        ...

    def step(self, t_s: float, dt_s: float) -> list[tuple[int, str]]:
        """Advance from t_s to t_s + dt_s. Returns (fire_id, what) for fires that started
        ("ignition") or went out by themselves ("extinguished") during the step."""
        ...

    def apply_drop(self, x_m: float, y_m: float, radius_m: float | None) -> list[int]:
        """A full load released at (x_m, y_m); radius None = model default. Returns fire ids
        hit; :meth:`drop_extinctions` tells which of them the drop itself put out."""
        ...

    def apply_pattern(self, pattern: DropPattern) -> list[int]:
        """A full load released as the ground pattern ``pattern`` (``fires.drop_model: pattern``,
        :mod:`fire_world_sim.drop_pattern`). Returns fire ids hit, as :meth:`apply_drop`."""
        ...

    def drop_extinctions(self, hit: list[int]) -> list[int]:
        """Of the fires ``hit`` by the drop just applied, those the drop put out at once and that
        :meth:`step` will therefore not report (the caller reports them with the drop)."""
        ...

    def truth(self) -> list[FireTruthRecord]: ...

    def detections_near(
        self, x_m: float, y_m: float, range_m: float
    ) -> list[tuple[int, float, float, float]]:
        """(fire_id, x_m, y_m, extent_m) of every active fire the sensor sees from (x_m, y_m)."""
        ...

    def cells_near(self, x_m: float, y_m: float, range_m: float, stamp_ns: int) -> CellsSample | None:
        """Raster cells within range (None for models without cells)."""
        ...

    @property
    def has_cells(self) -> bool:
        """True when the fires live on a cell grid (:meth:`cell_grid` is not None); such fires are
        shown by their grid, the others as discs."""
        ...

    def cell_grid(self) -> FireGrid | None:
        """The whole grid now (for ``/viz/fire_grid``), or None for a model without cells."""
        ...

    def fire_type_grid(self) -> np.ndarray | None:
        """(ny, nx) uint8 per cell of :meth:`cell_grid`: the fire type a cell burned with
        (``FireType``: 1 surface, 2 passive crown, 3 active crown; 0 not ignited), for fires on a
        landscape (crown fire); None for any other model."""
        ...

    @property
    def all_out(self) -> bool:
        """Every fire (including not yet started ones) is extinguished."""
        ...
