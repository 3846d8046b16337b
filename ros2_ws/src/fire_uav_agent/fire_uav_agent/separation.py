"""Turn-rate-limited collision avoidance between UAVs, on top of the Lloyd controller (FF III-A, Eq. 7).

FF's safety band (Eq. 7) keeps two UAVs apart only while both fly to their Voronoi centroids.
An attack run (steering straight at a fire), the queue over the lake and the landing approach
do not follow the centroid, and there the band holds nothing (FF V-D: "collision risk" beyond
14 UAVs; VI-A asks for "velocity obstacles or barrier certificates"). This module is a
sampled velocity-obstacle filter: each control step it checks the desired heading against
every peer's predicted straight-line motion over ``horizon_s``, and if the closest approach
would fall below ``radius_m`` it picks, among ``headings`` candidate headings, the one nearest
the desired heading that keeps every peer beyond ``radius_m`` over the horizon (or, when none
does, the one with the largest closest approach). Every UAV applies the same rule (reciprocal
avoidance); peers separated by more than ``vertical_m`` in height over the whole horizon are no
conflict.

Vertical rates (our addition; FF is silent, its UAVs fly at one height). The heights are
predicted too, each straight at its vertical speed (a peer's from its last two states, our own
the commanded v_z): a peer is no conflict only if the height difference stays above
``vertical_m`` over the horizon, as TCAS judges a vertical threat by the closure rate, not the
separation now (FAA, Introduction to TCAS II Version 7.1, 2011: the vertical tau). Checked on
the height difference now alone, a UAV climbing out of a missed landing at 15 m/s and a peer
descending to land at 15 m/s were "26.5 m apart, no conflict" 0.7 s before they passed 8.8 m apart
(28.5 m at 0.9 s; grass_running, 6 UAVs, auto, seed 2 of the tactics study, 565.8 s). The scenario's
``mission.vertical_band`` chooses (``agent_config.config_from_scenario``); its default ``auto``
predicts for FF's unicycle only, from what it did (docs/suppression.md, "Vertical rates in the
avoider"): FF's unicycle, 15 missions, the closest approach of the worst from 8.8 to 13.5 m
(grass_running seeds 1-3: 13.4 / 8.8 / 10.5 -> 14.0 / 13.7 / 13.5 m; FF's 5, 8 and 14 UAVs, seeds
1-3: 10.1-20.8 -> 14.5-26.4 m); on fixed-wings it lifted two tankers' 9.0 m pass (one going
around, ff_two_fires_tanker with unknown fires, seed 1) to 14.3 m but lowered small_uav's on
ff_two_fires from 14.8 / 22.3 / 14.2 to 11.3 / 11.4 / 14.1 m: a fixed-wing's commanded v_z, used
for its own height, is not the one it flies (the flight-path angle lags, climb and descent are
limited), so there the default stays the height now.

Vertical resolution (our addition; FF is silent, its unicycle turns at 10 rad/s). A fixed-wing
turns at g tan(phi_max) / v: at a monitor's 15.6 m/s small_uav's 45 deg bank is a 25 m turn radius,
2.5 s for a quarter turn, and the heading alone cannot clear 20 m from a peer that the height check
admits late. Measured (grass_brush_hill, small_uav on coordinated_turn, seed 3, 126.1 s): UAV 1, a
monitor descending at 4 m/s, and UAV 4, a suppressor climbing at 4.5 m/s to its layer, crossing
some 100 deg apart; both commanded their full climb and descent rates toward each other's
heights, the band (the height now) admitted the pair at 10 m, 37 m apart, and they passed 5.1 m
apart. So with ``vertical_resolution`` (agent_config sets it on ``coordinated_turn``; on ``jsbsim``
the J3Cub's ff_two_fires seed 2 came to 6.4 m with it, 13.9 m without) the agent also
changes its v_z when :func:`vertical_sense` finds a threat: a peer the present course brings
within ``radius_m + release_margin_m`` over the horizon while the heights, each straight at its
measured vertical speed, come within ``vertical_m``: the higher UAV stops descending, the lower
stops climbing (the lower only above ``vertical_m`` over the terrain; never while landing, whose
layers :func:`hold_layer` keeps), as TCAS II's coordinated "do not descend" / "do not climb"
advisories keep the vertical gap from closing (FAA, *Introduction to TCAS II Version 7.1*,
2011). Both judge the same two heights, so the senses are complementary; the heading filter runs
as before.

Detection range (our addition; FF is silent). Peers further than ``detect_m`` are ignored. FF's
150 m is 0.75 s at the unicycle's 200 m/s head-on closing speed, enough for a vehicle that turns
at 10 rad/s (and FF's figures rest on it: ff_paper keeps it); a fixed-wing's horizon is at least
its quarter turn (:func:`avoid_heading`), 12 s for the tanker at 75 m/s,
and 150 m cut it to one second (two tankers on one layer passed 7.28 m apart,
grass_running_tanker seed 2). So a fixed-wing's range is :func:`detect_range_m`, the distance two
aircraft at its top speed close over that horizon (agent_config sets it from the preset).
With every peer in that range constraining the candidate headings, on FF's 600 m map (small_uav
308 m, the J3Cub 364 m) two UAVs refilling at the lake passed 9.8 and 8.4 m apart (ff_two_fires
seed 2; 17.3 and 15.2 m with 150 m). So beyond ``on_course_beyond_m`` (FF's 150 m) a peer counts
only when the present course, straight at the present speed, comes within ``radius_m +
release_margin_m`` of the peer's straight line within the horizon, the head-on and crossing
conflicts the range was widened for: 17.3 and 11.0 m, and the tanker's 7.28 m pass 22.4 m
(docs/airframes.md, rows "detect range, on course"; over 7 seeds the missions take 5 % longer
than with 150 m, the difference in the landing phase: go-arounds after a final that crossed the
threshold more than the touch-down radius off the line, 8 in 35 landings against 3).

Choice where FF is silent: the unicycle of Eq. 4 turns at up to 10 rad/s (FF II-B), so a
heading change of up to 1 rad per 0.1 s control step is available and the filter acts only on
the heading (speed kept at the law's value, lowered to stall speed when no heading is clear).
Positions [m; map frame], velocities [m/s], headings [rad] ccw from +x.

Right of way (our addition). At 100 m/s two UAVs close 20 m per 0.1 s step and turn at
up to 10 rad/s, so a peer's straight-line prediction from its last two states is wrong exactly
when it matters (after a drop a UAV reverses towards the lake; measured: 3.0-3.6 m passes, 8
UAVs). So within ``yield_m`` of a peer with the right of way (the lower uav id) a UAV only flies
headings that do not close on that peer's position (``cos(heading, bearing from peer) >= 0``), at
full speed; the peer keeps its course. The lowest id of a cluster always proceeds (no deadlock:
a symmetric "both turn away" rule kept two UAVs on opposite sides of a fire from ever reaching it).

Intent of a turning peer (our addition; FF is silent). Every UavState carries the
centroid its sender steers at (FF Eqs. 8-12: the control law turns the unicycle towards it at up
to 10 rad/s). So a peer with the right of way within ``yield_m`` is checked twice: on its straight
line, and flying at the same speed straight at its centroid when that is more than
``intent_min_turn_rad`` off its course (:func:`peer_rows`): the reversal after a drop is seen the
step the peer publishes its new target, not two steps after it has turned. Measured on the FF
scenario: the closest approaches of 9.1 m (known fires, 14 UAVs, seed 1) and 7.8 m (unknown, 8 UAVs,
seed 1) became 13.2 m and 22.4 m at the same mission times (docs/benchmarks.md, acceptance matrix).
Intent rows for every peer within ``detect_m`` doubled the mission time of those cells (54 s
instead of 31 s; 160 s instead of 89 s): the UAVs that yield need them, the others do not.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from fire_uav_common.codecs.uav_state import PeerState
from fire_uav_common.constants import Objective

from .errors import ConfigError, InputError
from .estimation import wrap_angle

__all__ = [
    "Avoider",
    "PeerAvoidance",
    "SeparationConfig",
    "avoid_heading",
    "closest_approach_m",
    "detect_range_m",
    "effective_horizon_s",
    "hold_layer",
    "peer_rows",
    "turning_approach_m",
    "vertical_sense",
]


@dataclass(frozen=True)
class SeparationConfig:
    radius_m: float = 20.0  # [m] keep every predicted horizontal approach above this (FF Delta_ij = 2 x 10 m)
    vertical_m: float = (
        10.0  # [m] peers further apart than this in height are no conflict (the 10 m band in 3-D)
    )
    horizon_s: float = 2.0  # [s] look-ahead of the straight-line prediction
    # [m] peers further than this are ignored; FF's unicycle's, fixed-wings get their airframe's
    # (detect_range_m, set by agent_config.config_from_scenario)
    detect_m: float = 150.0
    headings: int = 72  # candidate headings, evenly spaced
    # [m] a fixed-wing's peers beyond this (and within detect_m) count only when its present course
    # meets them within the horizon (module doc, "Detection range"); FF's range
    on_course_beyond_m: float = 150.0
    release_margin_m: float = 10.0  # [m] once avoiding, the desired heading must clear radius + this
    yield_m: float = 60.0  # [m] within this of a peer with the right of way, do not close on it
    intent: bool = True  # also predict each peer flying at its published centroid (module doc)
    intent_min_turn_rad: float = 0.5  # [rad] the intent row is added only if it turns the peer this much
    # predict the heights over the horizon too (module doc; the scenario's mission.vertical_band
    # sets it); False: the height difference now only
    vertical_rates: bool = False
    # a fixed-wing also resolves a conflict vertically (module doc, "Vertical resolution"):
    # agent_config sets it for airframes; FF's unicycle turns at 10 rad/s and keeps the heading only
    vertical_resolution: bool = False

    def __post_init__(self) -> None:
        for name in ("radius_m", "vertical_m", "horizon_s", "detect_m", "on_course_beyond_m"):
            if not getattr(self, name) > 0:
                raise ConfigError(f"SeparationConfig.{name} must be > 0, got {getattr(self, name)}")
        if self.headings < 4:
            raise ConfigError(f"SeparationConfig.headings must be >= 4, got {self.headings}")


def closest_approach_m(rel_pos_m: np.ndarray, rel_vel_mps: np.ndarray, horizon_s: float) -> np.ndarray:
    """Closest distance [m] over t in [0, horizon_s] of ``rel_pos + rel_vel t``; rows are pairs, (n,)."""
    r = np.asarray(rel_pos_m, dtype=float).reshape(-1, 2)
    w = np.asarray(rel_vel_mps, dtype=float).reshape(-1, 2)
    ww = np.einsum("ij,ij->i", w, w)
    t = np.where(ww > 1e-12, -np.einsum("ij,ij->i", r, w) / np.maximum(ww, 1e-12), 0.0)
    t = np.clip(t, 0.0, horizon_s)
    c = r + w * t[:, None]
    return np.hypot(c[:, 0], c[:, 1])


def hold_layer(
    own_xyz_m: tuple[float, float, float],
    right_of_way_xyz_m: list[tuple[float, float, float]],
    cfg: SeparationConfig,
) -> bool:
    """Whether a landing UAV keeps its layer height instead of descending (FF IV-D d; our addition).

    FF's landing (IV-D d) descends "within a certain distance" of the start point and says
    nothing of peers. Our start points are 30 m apart, so two neighbours land side by side, and
    the altitude layers that kept them apart (14 m) close in the descent (measured: 9.3 m, known
    fires, 14 UAVs, seed 2). A UAV holds its layer while any peer with the right of way (rows of
    ``right_of_way_xyz_m``, positions [m; map]) is below it within ``cfg.radius_m`` horizontally.
    """
    x, y, z = own_xyz_m
    return any(math.hypot(px - x, py - y) < cfg.radius_m and pz < z for px, py, pz in right_of_way_xyz_m)


def peer_rows(
    state: tuple[float, float, float, float, float],
    centroid_xy: tuple[float, float],
    min_speed_mps: float,
    cfg: SeparationConfig,
    own_xy: tuple[float, float] | None = None,
    right_of_way: bool = True,
) -> list[tuple[float, float, float, float, float]]:
    """The predictions of one peer that :func:`avoid_heading` checks: rows (x_m, y_m, z_m, vx_mps, vy_mps).

    ``state`` is the straight-line prediction from the peer's last two states. With ``cfg.intent``
    a second row has the peer at the same point flying at its speed (at least ``min_speed_mps``)
    straight at ``centroid_xy``, the target it published with that state (FF Eqs. 8-12 steer at
    it; the unicycle turns at up to 10 rad/s, so a reversal takes about 0.3 s): added only when
    that heading differs from the peer's course by more than ``cfg.intent_min_turn_rad`` and the
    centroid is finite and not at the peer (then the peer is about to turn and the straight line
    is wrong exactly at the drop point, module doc). Only for a peer with the right of way
    (``right_of_way``; the others yield to us) within ``cfg.yield_m`` of ``own_xy``: predicting
    every peer's intent at up to ``detect_m`` doubled the mission time (8 UAVs, measured).
    """
    x, y, z, vx, vy = state
    rows = [state]
    cx, cy = centroid_xy
    if not cfg.intent or not right_of_way or not (math.isfinite(cx) and math.isfinite(cy)):
        return rows
    if own_xy is not None and math.hypot(x - own_xy[0], y - own_xy[1]) > cfg.yield_m:
        return rows
    bx, by = cx - x, cy - y
    nb = math.hypot(bx, by)
    if nb < 1e-6:
        return rows
    sp = max(math.hypot(vx, vy), min_speed_mps)
    if math.hypot(vx, vy) > 1e-9 and abs(wrap_angle(math.atan2(by, bx) - math.atan2(vy, vx))) <= (
        cfg.intent_min_turn_rad
    ):
        return rows
    rows.append((x, y, z, sp * bx / nb, sp * by / nb))
    return rows


def turning_approach_m(
    rel_pos_m: np.ndarray,
    peer_vel_mps: np.ndarray,
    speed_mps: float,
    heading_rad: float,
    candidates_rad: np.ndarray,
    turn_rate_radps: float,
    horizon_s: float,
    dt_s: float = 0.1,
) -> np.ndarray:
    """Closest approach [m] to any peer per candidate heading, (h,), for a vehicle that turns.

    Own motion: from heading ``heading_rad`` at ``speed_mps``, a coordinated turn at
    ``turn_rate_radps`` toward the candidate (the shorter way), then straight on it; peers (rows
    of ``rel_pos_m`` relative to us, ``peer_vel_mps``) straight. Sampled every ``dt_s`` over
    [0, ``horizon_s``].
    """
    t = np.arange(0.0, horizon_s + 1e-9, dt_s)  # (m,)
    cand = np.asarray(candidates_rad, dtype=float).reshape(-1)
    delta = np.remainder(cand - heading_rad + math.pi, math.tau) - math.pi  # (h,)
    w = max(turn_rate_radps, 1e-6)
    t_turn = np.abs(delta) / w
    sgn = np.sign(delta)
    tt = np.minimum(t[None, :], t_turn[:, None])  # (h, m) time spent turning
    th = heading_rad + sgn[:, None] * w * tt  # heading at the end of the turn part
    # arc: integral of v (cos, sin)(theta0 + s w t) dt; straight: v (cos, sin)(candidate)(t - t_turn)
    turning = sgn[:, None] != 0.0
    safe = np.where(turning, sgn[:, None] * w, 1.0)
    ax = np.where(
        turning,
        speed_mps * (np.sin(th) - math.sin(heading_rad)) / safe,
        speed_mps * math.cos(heading_rad) * tt,
    )
    ay = np.where(
        turning,
        -speed_mps * (np.cos(th) - math.cos(heading_rad)) / safe,
        speed_mps * math.sin(heading_rad) * tt,
    )
    rest = t[None, :] - tt
    ox = ax + speed_mps * np.cos(cand)[:, None] * rest  # (h, m)
    oy = ay + speed_mps * np.sin(cand)[:, None] * rest
    r = np.asarray(rel_pos_m, dtype=float).reshape(-1, 2)
    v = np.asarray(peer_vel_mps, dtype=float).reshape(-1, 2)
    px = r[:, 0][None, :, None] + v[:, 0][None, :, None] * t[None, None, :]  # (1, n, m)
    py = r[:, 1][None, :, None] + v[:, 1][None, :, None] * t[None, None, :]
    d = np.hypot(px - ox[:, None, :], py - oy[:, None, :])  # (h, n, m)
    return d.min(axis=(1, 2))


def effective_horizon_s(cfg: SeparationConfig, turn_rate_radps: float | None = None) -> float:
    """The avoider's look-ahead [s]: ``cfg.horizon_s``, or for a vehicle turning at
    ``turn_rate_radps`` [rad/s] at least the time of a quarter turn, (pi / 2) / rate (a deviation
    of 90 deg is what a head-on or crossing conflict may need; :func:`avoid_heading`)."""
    if turn_rate_radps is None:
        return cfg.horizon_s
    return max(cfg.horizon_s, 0.5 * math.pi / max(turn_rate_radps, 1e-6))


def detect_range_m(cfg: SeparationConfig, v_max_mps: float, turn_rate_radps: float) -> float:
    """The range [m] within which the avoider must see a peer for its own look-ahead to be of use.

    Two aircraft at the top speed ``v_max_mps`` head on close at 2 v_max; a pair whose closest
    approach, ``cfg.radius_m`` apart, lies at the end of the horizon H (:func:`effective_horizon_s`
    at ``turn_rate_radps``, the rate at the top speed, where the quarter turn takes longest) is
    2 v_max H + radius_m apart now. A peer ignored beyond that range cannot be in a conflict the
    horizon would have seen; a shorter range cuts the horizon to range / (2 v_max). Never less than
    ``cfg.detect_m`` (the range FF's unicycle flies with).

    The presets (g tan(phi_max) / v at v_max; docs/airframes.md): ``tanker`` 75 m/s at 45 deg: H =
    12.0 s, 2 x 75 x 12.0 + 20 = 1,822 m; ``small_uav`` 30 m/s at 45 deg: H = 4.8 s, 308 m;
    ``j3cub`` 30 m/s at 40 deg: H = 5.7 s, 364 m. The old 150 m was 1.0 s at the tankers' 144 m/s
    closing speed (grass_running_tanker seed 2: two tankers on one layer passed 7.28 m apart).
    """
    h = effective_horizon_s(cfg, turn_rate_radps)
    return max(cfg.detect_m, 2.0 * v_max_mps * h + cfg.radius_m)


def avoid_heading(
    own_xyz_m: tuple[float, float, float],
    speed_mps: float,
    desired_heading_rad: float,
    peers: np.ndarray,
    cfg: SeparationConfig,
    margin_m: float = 0.0,
    prefer_heading_rad: float | None = None,
    yield_to: np.ndarray | None = None,
    turn_rate_radps: float | None = None,
    heading_rad: float = 0.0,
    own_vz_mps: float = 0.0,
) -> tuple[float, bool, bool]:
    """Heading [rad] to fly, whether it differs from the desired one, and whether it is clear.

    ``turn_rate_radps`` (a fixed-wing's achievable rate, g tan(phi_max) / v): own motion toward a
    candidate heading is predicted as a turn from ``heading_rad`` at that rate, then straight
    (:func:`turning_approach_m`), over at least the time of a quarter turn; None: the heading is
    taken at once (FF's unicycle turns at 10 rad/s), as before.

    ``margin_m`` raises the clearance the desired heading needs (:class:`Avoider`'s hysteresis);
    ``prefer_heading_rad`` (default: the desired heading) is what a deviation stays nearest to.

    ``peers`` rows are (x_m, y_m, z_m, vx_mps, vy_mps[, vz_mps]) predicted to the same instant as
    ``own_xyz_m``; with ``cfg.vertical_rates`` a peer is relevant if its height difference comes
    within ``vertical_m`` over the horizon, the heights moving at their vertical speeds (a row's
    vz_mps, 0 without it; ``own_vz_mps`` ours). Returns ``(desired_heading_rad, False, True)`` when the desired heading keeps
    every relevant peer beyond ``radius_m`` over the horizon. ``yield_to`` (bool per peer row):
    peers with the right of way (module doc).
    """
    p = np.asarray(peers, dtype=float)
    cols = p.shape[-1] if p.ndim == 2 else 5
    if cols not in (5, 6):
        raise InputError(f"peers rows must have 5 or 6 columns (x, y, z, vx, vy[, vz]), got {cols}")
    p = p.reshape(-1, cols)
    x, y, z = own_xyz_m
    yt = np.zeros(p.shape[0], bool) if yield_to is None else np.asarray(yield_to, bool).reshape(-1)
    if yt.shape[0] != p.shape[0]:
        raise InputError(f"yield_to must have one entry per peer row ({p.shape[0]}), got {yt.shape[0]}")
    horizon = effective_horizon_s(cfg, turn_rate_radps)
    if p.shape[0]:
        rel = p[:, :2] - np.array([x, y])
        dz = p[:, 2] - z
        if cfg.vertical_rates:
            # the height difference at the horizon's end, both heights straight at their rates
            dz_end = dz + ((p[:, 5] if cols == 6 else 0.0) - own_vz_mps) * horizon
            # the closest over [0, horizon]: 0 if it changes sign, else the nearer end
            dz_min = np.where(dz * dz_end <= 0.0, 0.0, np.minimum(np.abs(dz), np.abs(dz_end)))
        else:
            dz_min = np.abs(dz)
        dist = np.hypot(rel[:, 0], rel[:, 1])
        near = (dist <= cfg.detect_m) & (dz_min <= cfg.vertical_m)
        if turn_rate_radps is not None and cfg.on_course_beyond_m < cfg.detect_m:
            # beyond on_course_beyond_m, only a peer our present course meets within the horizon
            far = near & (dist > cfg.on_course_beyond_m)
            if far.any():
                own_v = speed_mps * np.array([math.cos(heading_rad), math.sin(heading_rad)])
                meet = closest_approach_m(rel[far], p[far, 3:5] - own_v, horizon)
                near[np.flatnonzero(far)[meet >= cfg.radius_m + cfg.release_margin_m]] = False
        p, rel, yt = p[near], rel[near], yt[near]
    if p.shape[0] == 0:
        return desired_heading_rad, False, True
    away = -rel[yt & (np.hypot(rel[:, 0], rel[:, 1]) <= cfg.yield_m)]  # from right-of-way peers to us

    def opening(heading: np.ndarray) -> np.ndarray:
        """Per candidate heading: closes on no right-of-way peer within yield_m, (h,)."""
        if away.shape[0] == 0:
            return np.ones(heading.shape[0], bool)
        u = np.column_stack([np.cos(heading), np.sin(heading)])
        return np.all(u @ away.T >= 0.0, axis=1)

    def worst(heading: np.ndarray) -> np.ndarray:
        """Closest approach to any peer [m] per candidate heading, (h,)."""
        if turn_rate_radps is not None:
            return turning_approach_m(
                rel, p[:, 3:5], speed_mps, heading_rad, heading, turn_rate_radps, horizon
            )
        u = speed_mps * np.column_stack([np.cos(heading), np.sin(heading)])  # (h, 2)
        w = (p[None, :, 3:5] - u[:, None, :]).reshape(-1, 2)  # (h * n, 2) relative velocities
        r = np.broadcast_to(rel[None], (heading.shape[0], *rel.shape)).reshape(-1, 2)
        return closest_approach_m(r, w, cfg.horizon_s).reshape(heading.shape[0], -1).min(axis=1)

    des = np.array([desired_heading_rad])
    if worst(des)[0] >= cfg.radius_m + margin_m and opening(des)[0]:
        return desired_heading_rad, False, True
    ref = desired_heading_rad if prefer_heading_rad is None else prefer_heading_rad
    cand = ref + np.linspace(-math.pi, math.pi, cfg.headings, endpoint=False)
    d = worst(cand)
    dev = np.abs([wrap_angle(float(c - ref)) for c in cand])
    ok = (d >= cfg.radius_m + margin_m) & opening(cand)
    if ok.any():
        k = int(np.argmin(np.where(ok, dev, np.inf)))
        return float(wrap_angle(float(cand[k]))), True, True
    if away.shape[0]:  # nothing clear: straight away from the nearest right-of-way peer
        a = away[int(np.argmin(np.hypot(away[:, 0], away[:, 1])))]
        return float(math.atan2(a[1], a[0])), True, True  # at full speed: gain distance fast
    k = int(np.lexsort((dev, -d))[0])  # largest closest approach, then nearest the desired heading
    return float(wrap_angle(float(cand[k]))), True, False


def vertical_sense(
    own_xyz_m: tuple[float, float, float],
    speed_mps: float,
    heading_rad: float,
    own_vz_mps: float,
    peers: np.ndarray,
    horizon_s: float,
    cfg: SeparationConfig,
) -> int:
    """The vertical resolution of a fixed-wing: +1 do not descend, -1 do not climb, 0 none.

    A threat is a peer (rows x_m, y_m, z_m, vx_mps, vy_mps, vz_mps) that our present course,
    straight at ``speed_mps``, brings within ``radius_m + release_margin_m`` horizontally over
    ``horizon_s`` while the height difference, both heights straight at their measured vertical
    speeds (``own_vz_mps`` ours), comes within ``vertical_m``. Against every threat below us we
    stop descending, against every threat above us we stop climbing; threats on both sides: none.
    Both UAVs of a pair judge the same two heights, so their senses are complementary, as TCAS II
    coordinates its "do not descend" / "do not climb" advisories (FAA, *Introduction to TCAS II
    Version 7.1*, 2011).
    """
    p = np.asarray(peers, dtype=float).reshape(-1, 6)
    x, y, z = own_xyz_m
    rel = p[:, :2] - np.array([x, y])
    own_v = speed_mps * np.array([math.cos(heading_rad), math.sin(heading_rad)])
    horiz = closest_approach_m(rel, p[:, 3:5] - own_v, horizon_s) < cfg.radius_m + cfg.release_margin_m
    dz = p[:, 2] - z
    dz_end = dz + (p[:, 5] - own_vz_mps) * horizon_s
    dz_min = np.where(dz * dz_end <= 0.0, 0.0, np.minimum(np.abs(dz), np.abs(dz_end)))
    threat = horiz & (dz_min <= cfg.vertical_m)
    below = bool(np.any(threat & (dz < 0.0)))
    above = bool(np.any(threat & (dz >= 0.0)))
    if below and not above:
        return 1
    if above and not below:
        return -1
    return 0


class Avoider:
    """:func:`avoid_heading` with commitment, for one UAV (the state is its own last deviation).

    Two UAVs that each re-decide every step from the other's last velocity alternate: one
    deviates, so the other sees no conflict and turns back, and so on, into each other (the
    "reciprocal dance" of velocity obstacles; seen here at 0.6 m in a 143 deg crossing). Once a
    UAV deviates it keeps to its deviation (the nearest clear heading to it) until the desired
    heading clears ``radius_m + release_margin_m``.
    """

    def __init__(self, cfg: SeparationConfig) -> None:
        self.cfg = cfg
        self.heading_rad: float | None = None  # current deviation, None when not avoiding

    def step(
        self,
        own_xyz_m: tuple[float, float, float],
        speed_mps: float,
        desired_heading_rad: float,
        peers: np.ndarray,
        yield_to: np.ndarray | None = None,
        turn_rate_radps: float | None = None,
        heading_rad: float = 0.0,
        own_vz_mps: float = 0.0,
    ) -> tuple[float, bool, bool]:
        margin = 0.0 if self.heading_rad is None else self.cfg.release_margin_m
        head, changed, clear = avoid_heading(
            own_xyz_m, speed_mps, desired_heading_rad, peers, self.cfg, margin, self.heading_rad, yield_to,
            turn_rate_radps, heading_rad, own_vz_mps,
        )  # fmt: skip
        self.heading_rad = head if changed else None
        return head, changed, clear


class PeerAvoidance:
    """One agent's avoidance of its peers' predicted motion, every phase (the agent's last stage
    before the command goes out): the peers' motion from their last two states, and the
    :class:`Avoider` with its memory.

    ``uav_id``: this agent's (lower ids have the right of way); ``period_s``: the control period
    T [s]; ``v_stall_mps``, ``v_max_mps``, ``omega_max_radps``: the vehicle's limits (FF Eq. 5).
    """

    def __init__(
        self,
        uav_id: int,
        period_s: float,
        cfg: SeparationConfig,
        v_stall_mps: float,
        v_max_mps: float,
        omega_max_radps: float,
        turn_rate_at: Callable[[float], float] | None = None,
    ) -> None:
        self.uav_id, self.period_s, self.cfg = uav_id, period_s, cfg
        self.steps_resolved = 0  # control steps the vertical resolution changed v_z
        self._own_z: tuple[int, float, float] | None = None  # own last step, height, vertical speed
        self.turn_rate_at = turn_rate_at  # a fixed-wing's achievable turn rate [rad/s] at speed v [m/s]
        self.v_stall_mps, self.v_max_mps, self.omega_max_radps = v_stall_mps, v_max_mps, omega_max_radps
        self.avoider = Avoider(cfg)
        self.steps_changed = 0  # control steps the filter changed the heading
        # j -> step, x, y, z, vx, vy, vz: a peer's last state and the velocity from its last two
        self._motion: dict[int, tuple[int, float, float, float, float, float, float]] = {}

    def command(
        self,
        s: np.ndarray,
        cmd: tuple[float, float, float],
        target: tuple[float, float],
        peers: Mapping[int, PeerState],
        last_step: int,
        straight: bool = False,
        agl_m: float = math.inf,
        resolve_vertical: bool = True,
    ) -> tuple[float, float, float]:
        """``cmd`` (v [m/s], v_z [m/s], omega [rad/s]) with its heading replaced when a peer would
        come closer than ``radius_m`` within the horizon (turn at up to omega_max), and with
        ``cfg.vertical_resolution`` its v_z by :func:`vertical_sense` (``agl_m``: own height above
        the terrain [m]; ``resolve_vertical`` False: heading only, as on a landing's final).

        Peers' positions are their step k-1 estimates (time t_k), moved to t_{k+1} by the velocity
        of their last two states (``last_step``: the step this agent last ran). ``straight``: hold
        the current heading rather than turn to ``target``.
        """
        T = self.period_s
        own = self._own_z
        own_vz = 0.0
        if own is not None and last_step > own[0]:
            own_vz = (float(s[2]) - own[1]) / ((last_step - own[0]) * T)
        elif own is not None:
            own_vz = own[2]
        self._own_z = (last_step, float(s[2]), own_vz)
        rows = []
        right_of_way = []  # lower ids have the right of way (module doc)
        for j, p in sorted(peers.items()):
            if p.objective in (Objective.GROUNDED, Objective.LANDED):
                continue
            old = self._motion.get(j)
            vx = vy = pvz = 0.0
            if old is not None and p.step > old[0]:
                dt = (p.step - old[0]) * T
                vx, vy, pvz = (p.x_m - old[1]) / dt, (p.y_m - old[2]) / dt, (p.z_m - old[3]) / dt
                if math.hypot(vx, vy) > 1.5 * self.v_max_mps:  # a jump (rejoin, GPS reset): no velocity
                    vx = vy = pvz = 0.0
            elif old is not None:
                vx, vy, pvz = old[4], old[5], old[6]
            if old is None or p.step != old[0]:
                self._motion[j] = (p.step, p.x_m, p.y_m, p.z_m, vx, vy, pvz)
            lead = (last_step + 1 - p.step) * T  # from the peer's t to our t_{k+1}
            for row in peer_rows(
                (
                    p.x_m + vx * lead,
                    p.y_m + vy * lead,
                    p.z_m + (pvz * lead if self.cfg.vertical_rates else 0.0),
                    vx,
                    vy,
                ),
                (p.centroid_x_m, p.centroid_y_m),
                self.v_stall_mps,
                self.cfg,
                (float(s[0]), float(s[1])),
                j < self.uav_id,
            ):
                rows.append((*row, pvz))
                right_of_way.append(j < self.uav_id)
        if not rows:
            return cmd
        v, vz, om = cmd
        want = float(s[3]) if straight else math.atan2(target[1] - s[1], target[0] - s[0])
        speed = max(v, self.v_stall_mps)
        if self.cfg.vertical_resolution and resolve_vertical and self.turn_rate_at is not None:
            horizon = effective_horizon_s(self.cfg, self.turn_rate_at(speed))
            sense = vertical_sense(
                (float(s[0]), float(s[1]), float(s[2])), speed, float(s[3]), own_vz,
                np.array(rows), horizon, self.cfg,
            )  # fmt: skip
            new_vz = vz
            if sense > 0:
                new_vz = max(vz, 0.0)  # do not descend
            elif sense < 0 and agl_m > self.cfg.vertical_m:
                new_vz = min(vz, 0.0)  # do not climb
            if new_vz != vz:
                self.steps_resolved += 1
                vz = new_vz
                cmd = (v, vz, om)
        head, changed, clear = self.avoider.step(
            (float(s[0]), float(s[1]), float(s[2])),
            speed,
            want,
            np.array(rows),
            np.array(right_of_way, bool),
            None if self.turn_rate_at is None else self.turn_rate_at(speed),
            float(s[3]),
            vz,
        )
        if not changed:
            return cmd
        self.steps_changed += 1
        err = float(np.arctan2(math.sin(head - s[3]), math.cos(head - s[3])))
        om = max(-self.omega_max_radps, min(self.omega_max_radps, err / T))
        return (v if clear else self.v_stall_mps, vz, om)
