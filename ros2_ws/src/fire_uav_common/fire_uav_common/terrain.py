"""Terrain elevation E(x, y) (FF Eq. 12), shared by the world (truth) and the agents (a priori map).

Two kinds behind one interface (``elevation(x_m, y_m)``, ``gradient(x_m, y_m)``, map frame
metres): :class:`Terrain`, a base plane plus Gaussian hills, and :class:`GridTerrain`, a raster
of elevations (a landscape's elevation layer) interpolated bilinearly between cell centres.
Lakes are flat at the local elevation: discs, or a landscape's water bodies by their cells.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import ArgumentError
from .water import StraightRun, WaterCells

__all__ = ["GridTerrain", "Hill", "Lake", "Terrain"]


@dataclass(frozen=True)
class Hill:
    """Gaussian hill: height_m * exp(-|q - c|^2 / (2 sigma_m^2))."""

    x_m: float
    y_m: float
    height_m: float
    sigma_m: float

    def __post_init__(self) -> None:
        if not self.sigma_m > 0:
            raise ArgumentError(f"hill sigma_m must be > 0, got {self.sigma_m}")


@dataclass(frozen=True)
class Lake:
    """Water source: a disc of diameter_m centred at (x_m, y_m), or a water body of a landscape.

    ``water``: the body's water cells (its real outline); the disc is then the largest one inside
    it, where the agents aim. :meth:`contains` (is a point over the water) reads the outline when
    there is one. ``run``: the body's longest straight run over water (a scoop run needs one);
    for a disc, its diameter.
    """

    x_m: float
    y_m: float
    diameter_m: float
    water: WaterCells | None = field(default=None, compare=False, repr=False)
    run: StraightRun | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        if not self.diameter_m > 0:
            raise ArgumentError(f"lake diameter_m must be > 0, got {self.diameter_m}")

    def contains(self, x_m: float, y_m: float) -> bool:
        if self.water is not None:
            return bool(self.water.contains(x_m, y_m))
        return (x_m - self.x_m) ** 2 + (y_m - self.y_m) ** 2 <= (self.diameter_m / 2) ** 2

    @property
    def longest_run(self) -> StraightRun:
        """The longest straight segment over the water [m; map frame]."""
        if self.run is not None:
            return self.run
        r = self.diameter_m / 2
        return StraightRun(self.x_m - r, self.y_m, self.x_m + r, self.y_m, self.diameter_m)

    def shifted(self, dx_m: float, dy_m: float) -> Lake:
        """The same lake with the map frame's origin moved by (-dx_m, -dy_m)."""
        run = self.run
        if run is not None:
            run = StraightRun(
                run.x0_m + dx_m, run.y0_m + dy_m, run.x1_m + dx_m, run.y1_m + dy_m, run.length_m
            )
        water = None if self.water is None else self.water.shifted(dx_m, dy_m)
        return Lake(self.x_m + dx_m, self.y_m + dy_m, self.diameter_m, water, run)


