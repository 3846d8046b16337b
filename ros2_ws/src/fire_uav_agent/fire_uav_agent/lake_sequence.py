"""One fixed-wing at a time on the lake, the others stacked above it (issue #36). ROS-free.

FF (IV-D b) flies a refilling UAV "low and slow" near the lake and says nothing of several UAVs
refilling at once: its unicycle turns at up to 10 rad/s and clears a peer in a fraction of a
second. A fixed-wing cannot stop or turn in place: the J3Cub turns on a 59 m radius and needs
some 4 s for a quarter turn, and its descent from its layer to the scoop height begins 527 m
out (``airframe_model.descent_m``). Two UAVs going down to FF's 90 m lake and leaving it climbing
met nearly head-on at 8.7 m (``ff_two_fires`` on ``jsbsim``, 5 UAVs, seed 1; docs/airframes.md).

Real crews sequence the water instead: scooper aircraft hold above the water while another
aircraft is on the scoop run (USDA Forest Service, *Amphibious Water Scooper Aircraft Operations
Plan*, 2016); traffic joins an airport's pattern in turn, the others holding clear and above
(FAA, *Aeronautical Information Manual*, 4-3-3); and aircraft waiting for an approach hold in a
stack, one level each, each descending a level as the one below leaves (AIM 5-3-8, holding).
Here every agent computes the same rule from what the fleet already shares (each peer's
position, height and objective, ``PeerState``), with no message of its own:

* a UAV is **on the lake** (it occupies it) when it is below ``low_agl_m`` (the lowest rung of
  the stack less a band for the height tracking error), refilling within ``radius_m`` of the
  lake's centre (it has begun its descent to scoop, or is scooping) or, with any other airborne
  objective, within ``clear_radius_m`` (climbing back to its layer after its refill; landing
  UAVs are left out by the caller);
* the **waiting** UAVs are those refilling within ``radius_m`` that are not on the lake; each
  has a **rank**, its place among them by id (0 for the lowest id);
* the **holder** of the lake is the lowest id on the lake; if nobody is on it, the waiting UAV
  of rank 0;
* only the holder descends to the scoop height; a waiting UAV of rank k holds on rung k of the
  stack above the lake (``Guide``: the lowest FF layer plus k layer steps), so that no two
  waiting UAVs circle the lake at one height.

By id, not the nearest first, so that the order does not change as the waiting UAVs circle (a
nearest-first rule would flip between two UAVs orbiting the lake), and the holder is the lowest
of the stack (rank 0): it descends with nobody waiting below it. A holder that vanishes from the
peer states (declared crashed after the fleet's ``crash_threshold_steps``,
``PeerLink.alive_states``) frees the lake; a lost state is the peer's last known one (FF IV-B), so
it holds the lake until it is heard again or declared crashed. Peers' states are of the step
before (0.1 s old): two UAVs low on one step both count as on the lake, and the higher id climbs
back to its rung.

FF is silent on all of this; the rule is ours, for fixed-wing airframes only (``ff_paper``'s
missions do not use it and stay as the paper's), and an opt-in: ``Guide`` applies it with the
scenario's ``mission.lake_sequence: stack`` only (default ``none``, FF IV-D b). It lifted the
J3Cubs' seed 1 above to 13.4 m, but brought the tanker's (``ff_two_fires_tanker``, seed 1) from
168 m to 5.0 m at the landing entries, and made missions up to 435 s longer. With ``stack`` a
landing UAV also yields its layer's landing entry area to a lower id (``Guide._entry_taken``):
the tanker's seed 1 at 12.8 m, 181 s longer than by default (docs/airframes.md).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

__all__ = ["LakeSequenceConfig", "LakeUser", "hold_rank", "lake_holder", "on_lake"]


@dataclass(frozen=True)
class LakeSequenceConfig:
    """Where the lake is held. ``radius_m``: from the lake's centre, the lake's radius plus the
    distance a refilling UAV begins its descent from (``Guide.lake_margin_m``): within it a low
    refilling UAV is on the lake, one above waits. ``clear_radius_m``: within it a low UAV that no
    longer refills is on the lake (leaving it climbing; the lake's radius plus two turn radii,
    short of FF's takeoff column, so that a climb after takeoff does not count). ``low_agl_m``:
    below this height above terrain [m] a UAV is low."""

    radius_m: float
    clear_radius_m: float
    low_agl_m: float

    def __post_init__(self) -> None:
        for name in ("radius_m", "clear_radius_m", "low_agl_m"):
            v = getattr(self, name)
            if not (v > 0.0 and math.isfinite(v)):
                raise ValueError(f"{name} must be > 0 and finite, got {v}")


@dataclass(frozen=True)
class LakeUser:
    """One airborne UAV as the rule sees it: position [m; map], height above terrain [m] and
    whether its objective is REFILL."""

    uav_id: int
    x_m: float
    y_m: float
    agl_m: float
    refilling: bool


def _dist(u: LakeUser, lake_xy_m: tuple[float, float]) -> float:
    return math.hypot(u.x_m - lake_xy_m[0], u.y_m - lake_xy_m[1])


def on_lake(u: LakeUser, lake_xy_m: tuple[float, float], cfg: LakeSequenceConfig) -> bool:
    """Whether ``u`` occupies the lake: below ``cfg.low_agl_m``, within ``cfg.radius_m`` of its
    centre if refilling (descending to scoop, scooping), else within ``cfg.clear_radius_m``
    (climbing away)."""
    near = _dist(u, lake_xy_m) < (cfg.radius_m if u.refilling else cfg.clear_radius_m)
    return near and u.agl_m < cfg.low_agl_m


def _waiting(users: list[LakeUser], lake_xy_m: tuple[float, float], cfg: LakeSequenceConfig) -> list[int]:
    return sorted(
        u.uav_id
        for u in users
        if u.refilling and _dist(u, lake_xy_m) < cfg.radius_m and not on_lake(u, lake_xy_m, cfg)
    )


def lake_holder(
    users: Iterable[LakeUser], lake_xy_m: tuple[float, float], cfg: LakeSequenceConfig
) -> int | None:
    """The id of the one UAV that may be low over the lake (module doc): the lowest id on the
    lake, else the waiting UAV of rank 0 (the lowest id); None if neither exists."""
    users = list(users)
    occupying = [u.uav_id for u in users if on_lake(u, lake_xy_m, cfg)]
    if occupying:
        return min(occupying)
    waiting = _waiting(users, lake_xy_m, cfg)
    return waiting[0] if waiting else None


def hold_rank(
    uav_id: int, users: Iterable[LakeUser], lake_xy_m: tuple[float, float], cfg: LakeSequenceConfig
) -> int:
    """``uav_id``'s rank among the waiting UAVs and itself (0: the lowest id), its rung of the stack:
    for a UAV refilling within ``cfg.radius_m`` that does not hold the lake (one on the lake that
    yields to a lower id climbs back to its rung as if waiting)."""
    return sorted(set(_waiting(list(users), lake_xy_m, cfg)) | {uav_id}).index(uav_id)
