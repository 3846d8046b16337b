"""One fixed-wing at a time on the lake: who may descend to scoop (issue #36). ROS-free.

FF (IV-D b) flies a refilling UAV "low and slow" near the lake and says nothing of several UAVs
refilling at once: its unicycle turns at up to 10 rad/s and clears a peer in a fraction of a
second. A fixed-wing cannot stop or turn in place: the J3Cub turns on a 59 m radius and needs
some 4 s for a quarter turn, and its descent from its layer to the scoop height begins 527 m
out (``airframe_model.descent_m``). Two UAVs going down to FF's 90 m lake and leaving it climbing
met nearly head-on at 8.7 m (``ff_two_fires`` on ``jsbsim``, 5 UAVs, seed 1; docs/airframes.md).

Real crews sequence the water instead: scooper aircraft hold above the water while another
aircraft is on the scoop run (USDA Forest Service, *Amphibious Water Scooper Aircraft Operations
Plan*, 2016), and traffic joins an airport's pattern in turn, one aircraft on each part of it,
the others holding clear and above (FAA, *Aeronautical Information Manual*, 4-3-3). Here every
agent computes the same rule from what the fleet already shares (each peer's position, height
and objective, ``PeerState``), with no message of its own:

* a UAV is **on the lake** (it occupies it) when it is below its own layer by more than
  ``band_m``, refilling within ``radius_m`` of the lake's centre (it has begun its descent to
  scoop, or is scooping) or, with any other airborne objective, within ``clear_radius_m``
  (climbing back to its layer after its refill; landing UAVs are left out by the caller);
* the **holder** of the lake is the lowest id on the lake; if nobody is on it, the lowest id
  among the UAVs that refill within ``radius_m`` (the waiting ones);
* only the holder descends to the scoop height; every other refilling UAV keeps its layer (at
  least ``band_m`` above the scoop run), holding above the lake until it holds the lake.

The lowest id, not the nearest UAV, so that the choice does not change as the waiting UAVs
circle (a nearest-first rule would flip between two UAVs orbiting the lake). A holder that
vanishes from the peer states (declared crashed after the fleet's ``crash_threshold_steps``,
``PeerLink.alive_states``) frees the lake; a lost state is the peer's last known one (FF IV-B),
so it holds the lake until it is heard again or declared crashed. Peers' states are of the step
before (0.1 s old); two UAVs that begin their descents on one step see each other on the lake
the step after, and the higher id climbs back to its layer.

FF is silent on all of this; the rule is ours, for fixed-wing airframes only (``ff_paper``'s
missions do not use it and stay as the paper's).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

__all__ = ["LakeSequenceConfig", "LakeUser", "lake_holder", "on_lake"]


@dataclass(frozen=True)
class LakeSequenceConfig:
    """Where the lake is held. ``radius_m``: from the lake's centre, the lake's radius plus the
    distance a refilling UAV begins its descent from (``Guide.lake_margin_m``): within it a low
    refilling UAV is on the lake, a refilling one above it waits. ``clear_radius_m``: within it a
    low UAV that no longer refills is on the lake (leaving it climbing; the lake's radius plus two
    turn radii, short of the takeoff column so that a climb after takeoff does not count).
    ``band_m``: how far below its own layer a UAV must be to count as low (above the height
    tracking error)."""

    radius_m: float
    clear_radius_m: float
    band_m: float

    def __post_init__(self) -> None:
        if not (self.radius_m > 0.0 and math.isfinite(self.radius_m)):
            raise ValueError(f"radius_m must be > 0 and finite, got {self.radius_m}")
        if not (self.clear_radius_m > 0.0 and math.isfinite(self.clear_radius_m)):
            raise ValueError(f"clear_radius_m must be > 0 and finite, got {self.clear_radius_m}")
        if not (self.band_m > 0.0 and math.isfinite(self.band_m)):
            raise ValueError(f"band_m must be > 0 and finite, got {self.band_m}")


@dataclass(frozen=True)
class LakeUser:
    """One airborne UAV as the rule sees it: position [m; map], height above terrain [m], its own
    layer height [m above terrain] and whether its objective is REFILL."""

    uav_id: int
    x_m: float
    y_m: float
    agl_m: float
    layer_m: float
    refilling: bool


def on_lake(u: LakeUser, lake_xy_m: tuple[float, float], cfg: LakeSequenceConfig) -> bool:
    """Whether ``u`` occupies the lake: more than ``cfg.band_m`` below its own layer, within
    ``cfg.radius_m`` of its centre if refilling (descending to scoop, scooping), else within
    ``cfg.clear_radius_m`` (climbing away)."""
    d = math.hypot(u.x_m - lake_xy_m[0], u.y_m - lake_xy_m[1])
    near = d < (cfg.radius_m if u.refilling else cfg.clear_radius_m)
    return near and u.agl_m < u.layer_m - cfg.band_m


def lake_holder(
    users: Iterable[LakeUser], lake_xy_m: tuple[float, float], cfg: LakeSequenceConfig
) -> int | None:
    """The id of the one UAV that may be low over the lake (module doc): the lowest id on the
    lake, else the lowest id refilling within ``cfg.radius_m``; None if neither exists."""
    users = list(users)
    occupying = [u.uav_id for u in users if on_lake(u, lake_xy_m, cfg)]
    if occupying:
        return min(occupying)
    waiting = [
        u.uav_id
        for u in users
        if u.refilling and math.hypot(u.x_m - lake_xy_m[0], u.y_m - lake_xy_m[1]) < cfg.radius_m
    ]
    return min(waiting) if waiting else None
