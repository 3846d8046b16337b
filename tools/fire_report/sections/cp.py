"""CP section: the power-diagram partition, planned against flown paths, the optimisation's cost
against evaluations (CP Fig. 8) and the radio radius r_max (CP III-E, Eq. 11).

From the bag: ``/fleet/coverage/weights`` (each agent's seed and power weight per balancing
iteration), ``/fleet/coverage/candidates`` (every evaluated candidate's cost, energy and r_max),
``/fleet/coverage/mst`` (the fragment-merge MST's DONE radii), the agents' planned STC paths
(``/uav_<k>/viz``, namespace ``uav_<k>_search_path``) and the truth tracks while searching.
Choices (ours): the partition drawn is the power diagram of each agent's last reported
(seed, weight), recomputed on a fine grid over the area (CP Eq. 2: cell i holds the points with
the least power distance |q - s_i|^2 - w_i); the agents' own plan assigns coarse cells and
repairs connectivity (Eq. 9), so borders may differ by a coarse cell. An evaluation is a
candidate id's first KIND_COST message (the agree phase rebroadcasts costs already counted).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from fire_uav_common.constants import Objective
from matplotlib.colors import ListedColormap

from fire_report.data import RecordedMission
from fire_report.sections import Section
from fire_report.sections.bagdata import SectionData

DPI = 110


def power_labels(
    sites_xy: np.ndarray,
    weights_m2: np.ndarray,
    x_range: tuple[float, float],
    y_range: tuple[float, float],
    resolution_m: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Power-diagram label of every grid cell centre (CP Eq. 2): argmin_i |q - s_i|^2 - w_i.

    Returns (xs, ys, labels[ny, nx]) indexing the rows of ``sites_xy``; -1 everywhere if no site."""
    xs = np.arange(x_range[0] + resolution_m / 2, x_range[1], resolution_m)
    ys = np.arange(y_range[0] + resolution_m / 2, y_range[1], resolution_m)
    if len(sites_xy) == 0:
        return xs, ys, np.full((ys.size, xs.size), -1)
    gx, gy = np.meshgrid(xs, ys)
    s = np.asarray(sites_xy, dtype=float)
    d = (gx[..., None] - s[:, 0]) ** 2 + (gy[..., None] - s[:, 1]) ** 2 - np.asarray(weights_m2, dtype=float)
    return xs, ys, np.argmin(d, axis=-1)


def incumbent(costs: np.ndarray) -> np.ndarray:
    """Running minimum of the costs in evaluation order (CP Fig. 8's orange trace)."""
    return np.minimum.accumulate(np.asarray(costs, dtype=float)) if len(costs) else np.zeros(0)


def final_weights(data: SectionData) -> dict[int, tuple[np.ndarray, float, float, float, int]]:
    """uav -> (seed (2,), weight [m^2], area [m^2], target area [m^2], iteration) of its last report."""
    out = {}
    for u, rows in data.weights.items():
        t, it, seed, w, a, target = max(rows, key=lambda r: (r[1], r[0]))
        out[u] = (seed, w, a, target, it)
    return out


def _area(mission: RecordedMission) -> tuple[tuple[float, float], tuple[float, float]] | None:
    a = mission.scenario.get("area") if isinstance(mission.scenario, dict) else None
    if a is None:
        return None
    try:
        return (float(a["x_min_m"]), float(a["x_max_m"])), (float(a["y_min_m"]), float(a["y_max_m"]))
    except (KeyError, TypeError, ValueError):
        return None


def _search_track(mission: RecordedMission, uav: int) -> dict[str, np.ndarray] | None:
    s, v = mission.states.get(uav), mission.truth_vehicles.get(uav)
    if not s or not v:
        return None
    keep = np.isin(v["step"], s["step"][s["objective"] == Objective.SEARCH])
    return {k: v[k][keep] for k in ("t", "x", "y")} if keep.any() else None