@dataclass(frozen=True)
class Terrain:
    """E(x, y) = base_m + slope_x * x + slope_y * y + sum of hills [m above datum]."""

    base_m: float = 0.0
    slope_x: float = 0.0  # [m/m] rise per metre east
    slope_y: float = 0.0  # [m/m] rise per metre north
    hills: tuple[Hill, ...] = field(default_factory=tuple)

    def elevation(self, x_m: float | np.ndarray, y_m: float | np.ndarray) -> float | np.ndarray:
        """Ground height [m] at (x_m, y_m), map frame; vectorised over arrays."""
        if not self.hills and isinstance(x_m, float) and isinstance(y_m, float):
            # a point on a plane (every control step asks several times): the same three IEEE
            # operations as the array form below, in Python floats (a hill's exp stays numpy's)
            return float(self.base_m + self.slope_x * x_m + self.slope_y * y_m)
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        e = self.base_m + self.slope_x * x + self.slope_y * y
        for h in self.hills:
            e = e + h.height_m * np.exp(-((x - h.x_m) ** 2 + (y - h.y_m) ** 2) / (2 * h.sigma_m**2))
        return float(e) if e.ndim == 0 else e

    def gradient(self, x_m: float, y_m: float, eps_m: float = 0.5) -> tuple[float, float]:
        """(dE/dx, dE/dy) [m/m] by central differences."""
        dx = (self.elevation(x_m + eps_m, y_m) - self.elevation(x_m - eps_m, y_m)) / (2 * eps_m)
        dy = (self.elevation(x_m, y_m + eps_m) - self.elevation(x_m, y_m - eps_m)) / (2 * eps_m)
        return float(dx), float(dy)

    @classmethod
    def from_dict(cls, d: dict) -> Terrain:
        """Build from a scenario's ``terrain:`` mapping (keys: base_m, slope_x, slope_y, hills)."""
        hills = tuple(Hill(**h) for h in d.get("hills", []) or [])
        return cls(
            base_m=float(d.get("base_m", 0.0)),
            slope_x=float(d.get("slope_x", 0.0)),
            slope_y=float(d.get("slope_y", 0.0)),
            hills=hills,
        )


@dataclass(frozen=True, eq=False)
class GridTerrain(Terrain):
    """Elevation from a raster [m]: ``elevation_m[i, j]`` is the height at the centre of the cell
    whose south-west corner is ``(x0_m + j cell_m, y0_m + i cell_m)`` (row 0 is the SOUTHERN row).

    Bilinear between cell centres, clamped to the outermost centres beyond them (a vehicle
    outside the raster sees the edge's height). ``source`` names where the grid came from; two
    grid terrains are equal when they are the same object (the arrays are not compared).
    """

    elevation_m: np.ndarray = field(default_factory=lambda: np.zeros((1, 1)))
    x0_m: float = 0.0
    y0_m: float = 0.0
    cell_m: float = 1.0
    source: str = ""

    def __post_init__(self) -> None:
        e = np.asarray(self.elevation_m, dtype=float)
        if e.ndim != 2 or e.size == 0 or not np.all(np.isfinite(e)):
            raise ArgumentError(f"grid terrain {self.source!r}: elevation must be a finite 2-D array")
        if not self.cell_m > 0:
            raise ArgumentError(f"grid terrain {self.source!r}: cell_m must be > 0, got {self.cell_m}")
        e.flags.writeable = False
        object.__setattr__(self, "elevation_m", e)

    def elevation(self, x_m: float | np.ndarray, y_m: float | np.ndarray) -> float | np.ndarray:
        """Ground height [m] at (x_m, y_m), map frame; vectorised over arrays."""
        e = self.elevation_m
        ny, nx = e.shape
        fx = np.clip((np.asarray(x_m, dtype=float) - self.x0_m) / self.cell_m - 0.5, 0.0, nx - 1)
        fy = np.clip((np.asarray(y_m, dtype=float) - self.y0_m) / self.cell_m - 0.5, 0.0, ny - 1)
        j0 = np.minimum(np.floor(fx).astype(int), max(nx - 2, 0))
        i0 = np.minimum(np.floor(fy).astype(int), max(ny - 2, 0))
        j1 = np.minimum(j0 + 1, nx - 1)
        i1 = np.minimum(i0 + 1, ny - 1)
        tx, ty = fx - j0, fy - i0
        out = (e[i0, j0] * (1 - tx) + e[i0, j1] * tx) * (1 - ty) + (
            e[i1, j0] * (1 - tx) + e[i1, j1] * tx
        ) * ty
        return float(out) if out.ndim == 0 else out

    def gradient(self, x_m: float, y_m: float, eps_m: float | None = None) -> tuple[float, float]:
        """(dE/dx, dE/dy) [m/m] by central differences over half a cell."""
        return super().gradient(x_m, y_m, 0.5 * self.cell_m if eps_m is None else eps_m)

    def __eq__(self, other: object) -> bool:
        return self is other

    def __hash__(self) -> int:
        return id(self)
