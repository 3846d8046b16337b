"""The dispatch briefing of the known-fires mode: noisy initial estimates of every fire (FF III-C, IV-D c).

FF's fleet knows its fires from the start -- their number and initial position and extent --
and refines them with its sensors. With ``mission.prior_fires: known`` the runner (and the
in-process harness) give every agent the same briefing through its ``prior_fires`` parameter;
the agents never read the scenario's fires themselves. The briefing is drawn here, next to the
truth, with a seeded stream: centre + N(0, ``prior_position_sigma_m``^2) per axis, extent times
(1 + N(0, ``prior_extent_sigma_fraction``^2)) kept within [0.5, 1.5] of the truth. FF gives no
noise figures; 10 m and 20 % are our choice (a spotter's estimate, well inside the 70 m sensor
range, so the first pass over a fire finds it). Only analytic fires that burn at t = 0 are
briefed (a raster fire has no single centre and extent).
"""

from __future__ import annotations

from fire_uav_common.rng import stream
from fire_uav_common.scenario import Scenario

__all__ = ["prior_fire_estimates"]


def prior_fire_estimates(scenario: Scenario, seed: int | None = None) -> list[tuple[float, float, float]]:
    """(x_m, y_m, extent_m) per briefed fire, in the scenario's order; [] unless ``prior_fires: known``."""
    m = scenario.mission
    if m.prior_fires != "known" or scenario.fires.model != "analytic":
        return []
    rng = stream(scenario.seed if seed is None else int(seed), "prior_fires", 0)
    out = []
    for f in scenario.fires.analytic:
        if f.start_s > 0:
            continue
        dx, dy, de = rng.normal(size=3)
        scale = min(1.5, max(0.5, 1.0 + m.prior_extent_sigma_fraction * float(de)))
        out.append(
            (
                f.x_m + m.prior_position_sigma_m * float(dx),
                f.y_m + m.prior_position_sigma_m * float(dy),
                f.sigma_m * scale,
            )
        )
    return out
