"""The one small interface both fire models implement (crazyswarm2-style swappable backend)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from ..sensors import CellsSample

__all__ = ["FireModel", "FireTruthRecord"]


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


class FireModel(Protocol):
    """Fires advance in sim time; drops suppress them; sensors query them."""

    def step(self, t_s: float, dt_s: float) -> list[tuple[int, str]]:
        """Advance from t_s to t_s + dt_s. Returns (fire_id, what) for fires that started
        ("ignition") or went out by themselves ("extinguished") during the step."""
        ...

    def apply_drop(self, x_m: float, y_m: float, radius_m: float | None) -> list[int]:
        """A full load released at (x_m, y_m); radius None = model default. Returns fire ids
        hit (the caller then reports which of them went out via ``truth()``)."""
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
    def all_out(self) -> bool:
        """Every fire (including not yet started ones) is extinguished."""
        ...
