"""Fire models behind one interface (:class:`FireModel`): analytic Gaussian (FF) and raster (PM VI)."""

from ..errors import ConfigError
from .analytic import AnalyticFireModel
from .base import FireGrid, FireModel, FireTruthRecord
from .raster import RasterFireModel

__all__ = [
    "AnalyticFireModel",
    "FireGrid",
    "FireModel",
    "FireTruthRecord",
    "RasterFireModel",
    "make_fire_model",
]


def make_fire_model(fires_spec, terrain, lakes=()) -> FireModel:
    """Build the model a scenario's ``fires:`` section asks for."""
    if fires_spec.model == "analytic":
        return AnalyticFireModel(fires_spec.analytic, fires_spec.extinction_sigma_m, fires_spec.drop_radius_m)
    if fires_spec.model == "raster":
        return RasterFireModel(
            fires_spec.raster, terrain, lakes=lakes, drop_radius_m=fires_spec.drop_radius_m
        )
    raise ConfigError(f"unknown fire model {fires_spec.model!r}")
