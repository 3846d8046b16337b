"""fire_report.metrics on small in-memory missions whose answers are worked out by hand (fast).

References: brute-force nearest-site loops for the Voronoi labels, EKF errors typed from the
numbers fed in (estimate minus truth, yaw wrapped, trace of a diagonal P), percentiles of a
single value, polar geometry of single raster cells, and event counts by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_report.data import RecordedEvent, RecordedMission
from fire_report.metrics import (
    _percentiles,
    compute_metrics,
    ekf_errors,
    mission_duration_s,
    perimeter_distance_error,
    perimeter_distance_error_raster,
    true_outer_distance,
    voronoi_labels,
)
from fire_uav_common.constants import EventType


def _mission(**kw) -> RecordedMission:
    m = RecordedMission(path="mem", custom_data={}, scenario=kw.pop("scenario", {}), warnings=[], topics={})
    for k, v in kw.items():
        setattr(m, k, v)
    return m


def _event(t, type_, uav=0, fire_id=-1, value=0.0, detail="", source="world", peer=-1):
    return RecordedEvent(t, type_, uav, peer, fire_id, 0.0, 0.0, value, detail, source)


def test_voronoi_labels_against_brute_force():
    sites = np.array([[10.0, -40.0], [70.0, 0.0], [35.0, 20.0]])
    xs, ys, lab = voronoi_labels(sites, (0.0, 100.0), (-50.0, 30.0), 10.0)
    assert xs.tolist() == [5.0 + 10.0 * k for k in range(10)]  # cell centres inside the range
    assert ys.tolist() == [-45.0 + 10.0 * k for k in range(8)]
    want = np.empty((8, 10), dtype=int)
    for r, y in enumerate(ys):
        for c, x in enumerate(xs):
            want[r, c] = min(range(3), key=lambda s: (x - sites[s, 0]) ** 2 + (y - sites[s, 1]) ** 2)
    assert lab.tolist() == want.tolist()
    _, _, one = voronoi_labels(sites[:1], (0.0, 100.0), (-50.0, 30.0), 10.0)
    assert (one == 0).all() and one.shape == (8, 10)  # one site owns everything
    _, _, none = voronoi_labels(np.zeros((0, 2)), (0.0, 100.0), (-50.0, 30.0), 10.0)
    assert (none == -1).all() and none.shape == (8, 10)


def _p(diag):
    return np.array([np.diag(d) for d in diag], dtype=float)


def test_ekf_errors_match_by_step_and_keep_only_airborne_samples():
    est = {
        "t": np.array([0.0, 0.1, 0.2, 0.3]),
        "step": np.array([0, 1, 2, 3]),
        "x": np.array([0.0, 11.0, 22.0, 33.0]),
        "y": np.array([0.0, 5.0, 6.0, 7.0]),
        "z": np.array([0.0, 100.5, 101.0, 0.0]),
        "yaw": np.array([0.0, 3.1, 0.2, 0.0]),
        "P": _p([[1, 1, 1, 1], [1, 2, 3, 4], [0.5, 0.5, 0.5, 0.5], [9, 9, 9, 9]]),
    }
    tru = {
        "t": np.array([0.1, 0.2, 0.3, 0.4]),
        "step": np.array([1, 2, 3, 4]),
        "x": np.array([10.0, 20.0, 30.0, 40.0]),
        "y": np.array([4.0, 6.5, 7.0, 8.0]),
        "z": np.array([100.0, 100.0, 0.0, 0.0]),
        "yaw": np.array([-3.1, 0.0, 0.0, 0.0]),
        "status": np.array([1, 1, 0, 1]),  # step 3 on the ground
    }
    e = ekf_errors(_mission(states={0: est}, truth_vehicles={0: tru}), 0)
    assert e["t"].tolist() == [0.1, 0.2]  # steps 1 and 2: recorded both ways and airborne
    assert e["x"].tolist() == [1.0, 2.0] and e["y"].tolist() == [1.0, -0.5] and e["z"].tolist() == [0.5, 1.0]
    np.testing.assert_allclose(e["yaw"], [6.2 - 2 * math.pi, 0.2])  # 3.1 - (-3.1), wrapped
    assert e["trace_p"].tolist() == [10.0, 2.0]
    # without a status every matched step counts
    no_status = {k: v for k, v in tru.items() if k != "status"}
    assert ekf_errors(_mission(states={0: est}, truth_vehicles={0: no_status}), 0)["t"].tolist() == [
        0.1,
        0.2,
        0.3,
    ]
    # one matched step is enough
    one = {k: v[:1] for k, v in tru.items()}
    assert ekf_errors(_mission(states={0: est}, truth_vehicles={0: one}), 0)["x"].tolist() == [1.0]


@pytest.mark.parametrize("which", ["no truth", "no estimate", "no match"])
def test_ekf_errors_empty_cases_have_every_key(which):
    est = {k: np.array([1.0]) for k in ("t", "step", "x", "y", "z", "yaw")} | {"P": _p([[1, 1, 1, 1]])}
    tru = {k: np.array([2.0]) for k in ("t", "step", "x", "y", "z", "yaw")}
    m = {
        "no truth": _mission(states={0: est}),
        "no estimate": _mission(truth_vehicles={0: tru}),
        "no match": _mission(states={0: est}, truth_vehicles={0: tru}),  # steps 1 vs 2
    }[which]
    e = ekf_errors(m, 0)
    assert sorted(e) == sorted(["t", "x", "y", "z", "yaw", "trace_p"])
    assert all(v.size == 0 for v in e.values())


def test_percentiles_of_one_value_and_of_none():
    assert _percentiles(np.array([-3.0])) == {
        "p50": 3.0,
        "p90": 3.0,
        "p95": 3.0,
        "p99": 3.0,
        "max": 3.0,
        "mean": 3.0,
    }
    assert _percentiles(np.zeros(0)) is None


def test_mission_duration_is_the_completion_time_else_the_last_message():
    done = _event(12.0, EventType.MISSION_COMPLETE, value=1.0)
    assert mission_duration_s(_mission(world_events=[done], t_last_s=20.0)) == 12.0
    assert mission_duration_s(_mission(world_events=[], t_last_s=20.0)) == 20.0


def test_drops_count_only_released_water_per_uav():
    world = [
        _event(1.0, EventType.DROP, uav=0, fire_id=0, value=100.0),
        _event(2.0, EventType.DROP, uav=3, fire_id=0, value=100.0),
        _event(2.5, EventType.DROP, uav=3, fire_id=0, value=0.0),  # empty tank: not a drop
        _event(4.0, EventType.DROP, uav=0, fire_id=-1, value=50.0),
        _event(5.0, EventType.MISSION_COMPLETE, value=1.0),
    ]
    m = compute_metrics(_mission(world_events=world, t_last_s=5.0))
    assert m["drop_count"] == 3
    assert m["drops_per_uav"] == {"0": 2, "3": 1}
    assert m["drops_per_fire"] == {"0": 2, "missed": 1}
    assert m["drop_times_s"] == [1.0, 2.0, 4.0] and m["inter_drop_intervals_s"] == [1.0, 2.0]
    assert m["mission_duration_s"] == 5.0 and m["outcome"] == "complete"


def _grid(cells, origin=(100.0, -50.0), res=10.0, shape=(20, 20)):
    data = np.zeros(shape, dtype=np.int8)
    for i, j, v in cells:
        data[i, j] = v
    return {"t": 0.0, "origin": origin, "resolution": res, "data": data}


def test_true_outer_distance_of_single_cells_by_polar_geometry():
    """One burning cell: its bin holds its centre's distance; the bin is its polar angle."""
    g = _grid([(3, 7, 100)])  # centre (100 + 75, -50 + 35) = (175, -15)
    centre = (175.0, 25.0)  # 40 m above the cell: the cell is at -90 degrees
    out = true_outer_distance(g, centre, 8)
    assert np.isnan(np.delete(out, 6)).all()  # -90 deg = 270 deg: bin 6 of 8
    assert out[6] == pytest.approx(40.0)
    g2 = _grid([(3, 7, 60), (3, 9, 20)])  # burnt counts, wet does not
    out2 = true_outer_distance(g2, (145.0, -15.0), 4)  # 30 m to the right of the centre: bin 0
    assert out2[0] == pytest.approx(30.0) and np.isnan(out2[1:]).all()


