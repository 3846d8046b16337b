"""The raster fire's cells on a landscape: per-cell layers and their fire behaviour (no ROS).

:class:`LandscapeCells` holds what the raster fire needs of a landscape window
(:mod:`fire_uav_common.scenario.ground`), flipped so that row 0 is the southern row like the
raster's grid: the fuel code per cell (0 outside the data), slope, aspect and the four canopy
layers. :meth:`LandscapeCells.behavior` is FlamMap's basic run over them
(:func:`.behavior.fire_behavior`) under a uniform 20-ft wind, or under a gridded one
(:mod:`fire_uav_common.scenario.wind_grid`: WindNinja's grids resampled to the cells), each
cell's wind through its own wind adjustment factor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from fire_uav_common.scenario import RasterLandscape, WindGrid

from ..errors import ConfigError
from .behavior import FireBehavior, FuelMoistures, Moisture, fire_behavior

__all__ = ["LandscapeCells"]


@dataclass(frozen=True)
class LandscapeCells:
    """A landscape window's layers on the raster's grid, row 0 the southern row."""

    spec: RasterLandscape
    fuel: np.ndarray  # (ny, nx) int16 fuel code, 0 outside the data
    slope_pct: np.ndarray
    aspect_deg: np.ndarray  # [deg cw from north], -1 flat
    canopy_cover: np.ndarray  # [fraction]
    canopy_height_m: np.ndarray
    canopy_base_height_m: np.ndarray
    canopy_bulk_density_kgpm3: np.ndarray

    @classmethod
    def read(cls, spec: RasterLandscape, ny: int, nx: int) -> LandscapeCells:
        """The window ``spec`` names, checked against the raster's (ny, nx); ConfigError if not."""
        from fire_uav_common.scenario.ground import landscape_of

        land = landscape_of(spec)
        if land.shape != (ny, nx):
            raise ConfigError(f"landscape grid {land.shape} differs from the raster's ({ny}, {nx})")
        return cls(
            spec=spec,
            fuel=np.ascontiguousarray(land.fuel[::-1]).astype(np.int16),
            slope_pct=land.slope_pct[::-1],
            aspect_deg=land.aspect_deg[::-1],
            canopy_cover=land.canopy_cover[::-1],
            canopy_height_m=land.canopy_height_m[::-1],
            canopy_base_height_m=land.canopy_base_height_m[::-1],
            canopy_bulk_density_kgpm3=land.canopy_bulk_density_kgpm3[::-1],
        )

    def wind_grid_cells(self, grid: WindGrid) -> tuple[np.ndarray, np.ndarray]:
        """(20-ft speed [m/s], from-direction [deg cw from north]) per cell of ``grid``, row 0 south."""
        from fire_uav_common.scenario.ground import wind_cells

        s = self.spec
        w = wind_cells(grid, s.source, s.window, s.cell_size_m)
        return w.speed_mps[::-1], w.from_deg[::-1]

    def behavior(
        self,
        fuel: np.ndarray,
        wind_20ft_mps: float,
        toward_deg: float,
        wind_limit: str,
        *,
        grid: WindGrid | None = None,
    ) -> FireBehavior:
        """Per-cell fire behaviour of ``fuel`` (0: nothing burns, e.g. a lake) under a 20-ft wind
        blowing toward ``toward_deg`` [deg ccw from +x], or with ``grid`` each cell's own 20-ft
        wind from the grid (the two scalars are then not used)."""
        m = self.spec.moisture
        speed: float | np.ndarray = wind_20ft_mps
        from_deg: float | np.ndarray = (270.0 - toward_deg) % 360.0
        if grid is not None:
            speed, from_deg = self.wind_grid_cells(grid)
        return fire_behavior(
            np.where(fuel > 0, fuel, 99),  # outside the data or a lake: barren
            self.slope_pct,
            self.aspect_deg,
            wind_20ft_mps=speed,
            wind_from_deg=from_deg,
            moistures=FuelMoistures(Moisture(m.m_1h, m.m_10h, m.m_100h, m.m_herb, m.m_woody)),
            canopy_cover=self.canopy_cover,
            canopy_height_m=self.canopy_height_m,
            canopy_base_height_m=self.canopy_base_height_m,
            canopy_bulk_density_kgpm3=self.canopy_bulk_density_kgpm3,
            foliar_moisture=self.spec.foliar_moisture,
            crown=self.spec.crown,
            wind_limit=wind_limit,
        )
