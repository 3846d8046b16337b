"""The recorded data the capability sections need beyond :class:`~fire_report.data.RecordedMission`.

One more pass over the bag, on the section topics only: the PM and CP traffic
(``/fleet/perimeter`` with every field, ``/fleet/coverage/*``), the raster truth
(``/viz/fire_grid``) and the agents' planned search paths (``/uav_<k>/viz``, namespace
``uav_<k>_search_path``). Times are sim seconds (header stamps), positions [m; map frame].
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

import fire_uav_recording as bag_io
import numpy as np
from fire_uav_common.constants import CandidateKind, MstKind
from fire_uav_common.stamps import stamp_to_s
from fire_uav_common.topics import (
    COVERAGE_CANDIDATES,
    COVERAGE_MST,
    COVERAGE_WEIGHTS,
    FLEET_PERIMETER,
    VIZ_FIRE_GRID,
)

from fire_report.errors import ReportError

PATH_NS = re.compile(r"uav_(\d+)_search_path")
VIZ_AGENT = re.compile(r"/uav_(\d+)/viz")


@dataclass(frozen=True)
class GridSnapshot:
    """One raster snapshot (OccupancyGrid): ``occ`` (ny, nx) int8 (0 unburned, 20 wet, 60 burnt,
    100 burning), cell (i, j) centred at (x0 + (j + 0.5) res, y0 + (i + 0.5) res)."""

    t_s: float
    x0_m: float
    y0_m: float
    res_m: float
    occ: np.ndarray

    def fire_mask(self) -> np.ndarray:
        """Burning or burnt cells (the fire shape PM compares with)."""
        return self.occ >= 60


@dataclass(frozen=True)
class PerimeterSample:
    """One PerimeterMap (PM IV-A); per-bin arrays, NaN where unknown."""

    t_s: float
    uav_id: int
    fire_id: int
    center_xy_m: tuple[float, float]
    outer_m: np.ndarray
    visit_s: np.ndarray
    spread_mps: np.ndarray
    importance: np.ndarray
    direction: int
    direction_changes: int


@dataclass(frozen=True)
class Cost:
    """One evaluated candidate (CoverageCandidate KIND_COST, first time it was heard)."""

    t_s: float
    uav_id: int
    candidate_id: int
    cost: float
    energy_j: float
    radio_radius_m: float
    seeds_m: np.ndarray  # (N, 2)


@dataclass
class SectionData:
    """What the sections read; empty containers when the bag holds none of it."""

    grids: list[GridSnapshot] = field(default_factory=list)
    perimeter: list[PerimeterSample] = field(default_factory=list)
    costs: list[Cost] = field(default_factory=list)  # in order of first appearance (evaluation order)
    cost_messages: int = 0  # KIND_COST messages including rebroadcasts
    proposals: int = 0
    # per UAV: [(t, iteration, seed (2,), weight, area, target)]
    weights: dict[int, list[tuple[float, int, np.ndarray, float, float, float]]] = field(default_factory=dict)
    # MST DONE: [(t, uav, sample_index, radius)]
    mst_done: list[tuple[float, int, int, float]] = field(default_factory=list)
    mst_messages: int = 0
    # per UAV: [(t, (n, 2) path points)] in time order
    planned_paths: dict[int, list[tuple[float, np.ndarray]]] = field(default_factory=dict)


def load_section_data(path: str, topics: dict[str, str], *, salvage: bool = True) -> SectionData:
    """Read the section topics of the bag at ``path`` (``topics``: the bag's name -> type)."""
    wanted = [t for t in (FLEET_PERIMETER, VIZ_FIRE_GRID, COVERAGE_WEIGHTS, COVERAGE_CANDIDATES, COVERAGE_MST)
              if t in topics]  # fmt: skip
    wanted += sorted(t for t in topics if VIZ_AGENT.fullmatch(t))
    data = SectionData()
    if not wanted:
        return data
    try:
        with bag_io.open_bag(path, salvage=salvage) as bag:
            for topic, _t_ns, msg in bag.messages(wanted):
                _take(data, topic, msg)
    except bag_io.BagError as err:
        raise ReportError(str(err)) from None
    data.grids.sort(key=lambda g: g.t_s)
    data.perimeter.sort(key=lambda p: (p.t_s, p.uav_id))
    return data


def _f32(values: Any) -> np.ndarray:
    return np.asarray(values, dtype=float)


def _take(data: SectionData, topic: str, msg: Any) -> None:
    if topic == VIZ_FIRE_GRID:
        info = msg.info
        occ = np.asarray(msg.data, dtype=np.int8).reshape(int(info.height), int(info.width))
        data.grids.append(GridSnapshot(stamp_to_s(msg.header.stamp), float(info.origin.position.x),
                               float(info.origin.position.y), float(info.resolution), occ))  # fmt: skip
    elif topic == FLEET_PERIMETER:
        data.perimeter.append(
            PerimeterSample(
                stamp_to_s(msg.header.stamp),
                int(msg.uav_id),
                int(msg.fire_id),
                (float(msg.center_x_m), float(msg.center_y_m)),
                _f32(msg.outer_distance_m),
                _f32(msg.outer_visit_time_s),
                _f32(msg.spread_rate_mps),
                _f32(msg.importance),
                int(msg.direction),
                int(msg.direction_changes),
            )  # fmt: skip
        )
    elif topic == COVERAGE_CANDIDATES:
        if int(msg.kind) == CandidateKind.PROPOSAL:
            data.proposals += 1
            return
        data.cost_messages += 1
        cid = int(msg.candidate_id)
        if any(c.candidate_id == cid for c in data.costs):
            return  # a rebroadcast (agree phase): the evaluation was counted when first heard
        seeds = np.asarray([(p.x, p.y) for p in msg.seeds], dtype=float).reshape(-1, 2)
        data.costs.append(Cost(stamp_to_s(msg.header.stamp), int(msg.uav_id), cid, float(msg.cost),
                               float(msg.energy_j), float(msg.radio_radius_m), seeds))  # fmt: skip
    elif topic == COVERAGE_WEIGHTS:
        data.weights.setdefault(int(msg.uav_id), []).append(
            (
                stamp_to_s(msg.header.stamp),
                int(msg.iteration),
                np.array([msg.seed_x_m, msg.seed_y_m]),
                float(msg.weight_m2),
                float(msg.area_m2),
                float(msg.target_area_m2),
            )  # fmt: skip
        )
    elif topic == COVERAGE_MST:
        data.mst_messages += 1
        if int(msg.kind) == MstKind.DONE:
            data.mst_done.append((stamp_to_s(msg.header.stamp), int(msg.uav_id), int(msg.sample_index),
                                  float(msg.radius_m)))  # fmt: skip
    else:  # /uav_<k>/viz
        for m in msg.markers:
            hit = PATH_NS.fullmatch(str(m.ns))
            if hit and m.points:
                pts = np.asarray([(p.x, p.y) for p in m.points], dtype=float)
                data.planned_paths.setdefault(int(hit.group(1)), []).append((stamp_to_s(m.header.stamp), pts))