def test_perimeter_errors_without_data_are_empty_with_both_keys():
    for fn in (perimeter_distance_error, perimeter_distance_error_raster):
        e = fn(_mission(), 0, 1)
        assert sorted(e) == ["error_m", "floor_m", "t"] and e["t"].size == 0 and e["error_m"].size == 0


def _state(steps, dx, lost):
    n = len(steps)
    s = np.asarray(steps)
    return {
        "t": 0.1 * s,
        "step": s,
        "x": s + dx,
        "y": np.zeros(n),
        "z": np.full(n, 100.0),
        "yaw": np.zeros(n),
        "P": _p([[1, 1, 1, 1]] * n),
        "received": np.arange(n) * 10,
        "lost": np.asarray(lost),
        "rejected": np.zeros(n, dtype=int),
    }


def _truth(steps):
    s = np.asarray(steps)
    n = len(steps)
    return {
        "t": 0.1 * s,
        "step": s,
        "x": s.astype(float),
        "y": np.zeros(n),
        "z": np.full(n, 100.0),
        "yaw": np.zeros(n),
        "status": np.ones(n, dtype=int),
    }


def test_metrics_of_two_uavs_by_hand():
    """UAV 0 is 1 m east of its truth at 3 steps, UAV 2 3 m at 2; packet counters are the last sample's."""
    world = [
        _event(1.0, EventType.DROP, uav=0, fire_id=0, value=100.0),
        _event(3.0, EventType.DROP, uav=2, fire_id=0, value=100.0),
        _event(5.0, EventType.MISSION_COMPLETE, value=0.0, detail="max_duration_s"),
    ]
    fleet = [_event(2.0, EventType.PEER_CRASHED, uav=0, peer=2, source="fleet")]
    m = compute_metrics(
        _mission(
            world_events=world,
            fleet_events=fleet,
            states={0: _state([1, 2, 3], 1.0, [0, 4, 5]), 2: _state([1, 2], 3.0, [1, 2])},
            truth_vehicles={0: _truth([1, 2, 3]), 2: _truth([1, 2])},
            t_last_s=6.0,
        )
    )
    assert m["packets"] == {
        "0": {"received": 20, "lost": 5, "rejected": 0},
        "2": {"received": 10, "lost": 2, "rejected": 0},
    }
    assert m["packets_lost_total"] == 7
    ekf = m["ekf_error"]
    assert ekf["samples"] == 5
    assert ekf["x"]["max"] == 3.0 and ekf["x"]["mean"] == pytest.approx((3 * 1.0 + 2 * 3.0) / 5)
    assert ekf["horizontal"]["p50"] == 1.0
    assert sorted(ekf["per_uav"]) == ["0", "2"]
    assert ekf["per_uav"]["2"]["x"]["mean"] == 3.0 and ekf["per_uav"]["0"]["yaw"]["max"] == 0.0
    assert ekf["units"] == {"x": "m", "y": "m", "z": "m", "yaw": "rad", "horizontal": "m"}
    assert m["event_counts"] == {"fleet.peer_crashed": 1, "world.drop": 2, "world.mission_complete": 1}
    assert m["outcome"] == "time_limit" and m["outcome_detail"] == "max_duration_s"
    assert m["peers_declared_crashed"] == [{"t_s": 2.0, "by_uav": 0, "peer_id": 2}]


