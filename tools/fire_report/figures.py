"""The papers' figures as PNG (matplotlib, Agg backend). Each function returns [(file, caption)].

A figure whose data is not in the bag is skipped (returns []), never an error.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from fire_uav_common.constants import EventType, Objective
from matplotlib.colors import ListedColormap
from matplotlib.ticker import MaxNLocator

from fire_report.data import (
    RecordedMission,
)
from fire_report.ground import Ground, draw_ground, fuel_legend_handles
from fire_report.matching import match_tracks_to_fires
from fire_report.metrics import (
    baseline_area,
    burned_area_series,
    ekf_errors,
    perimeter_distance_error,
    perimeter_distance_error_raster,
    voronoi_labels,
)

Figure = tuple[str, str]
DPI = 110


def _save(fig: plt.Figure, out: Path, name: str, caption: str) -> list[Figure]:
    fig.tight_layout()
    fig.savefig(out / name, dpi=DPI)
    plt.close(fig)
    return [(name, caption)]


def _colors(n: int) -> list:
    cmap = plt.get_cmap("tab20" if n > 10 else "tab10")
    return [cmap(i % cmap.N) for i in range(max(n, 1))]


def _area(mission: RecordedMission) -> tuple[tuple[float, float], tuple[float, float]]:
    a = mission.scenario.get("area") if isinstance(mission.scenario, dict) else None
    if isinstance(a, dict) and all(k in a for k in ("x_min_m", "x_max_m", "y_min_m", "y_max_m")):
        return (float(a["x_min_m"]), float(a["x_max_m"])), (float(a["y_min_m"]), float(a["y_max_m"]))
    xs = [s["x"] for s in mission.states.values() if s] + [f["x"] for f in mission.truth_fires.values() if f]
    ys = [s["y"] for s in mission.states.values() if s] + [f["y"] for f in mission.truth_fires.values() if f]
    if not xs:
        return (0.0, 1.0), (0.0, 1.0)
    x, y = np.concatenate(xs), np.concatenate(ys)
    pad = 0.05 * max(np.ptp(x), np.ptp(y), 10.0)
    return (float(x.min() - pad), float(x.max() + pad)), (float(y.min() - pad), float(y.max() + pad))


def _positions_at(mission: RecordedMission, t: float) -> dict[int, tuple[float, float]]:
    """Latest estimated (x, y) of each UAV at or before ``t`` (first state if none before);
    a UAV whose vehicle crashed before ``t`` is left out (the fleet no longer partitions with it)."""
    crashed = {e.uav_id for e in mission.world_events if e.type == EventType.CRASH and e.t_s <= t}
    out = {}
    for uav, s in mission.states.items():
        if s and uav not in crashed:
            i = max(0, int(np.searchsorted(s["t"], t, side="right")) - 1)
            out[uav] = (float(s["x"][i]), float(s["y"][i]))
    return out


def phase_times(mission: RecordedMission) -> list[tuple[str, float]]:
    """Takeoff, firefighting and landing instants for the map panels (FF Fig. 11), in time order.

    takeoff: when the last UAV left the ground; firefighting: the median drop after that (else
    halfway to landing); landing: when the last UAV began to land (else the last state). A UAV
    may drop before the last one is up, so the firefighting instant is taken after takeoff."""
    all_t = np.concatenate([s["t"] for s in mission.states.values() if s]) if mission.states else np.zeros(0)
    if all_t.size == 0:
        return []
    t0, t1 = float(all_t.min()), float(all_t.max())
    airborne = [
        float(s["t"][np.argmax(s["objective"] != Objective.GROUNDED)])
        for s in mission.states.values()
        if s and np.any(s["objective"] != Objective.GROUNDED)
    ]
    t_take = max(airborne) if airborne else t0
    landing = [
        float(s["t"][np.argmax(np.isin(s["objective"], (Objective.LAND, Objective.LANDED)))])
        for s in mission.states.values()
        if s and np.any(np.isin(s["objective"], (Objective.LAND, Objective.LANDED)))
    ]
    t_land = max(max(landing) if landing else t1, t_take)
    drops = [e.t_s for e in mission.world_events if e.type == EventType.DROP and t_take <= e.t_s <= t_land]
    t_fight = float(np.median(drops)) if drops else 0.5 * (t_take + t_land)
    return sorted([("takeoff", t_take), ("firefighting", t_fight), ("landing", t_land)], key=lambda p: p[1])


def _draw_crashes(ax: plt.Axes, mission: RecordedMission, t: float) -> None:
    """A crashed UAV stays on the map: a black cross where its vehicle fell, labelled."""
    for e in mission.world_events:
        if e.type != EventType.CRASH or e.t_s > t:
            continue
        x, y = e.x_m, e.y_m
        v = mission.truth_vehicles.get(e.uav_id)
        if not (np.isfinite(x) and np.isfinite(y)) and v:
            i = max(0, int(np.searchsorted(v["t"], e.t_s, side="right")) - 1)
            x, y = float(v["x"][i]), float(v["y"][i])
        if np.isfinite(x) and np.isfinite(y):
            ax.plot(x, y, "X", color="k", markersize=10, markeredgecolor="w", zorder=5)
            ax.annotate(
                f"UAV {e.uav_id} lost", (x, y), fontsize=7, xytext=(5, -10), textcoords="offset points"
            )


def _draw_world(ax: plt.Axes, mission: RecordedMission, t: float) -> None:
    for lake in (mission.scenario.get("lakes") or []) if isinstance(mission.scenario, dict) else []:
        try:
            r = float(lake.get("diameter_m", 0.0)) / 2
            ax.add_patch(plt.Circle((float(lake["x_m"]), float(lake["y_m"])), r, color="tab:blue", alpha=0.5))
        except (KeyError, TypeError, ValueError):
            continue
    for fid, f in mission.truth_fires.items():
        if not f:
            continue
        i = max(0, int(np.searchsorted(f["t"], t, side="right")) - 1)
        if f["status"][i] == 0:
            ax.add_patch(
                plt.Circle((f["x"][i], f["y"][i]), max(f["extent"][i], 1.0), color="tab:red", alpha=0.35)
            )
            ax.plot(f["x"][i], f["y"][i], "x", color="darkred")
            ax.annotate(f"F{fid}", (f["x"][i], f["y"][i]), fontsize=7)


def fig_voronoi(mission: RecordedMission, out: Path, ground: Ground | None = None) -> list[Figure]:
    phases = phase_times(mission)
    if not phases:
        return []
    (x0, x1), (y0, y1) = _area(mission)
    res = max((x1 - x0) / 200.0, (y1 - y0) / 200.0, 1.0)
    ids = sorted(mission.states)
    colors = _colors(len(ids))
    fig, axes = plt.subplots(1, len(phases), figsize=(3.6 * len(phases), 3.9))
    for ax, (name, t) in zip(np.atleast_1d(axes), phases, strict=False):
        pos = _positions_at(mission, t)
        sites = np.asarray([pos[u] for u in ids if u in pos])
        xs, ys, lab = voronoi_labels(sites, (x0, x1), (y0, y1), res)
        if ground is not None:  # the cells' borders only: a tint would muddy the fuel colours
            draw_ground(ax, ground)
            if len(sites) > 1:
                ax.contour(xs, ys, lab, levels=np.arange(len(sites) - 1) + 0.5, colors="w", linewidths=0.8)
        else:
            ax.imshow(
                lab,
                origin="lower",
                extent=(x0, x1, y0, y1),
                cmap=ListedColormap(colors),
                alpha=0.25,
                interpolation="nearest",
                vmin=0,
                vmax=max(len(ids) - 1, 1),
            )
        _draw_world(ax, mission, t)
        _draw_crashes(ax, mission, t)
        for k, u in enumerate(ids):
            if u in pos:
                ax.plot(*pos[u], "^", color=colors[k], markeredgecolor="k", markersize=8)
                ax.annotate(str(u), pos[u], fontsize=7, xytext=(3, 3), textcoords="offset points")
        ax.set_title(f"{name}, t = {t:.1f} s", fontsize=10)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
    return _save(
        fig,
        out,
        "voronoi_phases.png",
        "The fleet at takeoff, while fighting the fires and at landing: each UAV (triangle, its own "
        "position estimate) and the area it covers (the part of the map nearest to it); red: the fires, "
        "blue: lakes, black cross: a UAV lost (as in FF Fig. 11)."
        + (
            " On a landscape the white lines bound the areas, over the ground's fuel types." if ground else ""
        ),
    )


def fig_ekf(mission: RecordedMission, out: Path) -> list[Figure]:
    errs = {u: ekf_errors(mission, u) for u in mission.uav_ids}
    errs = {u: e for u, e in errs.items() if e["t"].size}
    res: list[Figure] = []
    if errs:
        fig, axes = plt.subplots(4, 1, figsize=(9, 7.5), sharex=True)
        colors = _colors(len(errs))
        for k, (u, e) in enumerate(sorted(errs.items())):
            for ax, axis in zip(axes, ("x", "y", "z", "yaw"), strict=False):
                ax.plot(e["t"], e[axis], lw=0.7, color=colors[k], label=f"UAV {u}")
        for ax, lab in zip(
            axes, ("x error [m]", "y error [m]", "z error [m]", "yaw error [rad]"), strict=False
        ):
            ax.set_ylabel(lab)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7, ncol=min(len(errs), 7))
        axes[-1].set_xlabel("sim time [s]")
        res += _save(
            fig,
            out,
            "ekf_error.png",
            "Each UAV's own position estimate minus the truth, per axis, while it flew: small errors "
            "centred on zero mean the filter follows the vehicle (FF Fig. 4).",
        )
    traces = {u: (s["t"], np.trace(s["P"], axis1=1, axis2=2)) for u, s in mission.states.items() if s}
    if traces:
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
        colors = _colors(len(traces))
        t_end = min(float(t[0]) for t, _ in traces.values()) + 5.0
        for k, (u, (t, tr)) in enumerate(sorted(traces.items())):
            axes[0].plot(t, tr, lw=0.8, color=colors[k], label=f"UAV {u}")
            m = t <= t_end
            axes[1].plot(t[m], tr[m], ".-", lw=0.8, color=colors[k])
        axes[0].set_yscale("log")
        axes[0].set_title("whole mission", fontsize=10)
        axes[1].set_title("first 5 s, one point per control step", fontsize=10)
        for ax in axes:
            ax.set_xlabel("sim time [s]")
            ax.set_ylabel("filter uncertainty [m² + rad²]")
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7, ncol=2)
        res += _save(
            fig,
            out,
            "covariance_trace.png",
            "The uncertainty each UAV's filter reports about its own position and heading (the trace of "
            "its covariance, shared with its peers): it should fall within seconds of the start and stay "
            "low (FF Figs. 6, 7).",
        )
    return res


def fig_tracks(mission: RecordedMission, out: Path, ground: Ground | None = None) -> list[Figure]:
    ids = [u for u in mission.uav_ids if u in mission.states and u in mission.truth_vehicles]
    if not ids:
        return []
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    colors = _colors(len(ids))
    if ground is not None:  # the fleet over its ground, in the scenario's area
        draw_ground(axes[0], ground)
        (x0, x1), (y0, y1) = _area(mission)
        axes[0].set_xlim(x0, x1)
        axes[0].set_ylim(y0, y1)
    for k, u in enumerate(ids):
        s, v = mission.states[u], mission.truth_vehicles[u]
        axes[0].plot(v["x"], v["y"], "-", color=colors[k], lw=1.0)
        axes[0].plot(s["x"], s["y"], "--", color=colors[k], lw=0.7)
    u = ids[0]
    s, v = mission.states[u], mission.truth_vehicles[u]
    axes[1].plot(v["x"], v["y"], "k-", lw=1.2, label="true")
    axes[1].plot(s["x"], s["y"], "r--", lw=1.0, label="estimated")
    axes[1].set_title(f"UAV {u}")
    axes[1].legend()
    axes[0].set_title("all UAVs: true (solid) vs estimated (dashed)")
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.grid(alpha=0.3)
    return _save(
        fig, out, "tracks.png",
        "True (solid) and estimated (dashed) flight paths; where they part, the estimate was off (FF Fig. 5).",
    )  # fmt: skip


def fig_fire_estimates(mission: RecordedMission, out: Path) -> list[Figure]:
    """Per true fire: every agent's estimate of each track matched to it by position
    (:mod:`fire_report.matching`), truth dashed; unmatched tracks get a figure of their own."""
    res: list[Figure] = []
    uavs = sorted({u for u, _ in mission.fire_estimates})
    colors = dict(zip(uavs, _colors(len(uavs)), strict=False))
    match = match_tracks_to_fires(mission.fire_estimates, mission.truth_fires)
    tracks = sorted({f for _, f in mission.fire_estimates})
    groups: list[tuple[int | None, list[int]]] = [
        (fid, [t for t in tracks if match.get(t) == fid]) for fid in sorted(set(match.values()))
    ]
    groups += [(None, [t]) for t in tracks if t not in match]
    for fid, tids in groups:
        fig, axes = plt.subplots(3, 1, figsize=(9, 6.5), sharex=True)
        labelled: set[int] = set()
        for tid in tids:
            for u in uavs:
                e = mission.fire_estimates.get((u, tid))
                if not e:
                    continue
                for ax, key in zip(axes, ("x", "y", "extent"), strict=False):
                    ax.plot(
                        e["t"], e[key], lw=0.8, color=colors[u], label=None if u in labelled else f"UAV {u}"
                    )
                labelled.add(u)
        tru = mission.truth_fires.get(fid) if fid is not None else None
        if tru:
            for ax, key in zip(axes, ("x", "y", "extent"), strict=False):
                ax.plot(tru["t"], tru[key], "k--", lw=1.2, label="truth")
        for ax, lab in zip(axes, ("x [m]", "y [m]", "size (spread \u03c3) [m]"), strict=False):
            ax.set_ylabel(lab)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7, ncol=4)
        ids = ", ".join(str(t) for t in tids)
        n = len(tids)
        if fid is not None:
            axes[0].set_title(f"Fire {fid}: each UAV's estimate of its position and size", fontsize=10)
            name = f"fire_{fid}_estimates.png"
            cap = (
                f"Fire {fid}: where each UAV believed it was and how large, over time, against the truth "
                f"(dashed); the fleet shares and averages these estimates, so the lines should come together "
                f"on the truth (FF Figs. 8-10; fleet track{'s' * (n > 1)} {ids}, matched by position)."
            )
        else:
            axes[0].set_title("A fire the fleet reported that matches no real fire", fontsize=10)
            name = f"track_{tids[0]}_estimates.png"
            cap = (
                "A fire the fleet believed in that lies farther than the matching distance from every real "
                f"fire: each UAV's estimate over time (fleet track {ids})."
            )
        axes[-1].set_xlabel("sim time [s]")
        res += _save(fig, out, name, cap)
    return res


def fig_drops(mission: RecordedMission, out: Path) -> list[Figure]:
    drops = [e for e in mission.world_events if e.type == EventType.DROP]
    if not drops:
        return []
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4))
    fires = sorted({e.fire_id for e in drops})
    for row, fid in enumerate(fires):
        t = [e.t_s for e in drops if e.fire_id == fid]
        axes[0].plot(t, [row] * len(t), "v", markersize=7)
    axes[0].set_yticks(range(len(fires)), [f"fire {f}" if f >= 0 else "missed" for f in fires])
    axes[0].set_xlabel("sim time [s]")
    axes[0].set_title("when each drop fell", fontsize=10)
    times = np.sort([e.t_s for e in drops])
    if times.size > 1:
        axes[1].hist(np.diff(times), bins=min(20, times.size - 1), color="tab:blue")
        axes[1].axvline(
            np.diff(times).mean(), color="k", ls="--", label=f"mean {np.diff(times).mean():.1f} s"
        )
        axes[1].legend()
    axes[1].set_xlabel("interval between consecutive drops [s]")
    axes[1].set_title("time between drops", fontsize=10)
    counts = [sum(1 for e in drops if e.fire_id == f) for f in fires]
    axes[2].bar([f"fire {f}" if f >= 0 else "missed" for f in fires], counts, color="tab:red")
    axes[2].set_title("drops per fire", fontsize=10)
    return _save(
        fig, out, "drops.png",
        "Water drops: when each fell and on which fire, the time between consecutive drops of the fleet "
        "(FF Table I) and the drops per fire (FF Fig. 14).",
    )  # fmt: skip


def fig_perimeter(mission: RecordedMission, out: Path) -> list[Figure]:
    if not mission.perimeters:
        return []
    fig = plt.figure(figsize=(10, 4.2))
    axp = fig.add_subplot(1, 2, 1, projection="polar")
    axe = fig.add_subplot(1, 2, 2)
    match = (
        match_tracks_to_fires(mission.fire_estimates, mission.truth_fires) if mission.fire_estimates else {}
    )
    for (u, fid), p in sorted(mission.perimeters.items()):
        outer = p["outer"][-1]
        ang = (np.arange(outer.size) + 0.5) * 2 * np.pi / max(outer.size, 1)
        # the fleet's track ids are not the world's fire ids: name the true fire it follows
        label = f"UAV {u}, fire {match[fid]}" if fid in match else f"UAV {u}"
        axp.plot(np.append(ang, ang[:1]), np.append(outer, outer[:1]), label=label)
        fn = perimeter_distance_error_raster if mission.fire_grids else perimeter_distance_error
        e = fn(mission, u, fid)
        if e["t"].size:
            axe.plot(e["t"], e["error_m"], label=label)
    axp.yaxis.set_major_locator(MaxNLocator(4))
    axp.tick_params(labelsize=7)
    axp.set_title("last perimeter map: distance of the edge [m]", fontsize=10)
    axp.legend(fontsize=7, loc="lower left")
    axe.set_xlabel("sim time [s]")
    axe.set_ylabel("max distance error over 360 angles [m]")
    axe.set_title("perimeter distance error", fontsize=10)
    axe.grid(alpha=0.3)
    return _save(
        fig, out, "perimeter.png",
        "Monitored fires: each monitor's last map of the fire's edge, and how far it was from the true edge "
        "over time (the perimeter-monitoring paper's distance error).",
    )  # fmt: skip


def fig_faults(
    mission: RecordedMission, out: Path, outages: list[tuple[float, float]] | None = None
) -> list[Figure]:
    """Lost peer messages over time with the faults marked; ``outages``: (start, end) [s] of every
    link outage, scheduled or injected (default: the scenario's)."""
    if outages is None:
        outages = []
        for o in (
            (mission.scenario.get("comms") or {}).get("outages") or []
            if isinstance(mission.scenario, dict)
            else []
        ):
            try:
                outages.append((float(o["start_s"]), float(o["end_s"])))
            except (KeyError, TypeError, ValueError):
                continue
    states = {u: s for u, s in mission.states.items() if s}
    crashes = [e for e in mission.world_events if e.type == EventType.CRASH]
    peer = [e for e in mission.fleet_events if e.type == EventType.PEER_CRASHED]
    if not states and not crashes and not peer:
        return []
    fig, ax = plt.subplots(figsize=(10, 3.8))
    colors = _colors(len(states))
    for k, (u, s) in enumerate(sorted(states.items())):
        ax.step(s["t"], s["lost"], where="post", color=colors[k], lw=0.9, label=f"UAV {u}")
    for i, e in enumerate(crashes):  # labelled in the legend: a label on the plot may cover the curves
        ax.axvline(e.t_s, color="k", lw=1.5, label="UAV lost" if i == 0 else None)
    for i, e in enumerate(peer):
        ax.axvline(e.t_s, color="tab:orange", ls=":", lw=1, label="peer declared lost" if i == 0 else None)
    for i, (t0, t1) in enumerate(outages or []):
        ax.axvspan(t0, t1, color="grey", alpha=0.15, label="link outage" if i == 0 else None)
    ax.set_xlabel("sim time [s]")
    ax.set_ylabel("peer messages lost, total")
    ax.grid(alpha=0.3)
    if states or crashes or peer:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return _save(
        fig, out, "faults.png",
        "Peer messages each UAV has lost so far (random loss, outages and silent peers), with the UAVs "
        "lost (black), the moments a peer was declared lost (orange, dotted) and the link outages (grey).",
    )  # fmt: skip


# --- raster suppression -------------------------------------------------------
GRID_COLORS = ListedColormap(["#f2efe6", "#8fc1e3", "#555555", "#ff6a00"])  # unburned, wet, burnt, burning


def _grid_index(data: np.ndarray) -> np.ndarray:
    return np.select([data >= 100, data >= 60, data >= 20], [3, 2, 1], 0)


_DROP_LINE = re.compile(r"pattern \((-?[\d.]+), (-?[\d.]+)\) -> \((-?[\d.]+), (-?[\d.]+)\) m")


def drop_line(detail: str) -> tuple[float, float, float, float] | None:
    """(x0, y0, x1, y1) [m] of a drop's ground pattern from its DROP event's detail (the world
    writes ``pattern (x0, y0) -> (x1, y1) m`` there with ``fires.drop_model: pattern``), else None."""
    m = _DROP_LINE.search(detail or "")
    if m is None:
        return None
    x0, y0, x1, y1 = (float(g) for g in m.groups())
    return (x0, y0, x1, y1)


def fig_raster_front(mission: RecordedMission, out: Path, ground: Ground | None = None) -> list[Figure]:
    """FF Fig. 11 for a raster fire: the true grid at four times with the fleet's shared front
    (/fleet/front), the drops so far (hit: filled, missed: open) and the UAVs' Voronoi cells.
    On a landscape the unburned cells are left clear over the ground's fuel types and hillshade."""
    grids = mission.fire_grids
    if not grids:
        return []
    picks = sorted({int(round(k)) for k in np.linspace(0, len(grids) - 1, 4)})
    fig, axes = plt.subplots(1, len(picks), figsize=(2.8 * len(picks), 3.2), squeeze=False)
    (x0, x1), (y0, y1) = _area(mission)
    drops = [e for e in mission.world_events if e.type == EventType.DROP and e.value > 0]
    for ax, k in zip(axes[0], picks, strict=True):
        g = grids[k]
        t = g["t"]
        ny, nx = g["data"].shape
        r = g["resolution"]
        ox, oy = g["origin"]
        index = _grid_index(g["data"])
        if ground is not None:
            draw_ground(ax, ground)
            index = np.ma.masked_equal(index, 0)
        ax.imshow(index, origin="lower", cmap=GRID_COLORS, vmin=0, vmax=3,
                  extent=(ox, ox + nx * r, oy, oy + ny * r), interpolation="nearest")  # fmt: skip
        pos = _positions_at(mission, t)
        if pos:
            sites = np.array(list(pos.values()))
            xs, ys, lab = voronoi_labels(sites, (x0, x1), (y0, y1), max((x1 - x0) / 200, 2.0))
            ax.contour(xs, ys, lab, levels=np.arange(len(sites)) + 0.5, colors="k", linewidths=0.5, alpha=0.6)
            ax.plot(sites[:, 0], sites[:, 1], "^", color="navy", ms=5)
        for _uav, rows in sorted(mission.fronts.items()):
            before = [f for f in rows if f["t"] <= t]
            if before:
                f = before[-1]
                on = f["state"] == 1  # FireCells.CELL_BURNING
                ax.plot(f["x"][on], f["y"][on], ".", ms=1.5, color="magenta", alpha=0.6)
        for e in drops:
            if e.t_s <= t:
                hit = e.fire_id >= 0
                ax.plot(e.x_m, e.y_m, "o", ms=4, mfc="tab:blue" if hit else "none", mec="tab:blue", alpha=0.8)
                line = drop_line(e.detail)
                if line is not None:  # a ground pattern (fires.drop_model: pattern): its centre line
                    ax.plot(line[0::2], line[1::2], "-", color="tab:blue", lw=1.2, alpha=0.8)
        _draw_crashes(ax, mission, t)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_title(f"t = {t:.0f} s", fontsize=9)
    cap = (
        "Raster fire (grey burnt, orange burning, blue wet) with the fleet's shared front (magenta), drops "
        "(filled: wet a burning cell; a ground pattern's centre line drawn from its release) and the UAVs' "
        "Voronoi cells."
    )
    if ground is not None:
        cap += " Under it, the ground's fuel types and terrain (see the landscape map)."
    return _save(fig, out, "raster_front.png", cap)


def fig_burned_area(
    mission: RecordedMission, out: Path, baseline: RecordedMission | None = None
) -> list[Figure]:
    """Burned area over time, against the no-fleet baseline bag when given (``--baseline``)."""
    t, area, _ = burned_area_series(mission)
    fires = mission.scenario.get("fires") if isinstance(mission.scenario, dict) else None
    if t.size == 0 or not (isinstance(fires, dict) and fires.get("model") == "raster"):
        return []
    fig, ax = plt.subplots(figsize=(7, 3.6))
    ax.plot(t, area / 1e4, color="tab:red", label=f"fleet ({len(mission.uav_ids)} UAVs)")
    base = baseline_area(baseline)
    if base is not None:
        ax.plot(base["t_s"], base["area_m2"] / 1e4, "k--", label="no fleet (baseline)")
    ax.set_xlabel("sim time [s]")
    ax.set_ylabel("burned area [ha]")
    ax.grid(alpha=0.3)
    ax.legend()
    cap = "Burned area over time, with the fleet" + (
        " and with no fleet (the same scenario and seed run with --uavs 0)."
        if base is not None
        else "; a run of the same scenario and seed with --uavs 0, given as --baseline, adds the fire alone."
    )
    return _save(fig, out, "burned_area.png", cap)


def _deg(lat: float, lon: float) -> str:
    return f"{abs(lat):.4f}\u00b0 {'N' if lat >= 0 else 'S'}, {abs(lon):.4f}\u00b0 {'E' if lon >= 0 else 'W'}"


def fig_landscape(mission: RecordedMission, out: Path, ground: Ground | None) -> list[Figure]:
    """The mission's ground: fuel types shaded by the terrain (``fire_report.ground``), the area
    burned by the end (the last fire grid's burnt and burning cells, outlined), the ignitions,
    the UAVs' true tracks and homes, the refill lakes and the UAVs lost."""
    if ground is None:
        return []
    fig, (ax, lax) = plt.subplots(1, 2, figsize=(9.4, 6.0), width_ratios=(4.2, 1.0))
    lax.axis("off")
    draw_ground(ax, ground)
    handles = fuel_legend_handles(ground)
    if mission.fire_grids:
        g = mission.fire_grids[-1]
        ny, nx = g["data"].shape
        r, (ox, oy) = g["resolution"], g["origin"]
        burned = (g["data"] >= 60).astype(float)
        if burned.any():
            xs, ys = ox + (np.arange(nx) + 0.5) * r, oy + (np.arange(ny) + 0.5) * r
            ax.contourf(xs, ys, burned, levels=[0.5, 1.5], colors=["#202020"], alpha=0.35)
            # above the tracks: a monitor circling the fire would hide its edge
            ax.contour(xs, ys, burned, levels=[0.5], colors=["#d7191c"], linewidths=1.8, zorder=4)
            handles.append(plt.Line2D([], [], color="#d7191c", lw=1.6, label=f"burned by {g['t']:.0f} s"))
    ids = sorted(mission.truth_vehicles)
    colors = _colors(len(ids))
    for k, u in enumerate(ids):
        v = mission.truth_vehicles[u]
        if v and v["x"].size:
            ax.plot(v["x"], v["y"], "-", color=colors[k], lw=0.6, alpha=0.7)
            ax.plot(v["x"][0], v["y"][0], "^", color=colors[k], markeredgecolor="k", ms=7)
    if ids:
        handles.append(plt.Line2D([], [], color="k", lw=0.7, marker="^", ms=6, label="UAV tracks, homes"))
    for x, y, d in ground.lakes:
        if d > 0:
            ax.add_patch(plt.Circle((x, y), d / 2, fill=False, ls="--", color="k", lw=1.0))
    if any(d > 0 for _, _, d in ground.lakes):
        handles.append(plt.Line2D([], [], color="k", ls="--", lw=1.0, label="refill disc"))
    starts = [(x, y, f"ignition {i}") for i, (x, y, _) in enumerate(ground.ignitions)] or [
        (float(f["x"][0]), float(f["y"][0]), f"fire {fid}")
        for fid, f in sorted(mission.truth_fires.items())
        if f
    ]  # a raster fire's ignitions, else where each fire was first recorded
    for x, y, label in starts:
        ax.plot(x, y, "*", color="#d7191c", markeredgecolor="k", ms=12, zorder=5)
        ax.annotate(label, (x, y), fontsize=8, xytext=(6, 4), textcoords="offset points", zorder=5)
    _draw_crashes(ax, mission, math.inf)
    (x0, x1), (y0, y1) = _area(mission)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (east) [m]")
    ax.set_ylabel("y (north) [m]")
    lax.legend(handles=handles, fontsize=8, loc="upper left", borderaxespad=0.0, frameon=False)
    sw, ne = ground.latlon([x0, x1], [y0, y1])
    corners = (
        f"south-west corner {_deg(float(sw[0]), float(ne[0]))}, north-east {_deg(float(sw[1]), float(ne[1]))}"
    )
    return _save(
        fig, out, "landscape.png",
        f"The ground of the mission, landscape {ground.name}: fuel types (the 53 standard fuel models in "
        "Scott & Burgan's families) shaded by the terrain (sun from the north-west), the area burned by "
        "the end (outlined red), the ignitions (stars), each UAV's true track from its home (triangle) "
        f"and the lakes the fleet refills from; {corners} (WGS84).",
    )  # fmt: skip


ALL_FIGURES = (
    fig_voronoi, fig_tracks, fig_ekf, fig_fire_estimates, fig_drops, fig_perimeter, fig_faults,
    fig_raster_front, fig_burned_area,
)  # fmt: skip


def make_figures(
    mission: RecordedMission,
    out: Path,
    baseline: RecordedMission | None = None,
    outages: list[tuple[float, float]] | None = None,
    ground: Ground | None = None,
) -> list[Figure]:
    """Write every figure the bag has data for into ``out``; return [(file, caption)].
    ``outages``: every link outage's (start, end) [s] for the faults figure (default: the scenario's);
    ``ground``: the mission's landscape (``fire_report.ground.mission_ground``), drawn under the maps."""
    figs: list[Figure] = fig_landscape(mission, out, ground)
    for fn in ALL_FIGURES:
        if fn in (fig_voronoi, fig_tracks, fig_raster_front):
            figs += fn(mission, out, ground)  # type: ignore[operator]
        elif fn is fig_burned_area:
            figs += fig_burned_area(mission, out, baseline)
        elif fn is fig_faults:
            figs += fig_faults(mission, out, outages)
        else:
            figs += fn(mission, out)
    return figs
