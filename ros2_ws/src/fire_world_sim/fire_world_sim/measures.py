"""Measures of suppression success, computed by the world from its own truth.

Fire-service question: with N UAVs and this tactic, how much ground burns? The world keeps:

* **burned area** [m^2] over time: burning + burnt area of every fire (raster: ignited cells x
  cell area; analytic: pi sigma^2 of each fire, FF's Gaussian extent, for completeness);
* **hit rate** [-]: drops that wet at least one burning cell (raster) or hit an active fire
  (analytic), over all drops that released water (a request with an empty tank is no drop);
* **water on burning cells** [kg]: per drop, the released mass times the fraction of the
  footprint's cells that were burning (raster; the footprint is the disc of ``drop_radius_m``
  over cell centres); an analytic hit counts its whole load;
* **time to containment** [s], defined precisely in :class:`Containment`.

These are recomputed from the bag by the report (``fire_report.metrics.raster_measures``)
from ``/world/truth`` areas and ``/world/events`` drops, independently of this module.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from .errors import ConfigError, SequenceError

__all__ = ["CONTAINMENT_WINDOW_S", "Containment", "SuppressionMeasures"]

CONTAINMENT_WINDOW_S = 60.0  # [s] no front cell advancing for this long = contained


@dataclass
class Containment:
    """Time to containment: "no front cell advancing for ``window_s``" made precise.

    At sim time t the fire is **contained** when nothing burns any more, or when no cell has
    been ignited by the fire in the half-open window (t - window_s, t]: the latest ignition time
    of any cell, pre-burn included, is at most t - window_s. ``contained_at_s`` is the first
    update time from which the fire has stayed contained until now: a cell igniting later (the
    line breached, e.g. a wetted cell drying out) resets it to None, and a later quiet window
    sets it again. Hence ``contained_at_s`` >= last ignition + window_s, and a fire that never
    stops spreading reports None. Updates must come in non-decreasing time order.
    """

    window_s: float = CONTAINMENT_WINDOW_S
    contained_at_s: float | None = None
    _last_t_s: float = -math.inf

    def __post_init__(self) -> None:
        if not self.window_s > 0:
            raise ConfigError(f"containment window_s must be > 0, got {self.window_s}")

    def update(self, t_s: float, last_ignition_s: float, burning: bool) -> float | None:
        """Account the fire's state at ``t_s`` [s]; returns ``contained_at_s`` [s] or None.

        ``last_ignition_s``: latest ignition time [s] of any cell (-inf if none ignited yet);
        ``burning``: whether any cell is burning at ``t_s``.
        """
        if t_s < self._last_t_s:
            raise SequenceError(f"containment updates must not go back in time ({t_s} < {self._last_t_s})")
        self._last_t_s = t_s
        quiet = (not burning) or (t_s - last_ignition_s >= self.window_s - 1e-9)
        if not quiet:
            self.contained_at_s = None
        elif self.contained_at_s is None:
            self.contained_at_s = float(t_s)
        return self.contained_at_s


@dataclass
class SuppressionMeasures:
    """Running totals of one mission (see the module doc); ``as_dict`` gives plain values."""

    drops: int = 0  # drops that released water
    hits: int = 0  # ... of which wet at least one burning cell / hit an active fire
    water_released_kg: float = 0.0
    water_on_burning_kg: float = 0.0
    burned_area_m2: float = 0.0  # at the latest update
    area_t_s: list[float] = field(default_factory=list)  # [s] sample times of the area history
    area_m2: list[float] = field(default_factory=list)  # [m^2] burned area at area_t_s
    containment: Containment = field(default_factory=Containment)
    area_every_s: float = 1.0  # [s] area history sampling period

    def add_drop(self, kg: float, burning_cells: int, footprint_cells: int, hit: bool) -> float:
        """One drop of ``kg`` [kg]; returns the water [kg] that fell on burning cells."""
        if kg <= 0:
            return 0.0
        self.drops += 1
        self.hits += int(hit)
        self.water_released_kg += kg
        on = kg * burning_cells / footprint_cells if footprint_cells > 0 else (kg if hit else 0.0)
        self.water_on_burning_kg += on
        return on

    def update(self, t_s: float, burned_area_m2: float, last_ignition_s: float, burning: bool) -> None:
        self.burned_area_m2 = float(burned_area_m2)
        if not self.area_t_s or t_s - self.area_t_s[-1] >= self.area_every_s - 1e-9:
            self.area_t_s.append(float(t_s))
            self.area_m2.append(float(burned_area_m2))
        self.containment.update(t_s, last_ignition_s, burning)

    @property
    def hit_rate(self) -> float | None:
        return self.hits / self.drops if self.drops else None

    def as_dict(self) -> dict:
        return {
            "drops": self.drops,
            "hits": self.hits,
            "hit_rate": self.hit_rate,
            "water_released_kg": self.water_released_kg,
            "water_on_burning_kg": self.water_on_burning_kg,
            "burned_area_m2": self.burned_area_m2,
            "contained_at_s": self.containment.contained_at_s,
        }