def test_metrics_without_uavs_have_no_ekf_figures():
    m = compute_metrics(_mission(world_events=[], t_last_s=3.0))
    ekf = m["ekf_error"]
    assert ekf["samples"] == 0 and ekf["per_uav"] == {}
    assert all(ekf[k] is None for k in ("x", "y", "z", "yaw", "horizontal"))
    assert m["outcome"] == "incomplete" and m["mission_duration_s"] == 3.0


def test_perimeter_error_needs_both_the_map_and_the_truth():
    per = {"t": np.array([1.0]), "center": np.array([[0.0, 0.0]]), "outer": np.full((1, 8), 10.0)}
    tru = {"t": np.array([1.0]), "area": np.array([math.pi * 100.0])}  # radius 10 m
    assert perimeter_distance_error(_mission(perimeters={(0, 1): per}), 0, 1)["t"].size == 0
    assert perimeter_distance_error(_mission(truth_fires={1: tru}), 0, 1)["t"].size == 0
    both = perimeter_distance_error(_mission(perimeters={(0, 1): per}, truth_fires={1: tru}), 0, 1)
    # the worst angle lies between two of the 8 bin points, where their hull sags inside the circle
    sag = 10.0 * (1 - math.cos(math.pi / 8))
    assert both["t"].tolist() == [1.0] and both["error_m"] == pytest.approx([sag], rel=1e-3)
    m = compute_metrics(_mission(perimeters={(0, 1): per}, truth_fires={1: {**tru, "status": np.array([1])}}))
    assert m["perimeter_distance_error_m"] == {"0/1": pytest.approx(sag, rel=1e-3)}
    assert m["perimeter_distance_error_floor_m"] == {"0/1": 0.0}
    assert m["seed"] is None and m["uav_count"] == 0


