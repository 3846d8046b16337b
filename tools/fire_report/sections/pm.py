"""PM section: the monitor's perimeter track (PM Fig. 9), the distance error over time
(PM Figs. 15-16) and the direction changes (PM Fig. 11 counts them).

Distance error (PM Sec. VI-E): ``fire_perimeter_monitor.distance_error``, the one definition
the benchmark (scripts/bench_perimeter.py) and metrics.json use too. At 360 angles around the
monitor's map centre, |extent of the true fire - extent of the convex hull of the monitor's
on-board perimeter cells|; the maximum over the angles and its running average, in metres
and cells, with the perfect-map floor beside it (the same metric for a map holding the whole
current fire: what the hull alone costs on a fire with notches, e.g. cut by drops). Choices
where the paper is vague (ours, shared with the benchmark):

- the true shape is the union of the burning or burnt raster cells of ``/viz/fire_grid`` (the
  world's truth at the viz rate), its extent along a ray computed exactly; the constructed
  shape is the hull of cell-sized squares at the PerimeterMap's bin points
  ``centre + d_i (cos a_i, sin a_i)`` (``a_i`` the bin centre angle, as perimeter_viewer draws it);
- the error is sampled at every grid snapshot, against each monitor's latest map at or before it
  (not each new cell: the bag holds the truth only at the viz rate);
- without a raster (analytic fire) the true shape is the circle of the fire's equivalent radius
  sqrt(area / pi) from ``/world/truth`` (convex: floor 0), and the section says so.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import fire_perimeter_monitor.distance_error as de
import matplotlib.pyplot as plt
import numpy as np
from fire_uav_common.constants import Objective, PerimeterDirection
from matplotlib.colors import ListedColormap

from fire_report.data import RecordedMission
from fire_report.sections import Section
from fire_report.sections.bagdata import PerimeterSample, SectionData

N_ANGLES = 360
DPI = 110
MATCH_WINDOW_S = 2.0  # a map older than this at a grid snapshot is not compared [s]


# --- geometry (pure numpy) ---------------------------------------------------------------------
def angles_rad(n: int = N_ANGLES) -> np.ndarray:
    """The ``n`` compared directions, counter-clockwise from +x [rad]."""
    return np.arange(n) * 2 * math.pi / n


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise convex hull of (n, 2) points (Andrew's monotone chain); (k, 2)."""
    pts = np.unique(np.asarray(points, dtype=float).reshape(-1, 2), axis=0)
    if len(pts) < 3:
        return pts

    def cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
        return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))

    lower: list[np.ndarray] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[np.ndarray] = []
    for p in pts[::-1]:
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.asarray(lower[:-1] + upper[:-1])