def mst_radius(data: SectionData) -> dict[str, float] | None:
    """r_max of the newest MST session (the largest DONE radius over its sampled instants) and its
    number of instants; None without DONE messages. A session's instants carry consecutive
    ``sample_index`` values (plan key * stride + instant), so a session is a run of consecutive
    indices: the one holding the newest DONE."""
    done = [(t, idx, r) for t, _u, idx, r in data.mst_done if np.isfinite(r)]
    if not done:
        return None
    radius: dict[int, float] = {}
    for _t, idx, r in done:
        radius[idx] = max(radius.get(idx, 0.0), r)
    newest = max(done)[1]
    lo = hi = newest
    while lo - 1 in radius:
        lo -= 1
    while hi + 1 in radius:
        hi += 1
    session = [radius[i] for i in range(lo, hi + 1)]
    return {"r_max_m": float(max(session)), "instants": len(session)}


def build(mission: RecordedMission, data: SectionData, out: Path) -> Section | None:
    if not (data.costs or data.weights or data.planned_paths):
        return None
    sec = Section("cp", "Coverage search (CP)")
    m: dict = {
        "evaluations": len(data.costs),
        "cost_messages": data.cost_messages,
        "proposals": data.proposals,
    }
    if data.costs:
        costs = np.asarray([c.cost for c in data.costs])
        best = data.costs[int(np.argmin(costs))]
        m["best"] = {"candidate_id": best.candidate_id, "cost": best.cost, "energy_j": best.energy_j,
                     "radio_radius_m": best.radio_radius_m, "evaluated_by": best.uav_id,
                     "evaluation": int(np.argmin(costs)) + 1}  # fmt: skip
        m["first_cost"] = float(costs[0])
        sec.rows += [
            ("evaluations (candidates with a cost)", str(len(data.costs))),
            (
                "best candidate",
                f"{best.candidate_id} (evaluation {m['best']['evaluation']}, by UAV {best.uav_id})",
            ),
            ("best cost [-]", f"{best.cost:.3f} (first evaluation: {costs[0]:.3f})"),
            ("best sum of path energies [J]", f"{best.energy_j:.4g}"),
            ("best r_max (centralised, in the cost) [m]", f"{best.radio_radius_m:.1f}"),
        ]
    mst = mst_radius(data)
    if mst is not None:
        m["mst"] = mst
        sec.rows.append(("r_max from the fleet's message-passing MST [m]",
                         f"{mst['r_max_m']:.1f} over {mst['instants']} sampled instants"))  # fmt: skip
    fw = final_weights(data)
    area = _area(mission)
    if fw and area is not None:
        ids = sorted(fw)
        sites = np.asarray([fw[u][0] for u in ids])
        w = np.asarray([fw[u][1] for u in ids])
        (x0, x1), (y0, y1) = area
        res = max((x1 - x0), (y1 - y0)) / 250.0
        _, _, lab = power_labels(sites, w, (x0, x1), (y0, y1), res)
        areas = {u: float(np.count_nonzero(lab == i)) * res * res for i, u in enumerate(ids)}
        target = {u: fw[u][3] for u in ids}
        m["partition"] = {str(u): {"area_m2": areas[u], "target_area_m2": target[u], "iteration": fw[u][4],
                                   "reported_area_m2": fw[u][2]} for u in ids}  # fmt: skip
        worst = max(abs(areas[u] - target[u]) / target[u] for u in ids if target[u] > 0) if ids else 0.0
        m["partition_max_relative_area_error"] = float(worst)
        sec.rows.append(("power cells: area / target [km^2]",
                         ", ".join(f"UAV {u}: {areas[u] / 1e6:.3f} / {target[u] / 1e6:.3f}" for u in ids)))  # fmt: skip
        sec.figures += _fig_partition(mission, data, ids, sites, lab, area, out)
    if data.planned_paths:
        m["planned_paths"] = {str(u): {"plans": len(v), "points": int(len(v[-1][1])),
                                       "length_m": float(np.sum(np.linalg.norm(np.diff(v[-1][1], axis=0), axis=1)))}
                              for u, v in sorted(data.planned_paths.items())}  # fmt: skip
    sec.metrics = m
    if not data.planned_paths:
        sec.notes.append("No planned path in the bag (agents before the uav_<k>_search_path marker).")
    sec.figures += _fig_cost(data, out)
    return sec