def test_metrics_keys_and_the_fleet_event_lists():
    """The metrics.json keys (docs/recording.md); rejoins, crashes and scheduled outages as given;
    drops per UAV ordered by id as a number."""
    world = [
        _event(1.0, EventType.DROP, uav=10, fire_id=0, value=5.0),
        _event(2.0, EventType.DROP, uav=9, fire_id=0, value=5.0),
        _event(3.0, EventType.CRASH, uav=9, detail="terrain"),
    ]
    fleet = [
        _event(4.0, EventType.PEER_CRASHED, uav=10, peer=9, source="fleet"),
        _event(5.0, EventType.PEER_REJOINED, uav=10, peer=9, source="fleet"),
    ]
    outages = [{"start_s": 1.0, "end_s": 2.0}]
    m = compute_metrics(
        _mission(
            world_events=world, fleet_events=fleet, scenario={"name": "s", "comms": {"outages": outages}}
        )
    )
    assert set(m) == {
        "bag",
        "scenario",
        "seed",
        "uav_count",
        "outcome",
        "outcome_detail",
        "mission_duration_s",
        "drop_count",
        "drops_per_fire",
        "drops_per_uav",
        "drop_times_s",
        "mean_inter_drop_interval_s",
        "inter_drop_intervals_s",
        "extinction_times_s",
        "crash_events",
        "peers_declared_crashed",
        "peers_rejoined",
        "packets",
        "packets_lost_total",
        "packets_rejected_total",
        "link_outages_scheduled",
        "ekf_error",
        "perimeter_distance_error_m",
        "perimeter_distance_error_floor_m",
        "drops",
        "hits",
        "hit_rate",
        "water_released_kg",
        "water_on_burning_kg",
        "burned_area_m2",
        "contained_at_s",
        "event_counts",
        "recorder_closed_cleanly",
        "warnings",
        "min_separation_m",
        "collisions",
        "landed",
        "landing_error_m",
        "touchdown_spacing_m",
        "fires_total",
        "fires_active_at_end",
    }
    assert m["bag"] == "mem" and m["scenario"] == "s" and m["link_outages_scheduled"] == outages
    assert list(m["drops_per_uav"]) == ["9", "10"]
    assert m["crash_events"] == [{"t_s": 3.0, "uav_id": 9, "detail": "terrain"}]
    assert m["peers_rejoined"] == [{"t_s": 5.0, "by_uav": 10, "peer_id": 9}]
    assert m["packets_rejected_total"] == 0 and m["outcome_detail"] == "no MISSION_COMPLETE event in the bag"
    assert compute_metrics(_mission(scenario={"name": "s"}))["link_outages_scheduled"] == []
