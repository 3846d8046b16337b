"""Cell importance and the back/front planning windows (PM Eqs. 1-8, Listing 3).

All functions are pure and vectorised over numpy arrays. Units: distances [m], times [s],
rates of spread [m/s], importance [m] (Eq. 4 is a spread distance: ROS times a time).

Perimeter-cell indexing follows PM IV-B (the convention of Eqs. 5-6): index 0 is the cell the
UAV occupies (the paper's i = 1) and the index grows *against* the flying direction, so
cells ``0 .. N-1`` form the back window and ``N .. 2N-1`` the front window, the last one being
the cell just in front of the UAV.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .errors import ConfigError, InputError

__all__ = [
    "WindowImportance",
    "adjust_heterogeneity",
    "cell_importance",
    "rate_of_spread",
    "should_turn",
    "time_since_visit",
    "time_to_cell",
    "window_importance",
    "worst_angle_turn",
    "WorstAngle",
]


def rate_of_spread(
    d_outer_m: np.ndarray, d_inner_m: np.ndarray, t_outer_s: np.ndarray, t_inner_s: np.ndarray
) -> np.ndarray:
    """ROS per angle [m/s] from the outer and inner cell (PM Eq. 1).

    ``(d_outer - d_inner) / (t_outer - t_inner)``. Deviation (the paper is silent): where
    ``t_outer <= t_inner`` or an input is NaN the result is NaN (unknown), and a negative
    value (the farthest perimeter cell at a later visit is nearer the centre: raster noise,
    a burned-out cell) is clipped to 0, since the burned area never shrinks.
    """
    d_o = np.asarray(d_outer_m, dtype=float)
    d_i = np.asarray(d_inner_m, dtype=float)
    dt = np.asarray(t_outer_s, dtype=float) - np.asarray(t_inner_s, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        ros = np.where(dt > 0, (d_o - d_i) / np.where(dt > 0, dt, 1.0), np.nan)
    return np.where(np.isnan(ros), np.nan, np.maximum(ros, 0.0))


def time_since_visit(t_now_s: float, t_outer_s: np.ndarray) -> np.ndarray:
    """Time since the outer cell was last visited [s] (PM Eq. 2): ``t_current - t_outer``."""
    return t_now_s - np.asarray(t_outer_s, dtype=float)


def time_to_cell(d_to_cell_m: np.ndarray, speed_mps: float) -> np.ndarray:
    """Time to reach a cell along the constructed perimeter [s] (PM Eq. 3): ``d_toCell / speed``."""
    if not speed_mps > 0:
        raise ConfigError(f"UAV speed must be > 0 m/s, got {speed_mps}")
    return np.asarray(d_to_cell_m, dtype=float) / speed_mps


def cell_importance(ros_mps: np.ndarray, t_since_visit_s: np.ndarray, t_to_cell_s: np.ndarray) -> np.ndarray:
    """Cell importance [m] (PM Eq. 4): ``ROS * t_sinceVisit + ROS * t_toCell``.

    It is the distance the fire spreads at the cell's angle between the last visit and the
    projected next one, so it grows linearly in both times and in ROS.
    """
    ros = np.asarray(ros_mps, dtype=float)
    return ros * np.asarray(t_since_visit_s, dtype=float) + ros * np.asarray(t_to_cell_s, dtype=float)


def adjust_heterogeneity(ros_mps: np.ndarray, alpha: float) -> np.ndarray:
    """Heterogeneity-adjusted ROS over the perimeter cells (PM Eq. 7).

    ``ROS`` is kept where ``ROS <= ROS_avg and alpha >= 1``; everywhere else it becomes
    ``ROS_min + alpha * (ROS - ROS_min)``, with min and mean over the given cells. ``alpha = 0``
    makes every cell ``ROS_min`` (no heterogeneity), ``alpha = 1`` is the identity.
    """
    if not alpha >= 0:
        raise ConfigError(f"heterogeneity factor alpha must be >= 0, got {alpha}")
    ros = np.asarray(ros_mps, dtype=float)
    if ros.size == 0:
        return ros.copy()
    r_min = float(np.min(ros))
    r_avg = float(np.mean(ros))
    adjusted = r_min + alpha * (ros - r_min)
    if alpha >= 1.0:
        return np.where(ros <= r_avg, ros, adjusted)
    return adjusted


class WindowImportance(NamedTuple):
    """Result of :func:`window_importance`; cell arrays are in the Eq. 5-6 index order."""

    imp_back: float  # [m] Eq. 5
    imp_front: float  # [m] Eq. 6
    importance: np.ndarray  # [m] per cell, Eq. 4 with the adjusted ROS
    ros_adjusted: np.ndarray  # [m/s] per cell, Eq. 7
    t_to_cell_s: np.ndarray  # [s] per cell, Eq. 3
    n_back: int  # [-] cells in the back window (N)


def window_importance(
    ros_mps: np.ndarray,
    t_since_visit_s: np.ndarray,
    spacing_m: float,
    speed_mps: float,
    alpha: float = 1.0,
    weight: np.ndarray | None = None,
) -> WindowImportance:
    """Importance of the back and front planning windows (PM Eqs. 3-7, Listing 3).

    ``ros_mps`` and ``t_since_visit_s`` are per perimeter cell, index 0 the UAV's cell and
    growing against the flying direction; consecutive cells are ``spacing_m`` apart along the
    constructed perimeter. With ``2N`` cells the back window is cells ``0..N-1`` and the
    front window ``N..2N-1`` (Eqs. 5-6). ``d_toCell`` (Eq. 3) is the distance along the
    perimeter in the direction that reaches the cell without passing the other window: a
    back cell ``i`` is reached by turning back (``i * spacing``), a front cell by flying on
    (``(2N - i) * spacing``); this is what the paper's Appendix A assumes.

    Deviation: with an odd cell count the back window gets ``floor(M / 2)`` cells.
    ``weight`` (per cell, default 1) scales the importance after Eq. 7; a monitor uses 0 for
    cells a peer monitor is responsible for (not in the single-UAV paper).
    """
    ros = np.asarray(ros_mps, dtype=float)
    since = np.asarray(t_since_visit_s, dtype=float)
    if ros.shape != since.shape or ros.ndim != 1:
        raise InputError(f"ros and t_since must be equal 1-D arrays, got {ros.shape} and {since.shape}")
    m = ros.size
    n = m // 2
    idx = np.arange(m, dtype=float)
    d_to = np.where(idx < n, idx, m - idx) * spacing_m
    t_to = time_to_cell(d_to, speed_mps)
    ros_adj = adjust_heterogeneity(ros, alpha)
    imp = cell_importance(ros_adj, since, t_to)
    if weight is not None:
        imp = imp * np.asarray(weight, dtype=float)
    return WindowImportance(float(np.sum(imp[:n])), float(np.sum(imp[n:])), imp, ros_adj, t_to, n)


def should_turn(
    imp_back: float, imp_front: float, *, turn_on_tie: bool = False, tie_rel_tol: float = 1e-9
) -> bool:
    """Direction decision (PM Listing 3): turn back iff ``IMP_BACK > IMP_FRONT``.

    ``IMP_DIFF = IMP_FRONT - IMP_BACK`` (Eq. 8). Values within ``tie_rel_tol`` of each other
    (relative to the larger) are a tie. The paper is inconsistent at a tie: Listing 3 keeps
    the direction (strict ``>``, our default), while V-A says the UAV turns at location 4 for
    ``a >= 5``, where ``IMP_DIFF`` is exactly 0 at ``a = 5``; ``turn_on_tie=True`` gives the V-A
    reading. Keeping on ties also stops a UAV with all-zero importance from turning every step.
    """
    diff = imp_front - imp_back
    scale = max(abs(imp_front), abs(imp_back))
    if scale == 0.0:
        return False  # nothing known about either window: keep flying
    if abs(diff) <= tie_rel_tol * scale:
        return turn_on_tie
    return diff < 0


class WorstAngle(NamedTuple):
    """Result of :func:`worst_angle_turn`; cell arrays are in the Eq. 5-6 index order."""

    worst_on_m: float  # [m] largest predicted spread at a cell's next visit, flying on
    worst_back_m: float  # [m] the same after turning back
    on_m: np.ndarray  # [m] per cell, flying on
    back_m: np.ndarray  # [m] per cell, turning back
    ros_adjusted: np.ndarray  # [m/s] per cell, Eq. 7


def worst_angle_turn(
    ros_mps: np.ndarray,
    t_since_visit_s: np.ndarray,
    spacing_m: float,
    speed_mps: float,
    alpha: float = 1.0,
    weight: np.ndarray | None = None,
    reach_m: float = 0.0,
    keep_in_view: bool = True,
) -> WorstAngle:
    """Turning rule aimed at the worst angle (ours; replaces the window sums of Eqs. 5-6).

    Eq. 4 is the distance the fire spreads at a cell's angle between its last visit and the
    next one: the error the on-board map will have there when the UAV comes back. The
    distance error PM VI-E scores is the *maximum* of that error over the angles, while Eqs.
    5-6 *sum* it over half-perimeter windows, so a window with one badly stale cell can lose
    against a window of many slightly stale ones. Here each direction is scored by its worst
    cell: flying on reaches cell ``i`` (index as in :func:`window_importance`, growing against
    the flying direction) after ``(M - i) * spacing``, turning back after ``i * spacing``, each
    less ``reach_m`` (the sensor footprint refreshes a cell before the UAV is over it). A cell
    the UAV moves away from stays in the footprint while it is within ``reach_m`` behind, so
    its clock starts only when it leaves: that remaining time is taken off too (clipped at 0),
    so both directions are scored by the same uncovered gap (flying on, a cell just behind
    waits ``(M * spacing - 2 reach_m) / speed``, a lap less the footprint on both sides, not a
    lap less one reach). That gap assumes the UAV flying on comes round again; a monitor
    sharing the fire with a peer turns at its arc's end instead, and there
    ``keep_in_view=False`` counts the footprint ahead only (two monitors on monitor_grass, 10
    seeds: 12.0 m, against 12.8 m with the gap).
    With that

        on_i = ROS_adj_i * (t_sinceVisit_i + t_on_i),  back_i = ROS_adj_i * (t_sinceVisit_i + t_back_i)

    (Eq. 4 with Eq. 7's ROS). The UAV turns when ``max(back) < max(on)``. ``alpha`` keeps the
    paper's role: 0 makes every cell's ROS alike, and then a UAV that has been circling never
    turns (flying on, every cell waits one lap; turning, the cells ahead wait up to two: PM
    VI-D, circling is best for uniform spread); it turns only for a cell left staler than
    circling would leave it. Larger values weigh the fast cells more. Unlike the windows, the
    rule counts a cell's whole time to the next visit in either direction, so a stale cell
    just behind the UAV pulls it back, and a fast cell far ahead is not outvoted by many slow
    ones. ``weight`` (per cell) scales the values as in :func:`window_importance` (0: a
    peer's cells).
    """
    ros = np.asarray(ros_mps, dtype=float)
    since = np.asarray(t_since_visit_s, dtype=float)
    if ros.shape != since.shape or ros.ndim != 1:
        raise InputError(f"ros and t_since must be equal 1-D arrays, got {ros.shape} and {since.shape}")
    if not reach_m >= 0:
        raise ConfigError(f"reach_m must be >= 0, got {reach_m}")
    m = ros.size
    idx = np.arange(m, dtype=float)
    # time to the next refresh less the time the footprint still keeps the cell in view as the
    # UAV moves away from it (it is refreshed until then: its clock starts when it leaves)
    d_on, d_back = (m - idx) * spacing_m, idx * spacing_m
    keep = reach_m if keep_in_view else 0.0
    t_on = time_to_cell(np.maximum(np.maximum(d_on - reach_m, 0.0) - np.maximum(keep - d_back, 0.0), 0.0),
                        speed_mps)  # fmt: skip
    t_back = time_to_cell(np.maximum(np.maximum(d_back - reach_m, 0.0) - np.maximum(keep - d_on, 0.0), 0.0),
                          speed_mps)  # fmt: skip
    ros_adj = adjust_heterogeneity(ros, alpha)
    on = cell_importance(ros_adj, since, t_on)
    back = cell_importance(ros_adj, since, t_back)
    if weight is not None:
        w = np.asarray(weight, dtype=float)
        on, back = on * w, back * w
    if m == 0:
        return WorstAngle(0.0, 0.0, on, back, ros_adj)
    return WorstAngle(float(np.max(on)), float(np.max(back)), on, back, ros_adj)