def _save(fig: plt.Figure, out: Path, name: str, caption: str) -> list[tuple[str, str]]:
    fig.tight_layout()
    fig.savefig(out / name, dpi=DPI)
    plt.close(fig)
    return [(name, caption)]


def _fig_partition(mission, data, ids, sites, lab, area, out) -> list[tuple[str, str]]:
    (x0, x1), (y0, y1) = area
    cmap = plt.get_cmap("tab10")
    colors = [cmap(i % 10) for i in range(len(ids))]
    fig, ax = plt.subplots(figsize=(7.5, 7))
    ax.imshow(lab, origin="lower", extent=(x0, x1, y0, y1), cmap=ListedColormap(colors), alpha=0.22,
              interpolation="nearest", vmin=0, vmax=max(len(ids) - 1, 1))  # fmt: skip
    for k, u in enumerate(ids):
        plans = data.planned_paths.get(u)
        if plans:
            pts = plans[-1][1]
            ax.plot(pts[:, 0], pts[:, 1], "--", color=colors[k], lw=0.9, label=f"UAV {u} planned")
        trk = _search_track(mission, u)
        if trk is not None:
            ax.plot(trk["x"], trk["y"], "-", color=colors[k], lw=1.6, alpha=0.9, label=f"UAV {u} flown")
        ax.plot(*sites[k], "o", color=colors[k], markeredgecolor="k", markersize=8)
    for f in mission.truth_fires.values():
        if f:
            ax.plot(f["x"][0], f["y"][0], "r*", markersize=12)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=7, loc="upper left", ncol=2)
    ax.set_title("power-diagram partition, planned (dashed) and flown (solid) paths")
    return _save(fig, out, "cp_partition.png",
                 "Power-diagram partition from the agents' last (seed, weight) reports (CP Eqs. 2-8; dots: seeds), "
                 "each agent's planned spanning-tree coverage path (dashed) and its true track while searching "
                 "(solid); red star: the fire at ignition.")  # fmt: skip


def _fig_cost(data, out) -> list[tuple[str, str]]:
    if not data.costs:
        return []
    costs = np.asarray([c.cost for c in data.costs])
    r = np.asarray([c.radio_radius_m for c in data.costs])
    n = np.arange(1, costs.size + 1)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    axes[0].plot(n, costs, "o", color="tab:blue", label="cost per evaluation")
    axes[0].plot(n, incumbent(costs), "o-", color="tab:orange", ms=4, label="incumbent minimum")
    axes[0].set_xlabel("evaluation")
    axes[0].set_ylabel("cost f = r_max + lambda E [-]")
    axes[0].set_title("optimisation (CP Fig. 8)")
    axes[0].legend(fontsize=8)
    axes[1].plot(n, r, "s", color="tab:green", label="r_max of the candidate")
    axes[1].plot(
        n[int(np.argmin(costs))], r[int(np.argmin(costs))], "*", color="k", ms=14, label="best candidate"
    )
    axes[1].set_xlabel("evaluation")
    axes[1].set_ylabel("r_max [m]")
    axes[1].set_title("radio radius r_max (CP III-E)")
    axes[1].legend(fontsize=8)
    for ax in axes:
        ax.grid(alpha=0.3)
    return _save(fig, out, "cp_cost.png",
                 "Cost of each evaluated candidate in the order the fleet evaluated them, with the incumbent "
                 "minimum (CP Fig. 8), and each candidate's radio radius r_max.")  # fmt: skip