def ray_extent_polygon(poly: np.ndarray, center: tuple[float, float], ang: np.ndarray) -> np.ndarray:
    """Distance from ``center`` along each direction ``ang`` [rad] to the boundary of the convex
    polygon ``poly`` (k, 2) [m]; NaN where the centre is outside it or it has < 3 vertices."""
    out = np.full(ang.shape, np.nan)
    if len(poly) < 3:
        return out
    c = np.asarray(center, dtype=float)
    a, b = poly - c, np.roll(poly, -1, axis=0) - c
    cr = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    if np.any(cr < -1e-9):  # the centre is outside (a CCW hull has every edge to its left)
        return out
    d = np.stack([np.cos(ang), np.sin(ang)], -1)  # (m, 2)
    e = b - a  # (k, 2)
    # centre + t d = a + u e:  t (d x e) = a x e,  u (d x e) = a x d
    den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]  # (m, k)
    axe = a[:, 0] * e[:, 1] - a[:, 1] * e[:, 0]
    axd = a[None, :, 0] * d[:, None, 1] - a[None, :, 1] * d[:, None, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = axe[None, :] / den
        u = axd / den
    ok = (np.abs(den) > 1e-12) & (u >= -1e-9) & (u <= 1 + 1e-9) & (t >= 0)
    t = np.where(ok, t, np.nan)
    with np.errstate(all="ignore"):
        res = np.nanmax(t, axis=1) if t.size else out
    return np.where(np.isfinite(res), res, np.nan)


def constructed_extent(p: PerimeterSample, ang: np.ndarray) -> np.ndarray:
    """Radial extent [m] of the convex hull of ``p``'s known perimeter bins, per direction."""
    n = p.outer_m.size
    known = np.isfinite(p.outer_m)
    if n == 0 or np.count_nonzero(known) < 3:
        return np.full(ang.shape, np.nan)
    a = (np.arange(n)[known] + 0.5) * 2 * math.pi / n
    pts = np.asarray(p.center_xy_m) + p.outer_m[known][:, None] * np.stack([np.cos(a), np.sin(a)], -1)
    return ray_extent_polygon(convex_hull(pts), p.center_xy_m, ang)


def distance_error_series(
    data: SectionData, mission: RecordedMission
) -> dict[tuple[int, int], dict[str, np.ndarray]]:
    """(uav, fire) -> t [s], max_m, floor_m (perfect map), mean_m (over the 360 angles),
    avg_max_m, avg_floor_m (running means), and cell_m (the raster's cell, 0 without one).

    Truth from the raster snapshots when recorded, else the equivalent circle (see module doc)."""
    by_key: dict[tuple[int, int], list[PerimeterSample]] = {}
    for p in data.perimeter:
        by_key.setdefault((p.uav_id, p.fire_id), []).append(p)
    out = {}
    cell = data.grids[0].res_m if data.grids else 0.0
    for key, maps in sorted(by_key.items()):
        t_maps = np.asarray([p.t_s for p in maps])
        rows = []
        instants: list[tuple[float, Any]]
        if data.grids:
            instants = [(g.t_s, g) for g in data.grids]
        else:
            instants = [(float(t), None) for t in t_maps]
        for t, g in instants:
            k = int(np.searchsorted(t_maps, t + 1e-9, side="right")) - 1
            if k < 0 or t - t_maps[k] > MATCH_WINDOW_S:
                continue
            p = maps[k]
            pts = de.bin_points(p.center_xy_m, p.outer_m)
            if g is not None:
                fire = de.grid_cells(g.fire_mask(), g.x0_m, g.y0_m, g.res_m)
                truth = de.true_extent(fire, g.res_m, p.center_xy_m)
                est = de.hull_extent(pts, g.res_m, p.center_xy_m)
                perfect = de.hull_extent(
                    de.perfect_map_cells(fire, g.res_m, p.center_xy_m), g.res_m, p.center_xy_m
                )
                floor = de.max_error(truth, perfect)
            else:
                tru = mission.truth_fires.get(p.fire_id)
                if not tru:
                    continue
                i = int(np.clip(np.searchsorted(tru["t"], t), 0, tru["t"].size - 1))
                truth = np.full(de.N_ANGLES, math.sqrt(max(float(tru["area"][i]), 0.0) / math.pi))
                est = de.hull_extent(pts, 1e-6, p.center_xy_m)  # points: no raster cell
                floor = 0.0
            worst = de.max_error(truth, est)
            if not math.isfinite(worst) or pts.shape[0] < 3:
                continue
            err = np.abs(truth - np.where(np.isfinite(est), est, 0.0))
            rows.append((t, worst, floor, float(np.nanmean(err))))
        if rows:
            a = np.asarray(rows)
            out[key] = {"t": a[:, 0], "max_m": a[:, 1], "floor_m": a[:, 2], "mean_m": a[:, 3],
                        "avg_max_m": de.running_average(a[:, 1]), "avg_floor_m": de.running_average(a[:, 2]),
                        "cell_m": np.asarray(cell)}  # fmt: skip
    return out


def track_direction_changes(xy: np.ndarray, center: tuple[float, float], min_arc_rad: float = 0.35) -> int:
    """Reversals of the sense of travel around ``center`` seen in a flown track (independent of
    the monitor's own count): the unwrapped bearing's turning points that are at least
    ``min_arc_rad`` from the previous turning point (hysteresis against jitter)."""
    if len(xy) < 3:
        return 0
    th = np.unwrap(np.arctan2(xy[:, 1] - center[1], xy[:, 0] - center[0]))
    changes, sense, ref = 0, 0, th[0]
    for v in th[1:]:
        d = v - ref
        if sense >= 0 and d <= -min_arc_rad or sense <= 0 and d >= min_arc_rad:
            changes += sense != 0
            sense = 1 if d > 0 else -1
            ref = v
        elif (sense > 0 and v > ref) or (sense < 0 and v < ref):
            ref = v  # the extreme of the current sweep
    return int(changes)


# --- the section ---------------------------------------------------------------------------------
def _monitor_track(mission: RecordedMission, uav: int) -> dict[str, np.ndarray] | None:
    """True positions of ``uav`` while its state said MONITOR (matched by control step)."""
    s, v = mission.states.get(uav), mission.truth_vehicles.get(uav)
    if not s or not v:
        return None
    mon = s["step"][s["objective"] == Objective.MONITOR]
    keep = np.isin(v["step"], mon)
    if not keep.any():
        return None
    return {"t": v["t"][keep], "x": v["x"][keep], "y": v["y"][keep]}


def build(mission: RecordedMission, data: SectionData, out: Path) -> Section | None:
    if not data.perimeter:
        return None
    sec = Section("pm", "Perimeter monitoring (PM)")
    series = distance_error_series(data, mission)
    monitors = sorted({(p.uav_id, p.fire_id) for p in data.perimeter})
    last = {k: [p for p in data.perimeter if (p.uav_id, p.fire_id) == k][-1] for k in monitors}
    truth_kind = (
        "raster cells of /viz/fire_grid" if data.grids else "equivalent circle sqrt(A/pi) (no raster)"
    )
    sec.rows.append(("monitors (uav/fire)", ", ".join(f"{u}/{f}" for u, f in monitors)))
    sec.rows.append(("perimeter maps recorded", str(len(data.perimeter))))
    sec.rows.append(("true shape", truth_kind))
    metrics: dict = {"monitors": {}}
    for u, f in monitors:
        m: dict = {"maps": sum(1 for p in data.perimeter if (p.uav_id, p.fire_id) == (u, f))}
        m["direction_changes_reported"] = int(last[(u, f)].direction_changes)
        trk = _monitor_track(mission, u)
        if trk is not None:
            m["direction_changes_in_track"] = track_direction_changes(
                np.stack([trk["x"], trk["y"]], -1), last[(u, f)].center_xy_m
            )
        e = series.get((u, f))
        if e is not None:
            m["distance_error_samples"] = int(e["t"].size)
            m["max_distance_error_final_m"] = float(e["max_m"][-1])
            m["average_max_distance_error_m"] = float(e["avg_max_m"][-1])
            m["average_max_distance_error_floor_m"] = float(e["avg_floor_m"][-1])
            m["mean_distance_error_m"] = float(np.mean(e["mean_m"]))
            if float(e["cell_m"]) > 0:
                m["average_max_distance_error_cells"] = m["average_max_distance_error_m"] / float(e["cell_m"])
        metrics["monitors"][f"{u}/{f}"] = m
        sec.rows.append((f"UAV {u} / fire {f}: average max distance error [m] (perfect-map floor)",
                         f"{m['average_max_distance_error_m']:.1f} ({m['average_max_distance_error_floor_m']:.1f})"
                         + (f" = {m['average_max_distance_error_cells']:.2f} cells"
                            if "average_max_distance_error_cells" in m else "")
                         if e is not None else "-"))  # fmt: skip
        sec.rows.append((f"UAV {u} / fire {f}: direction changes (reported / seen in track)",
                         f"{m['direction_changes_reported']} / {m.get('direction_changes_in_track', '-')}"))  # fmt: skip
    metrics["true_shape"] = truth_kind
    sec.metrics = metrics
    sec.notes.append(
        "Distance error as PM Sec. VI-E: |true radial extent - extent of the convex hull of the monitor's "
        "perimeter cells| at 360 angles around its map centre, maximum over the angles, sampled at each "
        "recorded truth snapshot; the floor is the same metric for a perfect, instantaneous map. PM reports "
        "7.3 and 12.2 average maximum error (Fig. 16a, 16b; unit not stated, most likely cells) for "
        "its DEVS-FIRE cases, against 8.5 and 15.8 for circling."
    )
    sec.figures += _fig_track(mission, data, monitors, last, out)
    sec.figures += _fig_error(series, out, truth_kind)
    sec.figures += _fig_direction(data, monitors, out)
    return sec


def _save(fig: plt.Figure, out: Path, name: str, caption: str) -> list[tuple[str, str]]:
    fig.tight_layout()
    fig.savefig(out / name, dpi=DPI)
    plt.close(fig)
    return [(name, caption)]


def _fig_track(mission, data, monitors, last, out) -> list[tuple[str, str]]:
    fig, ax = plt.subplots(figsize=(7.5, 6.5))
    if data.grids:
        g = data.grids[-1]
        ny, nx = g.occ.shape
        img = np.zeros(g.occ.shape)
        img[g.occ == 60], img[g.occ == 100], img[g.occ == 20] = 1, 2, 3
        ax.imshow(img, origin="lower", extent=(g.x0_m, g.x0_m + nx * g.res_m, g.y0_m, g.y0_m + ny * g.res_m),
                  cmap=ListedColormap(["#e8f0e0", "#333333", "#e03020", "#3070d0"]), vmin=0, vmax=3,
                  interpolation="nearest")  # fmt: skip
    sc = None
    for u, f in monitors:
        trk = _monitor_track(mission, u)
        if trk is not None:
            sc = ax.scatter(trk["x"], trk["y"], c=trk["t"], s=3, cmap="viridis", label=f"UAV {u} track")
        p = last[(u, f)]
        ext = constructed_extent(p, angles_rad())
        a = angles_rad()
        ok = np.isfinite(ext)
        if ok.any():
            ax.plot(p.center_xy_m[0] + ext[ok] * np.cos(a[ok]), p.center_xy_m[1] + ext[ok] * np.sin(a[ok]),
                    "-", color="orange", lw=1.5, label=f"UAV {u}: constructed shape (hull), t = {p.t_s:.0f} s")  # fmt: skip
        ax.plot(*p.center_xy_m, "k+", markersize=10)
    if sc is not None:
        fig.colorbar(sc, ax=ax, label="sim time [s]")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title("monitor track over the fire (last truth snapshot)")
    return _save(fig, out, "pm_track.png",
                 "Perimeter track of each monitor (true positions while monitoring, coloured by time) over the "
                 "last raster snapshot (grey burnt, red burning, blue wet) and the shape constructed from its "
                 "last map (PM Fig. 9).")  # fmt: skip


def _fig_error(series, out, truth_kind) -> list[tuple[str, str]]:
    if not series:
        return []
    fig, ax = plt.subplots(figsize=(9, 4))
    for (u, f), e in series.items():
        ln = ax.plot(e["t"], e["max_m"], lw=0.8, alpha=0.6, label=f"UAV {u} / fire {f}: max over angles")
        ax.plot(
            e["t"],
            e["avg_max_m"],
            lw=1.8,
            color=ln[0].get_color(),
            label=f"UAV {u} / fire {f}: running average",
        )
        ax.plot(e["t"], e["avg_floor_m"], lw=1.0, ls="--", color=ln[0].get_color(),
                label=f"UAV {u} / fire {f}: perfect-map floor (running average)")  # fmt: skip
    ax.set_xlabel("sim time [s]")
    ax.set_ylabel("distance error [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(f"maximum distance error (truth: {truth_kind})")
    return _save(fig, out, "pm_distance_error.png",
                 "Maximum distance error between the true and the constructed fire shape over time, and its "
                 "running average (PM Figs. 15-16).")  # fmt: skip


def _fig_direction(data, monitors, out) -> list[tuple[str, str]]:
    fig, axes = plt.subplots(2, 1, figsize=(9, 4.5), sharex=True)
    for u, f in monitors:
        ps = [p for p in data.perimeter if (p.uav_id, p.fire_id) == (u, f)]
        t = [p.t_s for p in ps]
        axes[0].step(t, [1 if p.direction == PerimeterDirection.CCW else -1 for p in ps], where="post",
                     label=f"UAV {u} / fire {f}")  # fmt: skip
        axes[1].step(t, [p.direction_changes for p in ps], where="post")
    axes[0].set_yticks([-1, 1], ["CW", "CCW"])
    axes[0].set_ylabel("direction")
    axes[0].legend(fontsize=7)
    axes[1].set_ylabel("direction changes")
    axes[1].set_xlabel("sim time [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
    return _save(fig, out, "pm_direction.png",
                 "Each monitor's direction of travel along the perimeter and its count of direction changes "
                 "(PerimeterMap.direction, direction_changes; PM Fig. 11 compares these counts).")  # fmt: skip
