"""A synthetic mission bag whose metrics are known exactly (tests, benchmarks). No ROS needed.

The fleet flies circles; every estimate is the truth plus a constant error
(``EKF_ERROR``), the covariance is constant, and the events are the fixed schedule below
(scaled to ``duration_s``). :func:`expected_metrics` states the answer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import fire_uav_recording as bag_io
from fire_uav_common import topics
from fire_uav_common.constants import EventType, FireStatus, Objective, VehicleStatus
from fire_uav_common.stamps import s_to_ns, to_time_msg

EKF_ERROR = {"x": 1.5, "y": -0.5, "z": 0.25, "yaw": 0.02}  # estimate - truth [m, m, m, rad]
COVARIANCE_DIAG = (4.0, 4.0, 1.0, 0.01)  # trace 9.01
PERIMETER_BINS = 8
PERIMETER_OFFSET_M = 2.0  # the monitor's outer distance exceeds the true radius by this


@dataclass(frozen=True)
class SyntheticMission:
    """Parameters of the synthetic bag; event times are fractions of ``duration_s``."""

    uav_count: int = 2
    duration_s: float = 10.0
    control_period_s: float = 0.1
    seed: int = 7
    # (fraction of duration, uav, fire id or -1 for a miss)
    drops: tuple[tuple[float, int, int], ...] = (
        (0.1, 0, 0),
        (0.25, 1, 0),
        (0.4, 0, 1),
        (0.5, 1, -1),
        (0.8, 0, 1),
    )
    extinguished: tuple[tuple[float, int], ...] = ((0.6, 0), (0.9, 1))
    crash: tuple[float, int] | None = (0.7, 1)  # world: UAV 1 falls
    peer_crashed: tuple[float, int, int] | None = (0.8, 0, 1)  # UAV 0 declares UAV 1 crashed
    lost_final: tuple[int, ...] = (3, 4)  # last packets_lost per UAV (repeated if uav_count > 2)
    monitor: tuple[int, int] | None = (0, 1)  # UAV 0 monitors fire 1
    # the fire picture inside UavState (the current protocol); False: on /fleet/fires (bags of the older protocol)
    fires_in_state: bool = True
    scenario_yaml: str = (
        "name: synthetic\nseed: 7\narea: {x_min_m: 0, x_max_m: 600, y_min_m: 0, y_max_m: 600}\n"
        "lakes: [{x_m: 50, y_m: 50, diameter_m: 90}]\n"
        "comms: {loss_probability: 0.05, outages: [{from: 0, to: 1, start_s: 2.0, end_s: 3.0}]}\n"
    )

    def lost(self, uav: int) -> int:
        return self.lost_final[uav % len(self.lost_final)]


def write_synthetic_mission(path: str | Path, spec: SyntheticMission | None = None) -> SyntheticMission:
    """Write the bag directory ``path`` (must not exist) for ``spec``; return ``spec``."""
    spec = spec or SyntheticMission()
    ts = bag_io.fleet_typestore()
    T = ts.types
    Time, Header = T["builtin_interfaces/msg/Time"], T["std_msgs/msg/Header"]
    Clock = T["rosgraph_msgs/msg/Clock"]
    UavState, FireEstimate, FireEstimateArray = (
        T["fire_uav_msgs/msg/UavState"],
        T["fire_uav_msgs/msg/FireEstimate"],
        T["fire_uav_msgs/msg/FireEstimateArray"],
    )
    WorldTruth, VehicleTruth, FireTruth = (
        T["fire_uav_msgs/msg/WorldTruth"],
        T["fire_uav_msgs/msg/VehicleTruth"],
        T["fire_uav_msgs/msg/FireTruth"],
    )
    MissionEvent, PerimeterMap = T["fire_uav_msgs/msg/MissionEvent"], T["fire_uav_msgs/msg/PerimeterMap"]
    import numpy as np

    no_tag = np.zeros(32, dtype=np.uint8)  # uint8[32] auth: an unsigned message (docs/security.md)

    def header(sec: float) -> Any:
        return Header(stamp=to_time_msg(s_to_ns(sec), Time), frame_id="map")

    def event(
        sec: float,
        typ: int,
        uav: int = -1,
        peer: int = -1,
        fire: int = -1,
        detail: str = "",
        value: float = 0.0,
    ) -> Any:
        return MissionEvent(
            header=header(sec),
            type=typ,
            uav_id=uav,
            peer_id=peer,
            fire_id=fire,
            x_m=math.nan,
            y_m=math.nan,
            value=value,
            detail=detail,
        )

    n_steps = round(spec.duration_s / spec.control_period_s)
    D = spec.duration_s
    fires0 = {0: (300.0, 400.0, 50.0), 1: (450.0, 150.0, 30.0)}
    ext_t = {fid: f * D for f, fid in spec.extinguished}
    crash_t = spec.crash[0] * D if spec.crash else math.inf
    custom = {
        bag_io.KEY_SCENARIO_FILE: "synthetic.yaml",
        bag_io.KEY_SCENARIO_YAML: spec.scenario_yaml,
        bag_io.KEY_SEED: str(spec.seed),
        bag_io.KEY_UAV_COUNT: str(spec.uav_count),
        bag_io.KEY_SOFTWARE_VERSION: "synthetic",
    }
    world_events: list[tuple[float, Any]] = []
    for f, uav, fid in spec.drops:
        world_events.append(
            (f * D, event(f * D, EventType.DROP, uav=uav, fire=fid, detail="drop", value=2000.0))
        )
    for f, fid in spec.extinguished:
        world_events.append((f * D, event(f * D, EventType.EXTINGUISHED, fire=fid, detail="out")))
    if spec.crash:
        world_events.append(
            (crash_t, event(crash_t, EventType.CRASH, uav=spec.crash[1], detail="no command for 3.0 s"))
        )
    world_events.append(
        (D, event(D, EventType.MISSION_COMPLETE, detail="all fires out and every vehicle landed", value=1.0))
    )
    fleet_events: list[tuple[float, Any]] = []
    if spec.peer_crashed:
        f, by, peer = spec.peer_crashed
        fleet_events.append(
            (f * D, event(f * D, EventType.PEER_CRASHED, uav=by, peer=peer, detail="silent for 10 steps"))
        )
    pending_w = sorted(world_events, key=lambda x: x[0])
    pending_f = sorted(fleet_events, key=lambda x: x[0])

    with bag_io.BagWriter(path, custom_data=custom) as w:
        c_clock = w.add_connection(topics.CLOCK, Clock.__msgtype__, typestore=ts)
        c_state = w.add_connection(topics.FLEET_STATE, UavState.__msgtype__, typestore=ts)
        c_fires = w.add_connection(topics.FLEET_FIRES, FireEstimateArray.__msgtype__, typestore=ts)
        c_truth = w.add_connection(topics.WORLD_TRUTH, WorldTruth.__msgtype__, typestore=ts)
        c_wev = w.add_connection(topics.WORLD_EVENTS, MissionEvent.__msgtype__, typestore=ts)
        c_fev = w.add_connection(topics.FLEET_EVENTS, MissionEvent.__msgtype__, typestore=ts)
        c_per = w.add_connection(topics.FLEET_PERIMETER, PerimeterMap.__msgtype__, typestore=ts)

        def put(conn: Any, t: float, msg: Any) -> None:
            w.write(conn, s_to_ns(t), ts.serialize_cdr(msg, msg.__msgtype__))

        cov = np.diag(COVARIANCE_DIAG).ravel()

        def estimates(u: int, t: float, stamp: Any) -> list:
            return [
                FireEstimate(
                    fire_id=fid,
                    status=FireStatus.EXTINGUISHED if t >= ext_t.get(fid, math.inf) else FireStatus.ACTIVE,
                    x_m=fx + u,
                    y_m=fy - u,
                    extent_m=sig,
                    vx_mps=0.0,
                    vy_mps=0.0,
                    last_measurement=stamp,
                    front_x_m=math.nan,
                    front_y_m=math.nan,
                    max_spread_rate_mps=0.0,
                )
                for fid, (fx, fy, sig) in fires0.items()
            ]

        for k in range(n_steps):
            t = (k + 1) * spec.control_period_s
            stamp = to_time_msg(s_to_ns(t), Time)
            put(c_clock, t, Clock(clock=stamp))
            vehicles, fires = [], []
            for u in range(spec.uav_count):
                ang = 0.05 * t + 2 * math.pi * u / spec.uav_count
                x, y, z, yaw = 300 + 100 * math.cos(ang), 300 + 100 * math.sin(ang), 30.0, 0.3
                vehicles.append(
                    VehicleTruth(
                        uav_id=u,
                        status=VehicleStatus.CRASHED
                        if t >= crash_t and spec.crash and u == spec.crash[1]
                        else VehicleStatus.AIRBORNE,
                        x_m=x,
                        y_m=y,
                        z_m=z,
                        yaw_rad=yaw,
                        v_lin_mps=50.0,
                        v_z_mps=0.0,
                        omega_z_radps=0.0,
                        water_kg=np.float32(1000),
                        commands_clamped=0,
                        commands_missed=0,
                    )
                )
                if spec.crash and u == spec.crash[1] and t >= crash_t:
                    continue
                lost = min(k, spec.lost(u))
                put(
                    c_state,
                    t,
                    UavState(
                        header=header(t),
                        uav_id=u,
                        sequence=k + 1,
                        step=k,
                        x_m=x + EKF_ERROR["x"],
                        y_m=y + EKF_ERROR["y"],
                        z_m=z + EKF_ERROR["z"],
                        yaw_rad=yaw + EKF_ERROR["yaw"],
                        covariance=cov.copy(),
                        objective=Objective.SUPPRESS,
                        target_fire_id=0,
                        water_kg=np.float32(1000),
                        centroid_x_m=x,
                        centroid_y_m=y,
                        alive_peers=np.arange(spec.uav_count, dtype=np.uint8),
                        crashed_peers=np.zeros(0, dtype=np.uint8),
                        packets_received=k,
                        packets_lost=lost,
                        packets_rejected=0,
                        sent_per_topic=np.array([1, 1, 0, 0, 0, 0], dtype=np.uint16),
                        final=False,
                        fires_sequence=k + 1,
                        fires=estimates(u, t, stamp) if spec.fires_in_state else [],
                        auth=no_tag,
                    ),
                )
            for fid, (fx, fy, sig) in fires0.items():
                out = t >= ext_t.get(fid, math.inf)
                fires.append(
                    FireTruth(
                        fire_id=fid,
                        status=FireStatus.EXTINGUISHED if out else FireStatus.ACTIVE,
                        x_m=fx,
                        y_m=fy,
                        extent_m=0.0 if out else sig,
                        area_m2=0.0 if out else math.pi * sig**2,
                        drops_received=0,
                    )
                )
            truth = WorldTruth(
                header=header(t),
                step=k,
                min_separation_m=math.inf,
                collisions=0,
                vehicles=vehicles,
                fires=fires,
            )
            put(c_truth, t, truth)
            for u in range(spec.uav_count):
                if spec.crash and u == spec.crash[1] and t >= crash_t:
                    continue
                ests = estimates(u, t, stamp)
                if spec.fires_in_state:
                    continue
                put(
                    c_fires,
                    t,
                    FireEstimateArray(
                        header=header(t), uav_id=u, sequence=k + 1, step=k, fires=ests, auth=no_tag
                    ),
                )
            if spec.monitor and t < ext_t.get(spec.monitor[1], math.inf):
                u, fid = spec.monitor
                fx, fy, sig = fires0[fid]
                nb = PERIMETER_BINS
                put(
                    c_per,
                    t,
                    PerimeterMap(
                        header=header(t),
                        uav_id=u,
                        sequence=k + 1,
                        fire_id=fid,
                        center_x_m=fx,
                        center_y_m=fy,
                        outer_distance_m=np.full(nb, sig + PERIMETER_OFFSET_M, dtype=np.float32),
                        outer_visit_time_s=np.full(nb, t, dtype=np.float32),
                        spread_rate_mps=np.zeros(nb, dtype=np.float32),
                        importance=np.ones(nb, dtype=np.float32),
                        direction=0,
                        direction_changes=0,
                        auth=no_tag,
                    ),
                )
            while pending_w and pending_w[0][0] <= t + 1e-9:
                te, msg = pending_w.pop(0)
                put(c_wev, te, msg)
            while pending_f and pending_f[0][0] <= t + 1e-9:
                te, msg = pending_f.pop(0)
                put(c_fev, te, msg)
    return spec


def expected_metrics(spec: SyntheticMission) -> dict[str, Any]:
    """The metrics :func:`fire_report.compute_metrics` must give for the bag of ``spec``."""
    D = spec.duration_s
    drop_t = sorted(f * D for f, _, _ in spec.drops)
    per_fire: dict[str, int] = {}
    for _, _, fid in spec.drops:
        key = str(fid) if fid >= 0 else "missed"
        per_fire[key] = per_fire.get(key, 0) + 1
    intervals = [b - a for a, b in zip(drop_t, drop_t[1:], strict=False)]
    lost = {str(u): spec.lost(u) for u in range(spec.uav_count)}
    return {
        "drop_count": len(spec.drops),
        "drops_per_fire": dict(sorted(per_fire.items())),
        "mean_inter_drop_interval_s": sum(intervals) / len(intervals) if intervals else None,
        "extinction_times_s": {str(fid): f * D for f, fid in spec.extinguished},
        "crash_uavs": [spec.crash[1]] if spec.crash else [],
        "peers_declared_crashed": [(spec.peer_crashed[1], spec.peer_crashed[2])] if spec.peer_crashed else [],
        "packets_lost": lost,
        "packets_lost_total": sum(lost.values()),
        "mission_duration_s": D,
        "outcome": "complete",
        "ekf_abs_error": {k: abs(v) for k, v in EKF_ERROR.items()},
        "trace_p": sum(COVARIANCE_DIAG),
        "perimeter_error_m": PERIMETER_OFFSET_M,
    }
