"""fire_report on a synthetic bag whose answer is known (no ROS processes)."""

from __future__ import annotations

import dataclasses
import shutil

import numpy as np
import pytest
from fire_report import compute_metrics, load_mission
from fire_report.metrics import voronoi_labels, wrap_angle
from fire_report.synthetic import SyntheticMission, expected_metrics, write_synthetic_mission


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    path = tmp_path_factory.mktemp("bags") / "mission"
    spec = write_synthetic_mission(path)
    return path, spec


def test_metrics_match_the_known_answer(synthetic):
    path, spec = synthetic
    m = compute_metrics(load_mission(path))
    exp = expected_metrics(spec)
    assert m["drop_count"] == exp["drop_count"] == 5
    assert m["drops_per_fire"] == exp["drops_per_fire"] == {"0": 2, "1": 2, "missed": 1}
    assert m["mean_inter_drop_interval_s"] == pytest.approx(exp["mean_inter_drop_interval_s"]) == 1.75
    assert m["inter_drop_intervals_s"] == pytest.approx([1.5, 1.5, 1.0, 3.0])
    assert m["extinction_times_s"] == pytest.approx(exp["extinction_times_s"])
    assert [c["uav_id"] for c in m["crash_events"]] == exp["crash_uavs"]
    assert m["crash_events"][0]["t_s"] == pytest.approx(7.0)
    assert [(p["by_uav"], p["peer_id"]) for p in m["peers_declared_crashed"]] == exp["peers_declared_crashed"]
    assert {u: p["lost"] for u, p in m["packets"].items()} == exp["packets_lost"]
    assert m["packets_lost_total"] == exp["packets_lost_total"] == 7
    assert m["mission_duration_s"] == pytest.approx(exp["mission_duration_s"])
    assert m["outcome"] == exp["outcome"]
    assert m["seed"] == spec.seed and m["uav_count"] == spec.uav_count and m["scenario"] == "synthetic"
    for axis, err in exp["ekf_abs_error"].items():
        for key in ("p50", "p90", "p95", "p99", "max", "mean"):
            assert m["ekf_error"][axis][key] == pytest.approx(err, abs=1e-9), (axis, key)
    assert m["ekf_error"]["horizontal"]["p50"] == pytest.approx(np.hypot(1.5, 0.5))
    assert m["perimeter_distance_error_m"]["0/1"] == pytest.approx(exp["perimeter_error_m"], abs=1e-4)
    assert m["recorder_closed_cleanly"] is True and m["warnings"] == []


def test_mission_arrays(synthetic):
    path, spec = synthetic
    mission = load_mission(path)
    assert mission.uav_ids == [0, 1] and mission.fire_ids == [0, 1]
    trace = np.trace(mission.states[0]["P"], axis1=1, axis2=2)
    assert np.allclose(trace, expected_metrics(spec)["trace_p"])
    assert mission.states[1]["t"].max() < 7.0  # crashed UAV stops broadcasting
    assert mission.scenario["lakes"][0]["diameter_m"] == 90


def test_fire_estimates_read_alike_from_the_state_and_from_old_fires_topic(tmp_path, synthetic):
    """The fleet's fire picture rides in UavState; bags from before have it on /fleet/fires."""
    path, spec = synthetic
    assert spec.fires_in_state
    old = tmp_path / "old"
    write_synthetic_mission(old, dataclasses.replace(spec, fires_in_state=False))
    new_m, old_m = load_mission(path), load_mission(old)
    assert set(new_m.fire_estimates) == set(old_m.fire_estimates) == {(u, f) for u in (0, 1) for f in (0, 1)}
    for key, est in new_m.fire_estimates.items():
        assert len(est["t"]) > 10
        for col in ("t", "x", "y", "extent", "status"):
            assert np.array_equal(est[col], old_m.fire_estimates[key][col]), (key, col)
    m_new, m_old = compute_metrics(new_m), compute_metrics(old_m)
    m_new.pop("bag"), m_old.pop("bag")
    assert m_new == m_old


def test_outcome_incomplete_without_completion_event(tmp_path):
    spec = SyntheticMission(duration_s=2.0, drops=(), extinguished=(), crash=None, peer_crashed=None)
    path = tmp_path / "m"
    write_synthetic_mission(path, spec)
    mission = load_mission(path)
    mission.world_events = [e for e in mission.world_events if e.type != 10]
    m = compute_metrics(mission)
    assert m["outcome"] == "incomplete" and m["drop_count"] == 0 and m["mean_inter_drop_interval_s"] is None


def test_killed_recording_is_read_up_to_the_last_flush(tmp_path):
    """A copy of a bag taken while open (what SIGKILL leaves) is salvaged with a warning."""
    import fire_uav_recording as bag_io

    ts = bag_io.fleet_typestore()
    Ev = ts.types["fire_uav_msgs/msg/MissionEvent"]
    H, T = ts.types["std_msgs/msg/Header"], ts.types["builtin_interfaces/msg/Time"]
    w = bag_io.BagWriter(tmp_path / "live", custom_data={bag_io.KEY_SEED: "3"})
    w.open()
    c = w.add_connection("/world/events", Ev.__msgtype__, typestore=ts)
    for i in range(20):
        ev = Ev(
            header=H(stamp=T(sec=i, nanosec=0), frame_id="map"),
            type=2,
            uav_id=0,
            peer_id=-1,
            fire_id=0,
            x_m=0.0,
            y_m=0.0,
            value=1.0,
            detail="",
        )
        w.write(c, i * 10**9, ts.serialize_cdr(ev, Ev.__msgtype__))
        if i == 9:
            w.flush()
    shutil.copytree(tmp_path / "live", tmp_path / "killed")
    w.close()
    mission = load_mission(tmp_path / "killed")
    assert len(mission.world_events) == 10
    assert mission.custom_data[bag_io.KEY_SEED] == "3"
    assert mission.custom_data[bag_io.KEY_CLOSED] == "false"
    assert any("not closed" in w for w in mission.warnings)
    assert len(load_mission(tmp_path / "live").world_events) == 20


def test_voronoi_labels_partition_the_grid():
    rng = np.random.default_rng(1)
    sites = rng.uniform(0, 100, size=(5, 2))
    xs, ys, lab = voronoi_labels(sites, (0, 100), (0, 100), 2.0)
    assert lab.shape == (ys.size, xs.size)
    assert set(np.unique(lab)) <= set(range(5))
    gx, gy = np.meshgrid(xs, ys)
    d = np.hypot(gx[..., None] - sites[:, 0], gy[..., None] - sites[:, 1])
    assert np.all(d[np.arange(ys.size)[:, None], np.arange(xs.size), lab] <= d.min(axis=-1) + 1e-12)


def test_wrap_angle():
    assert np.allclose(
        wrap_angle(np.array([0.0, 3 * np.pi, -np.pi, 2 * np.pi + 0.1])), [0, np.pi, np.pi, 0.1]
    )


# --- the pure pieces on in-memory data (fast; what the mutation run of fire_report.metrics needs) ---
from fire_report.data import RecordedEvent, RecordedMission  # noqa: E402
from fire_report.metrics import (  # noqa: E402
    baseline_area,
    burned_area_series,
    containment_from_area,
    drop_outcomes,
    outcome,
    suppression_metrics,
    true_outer_distance,
)
from fire_uav_common.constants import EventType, FireStatus  # noqa: E402

ACTIVE, OUT = int(FireStatus.ACTIVE), int(FireStatus.EXTINGUISHED)


def _mission(**kw) -> RecordedMission:
    m = RecordedMission(path="mem", custom_data={}, scenario=kw.pop("scenario", {}), warnings=[], topics={})
    for k, v in kw.items():
        setattr(m, k, v)
    return m


def _drop(t, fire_id, kg, detail="", uav=0):
    return RecordedEvent(t, EventType.DROP, uav, -1, fire_id, 0.0, 0.0, kg, detail, "world")


def test_containment_from_area_is_sixty_quiet_seconds_after_the_last_growth():
    t = np.arange(0.0, 201.0, 1.0)
    grows_to_100 = np.minimum(t, 100.0)
    on = np.ones(t.size, bool)
    assert containment_from_area(t, grows_to_100, on, raster=True) == 160.0  # last growth at 100 s
    assert (
        containment_from_area(t[:160], grows_to_100[:160], on[:160], raster=True) is None
    )  # 59 s quiet at the end
    assert containment_from_area(t[:161], grows_to_100[:161], on[:161], raster=True) == 160.0  # exactly 60 s
    # a breach at 180 s: quiet again 60 s after it
    t3 = np.arange(0.0, 301.0, 1.0)
    breach = np.minimum(t3, 100.0) + np.where(t3 >= 180.0, 5.0, 0.0)
    assert containment_from_area(t3, breach, np.ones(t3.size, bool), raster=True) == 240.0
    # the first sample counts as growth: a flat history is contained 60 s after it starts
    flat = np.full(t.size, 7.0)
    assert containment_from_area(t + 10.0, flat, on, raster=True) == 70.0
    # no fire active: contained at once, growing or not
    assert containment_from_area(t, t.copy(), np.zeros(t.size, bool), raster=True) == 0.0
    out_at_50 = t < 50.0
    assert containment_from_area(t, np.minimum(t, 50.0), out_at_50, raster=True) == 50.0
    assert containment_from_area(np.zeros(0), np.zeros(0), np.zeros(0, bool), raster=True) is None
    # a shrinking area (a drop) is no growth
    down = np.maximum(100.0 - t, 0.0)
    assert containment_from_area(t, down, on, raster=True) == 60.0


def test_analytic_fires_are_contained_only_once_all_are_out():
    """An analytic fire does not spread cell by cell: a flat area while it burns is no containment
    (the no-fleet run of a two-fire mission said "contained at 60.1 s" with both fires burning)."""
    t = np.arange(0.0, 201.0, 1.0)
    flat = np.full(t.size, 7.0)
    assert containment_from_area(t, flat, np.ones(t.size, bool), raster=False) is None
    assert containment_from_area(t, flat, t < 120.0, raster=False) == 120.0
    assert containment_from_area(t, flat, np.zeros(t.size, bool), raster=False) == 0.0
    # the same flat history of a raster fire is contained after its 60 quiet seconds
    assert containment_from_area(t, flat, np.ones(t.size, bool), raster=True) == 60.0


def test_drop_outcomes_raster_and_analytic():
    events = [
        _drop(1.0, 0, 2000.0, "hit fires [0], 10 of 40 cells burning"),
        _drop(2.0, -1, 1000.0, "missed, 0 of 40 cells burning"),
        _drop(3.0, 0, 0.0, "empty tank, 3 of 40 cells burning"),  # released nothing: no drop
        _drop(4.0, 1, 500.0, "hit fires [1], 5 of 5 cells burning"),
        _drop(5.0, 1, 400.0, "no footprint, 0 of 0 cells burning"),
        RecordedEvent(6.0, EventType.EXTINGUISHED, 0, -1, 1, 0.0, 0.0, 1.0, "", "world"),
    ]
    r = drop_outcomes(events, is_raster=True)
    assert r == {
        "drops": 4,
        "hits": 3,
        "hit_rate": 0.75,
        "water_released_kg": 3900.0,
        "water_on_burning_kg": pytest.approx(500.0 + 500.0),
    }
    # analytic: no cell counts in the detail; a hit counts its whole load, a miss nothing
    analytic = [_drop(1.0, 0, 2000.0, "hit"), _drop(2.0, -1, 2000.0, "missed"), _drop(3.0, 2, 300.0)]
    a = drop_outcomes(analytic, is_raster=False)
    assert (a["drops"], a["hits"], a["water_on_burning_kg"]) == (3, 2, 2300.0)
    assert drop_outcomes(analytic, is_raster=True)["water_on_burning_kg"] == 0.0  # raster without counts
    assert drop_outcomes([], is_raster=True)["hit_rate"] is None


def test_burned_area_series_sums_the_fires_holding_each_last_sample():
    f0 = {
        "t": np.array([0.0, 10.0, 20.0]),
        "area": np.array([1.0, 2.0, 3.0]),
        "status": np.array([ACTIVE] * 3),
    }
    f1 = {"t": np.array([15.0, 25.0]), "area": np.array([10.0, 20.0]), "status": np.array([ACTIVE, OUT])}
    t, area, active = burned_area_series(_mission(truth_fires={0: f0, 1: f1, 2: {}}))
    assert t.tolist() == [0.0, 10.0, 15.0, 20.0, 25.0]
    assert area.tolist() == [1.0, 2.0, 12.0, 13.0, 23.0]  # fire 1 unseen before 15 s
    assert active.tolist() == [True, True, True, True, True]  # fire 0 still active at 25 s
    f0_out = dict(f0, status=np.array([ACTIVE, OUT, OUT]))
    _, _, active = burned_area_series(_mission(truth_fires={0: f0_out, 1: f1}))
    assert active.tolist() == [True, False, True, True, False]
    t, area, active = burned_area_series(_mission())
    assert t.size == area.size == active.size == 0 and active.dtype == bool


def test_suppression_metrics_and_baseline_from_a_mission():
    t = np.arange(0.0, 301.0, 1.0)
    fire = {"t": t, "area": 100.0 * np.minimum(t, 100.0), "status": np.full(t.size, ACTIVE)}
    drops = [
        _drop(20.0, 0, 2000.0, "hit fires [0], 10 of 40 cells burning"),
        _drop(40.0, -1, 2000.0, "missed"),
    ]
    raster = _mission(scenario={"fires": {"model": "raster"}}, truth_fires={0: fire}, world_events=drops)
    s = suppression_metrics(raster)
    assert (s["hit_rate"], s["water_on_burning_kg"], s["burned_area_m2"], s["contained_at_s"]) == (
        0.5,
        500.0,
        10000.0,
        160.0,
    )
    analytic = _mission(
        scenario={"fires": {"model": "analytic"}}, truth_fires={0: fire}, world_events=drops[:1]
    )
    assert suppression_metrics(analytic)["water_on_burning_kg"] == 500.0  # the count in the detail wins
    empty = suppression_metrics(_mission(scenario="not a dict"))
    assert empty["burned_area_m2"] is None and empty["contained_at_s"] is None
    assert baseline_area(None) is None and baseline_area(_mission()) is None
    b = baseline_area(_mission(truth_fires={0: fire}))
    assert b["t_s"].tolist() == t.tolist() and b["area_m2"][-1] == 10000.0


def test_true_outer_distance_per_bin_is_the_farthest_ignited_cell():
    res = 1.0
    data = np.zeros((21, 21), np.int8)
    data[10, 10:21] = 60  # a burnt ray from the centre cell toward +x, 10 cells long
    data[10:21, 10] = 100  # a burning ray toward +y
    data[0, 0] = 20  # wet: not burnt
    g = {"origin": (-10.5, -10.5), "resolution": res, "data": data}  # cell (10, 10) centred on (0, 0)
    d = true_outer_distance(g, (0.0, 0.0), 4)
    assert d[0] == pytest.approx(10.0) and d[1] == pytest.approx(10.0)  # bins [0, 90) and [90, 180) deg
    assert np.isnan(d[2]) and np.isnan(d[3])
    shifted = true_outer_distance(g, (5.0, 0.0), 4)  # seen from x = 5 m: the +x ray ends 5 m away
    assert shifted[0] == pytest.approx(5.0)
    assert np.isnan(true_outer_distance({**g, "data": np.zeros((3, 3), np.int8)}, (0, 0), 8)).all()


def test_outcome_names_the_last_completion_event():
    def done(v):
        return RecordedEvent(9.0, EventType.MISSION_COMPLETE, -1, -1, -1, 0, 0, v, f"value {v}", "world")

    assert outcome(_mission(world_events=[done(1.0)])) == ("complete", "value 1.0")
    assert outcome(_mission(world_events=[done(0.0)])) == ("time_limit", "value 0.0")
    assert outcome(_mission(world_events=[done(1.0), done(0.0)]))[0] == "time_limit"
    assert outcome(_mission())[0] == "incomplete"


def _disc_grid(t: float, r_m: float, res: float = 2.0, n: int = 100) -> dict:
    c = (np.arange(n) + 0.5) * res
    xx, yy = np.meshgrid(c, c)
    data = np.where(np.hypot(xx - 100.0, yy - 100.0) <= r_m, 60, 0).astype(np.int8)
    return {"t": t, "origin": (0.0, 0.0), "resolution": res, "data": data}


def test_raster_perimeter_error_uses_the_grid_nearest_in_time_around_the_maps_centre():
    from fire_report.metrics import perimeter_distance_error_raster

    bins = 24
    grids = [_disc_grid(0.0, 30.0), _disc_grid(100.0, 40.0), _disc_grid(200.0, 60.0)]
    outer = np.array([np.full(bins, 40.0), np.full(bins, 70.0), np.full(bins, np.nan), np.full(bins, 30.0)])
    per = {
        "t": np.array([90.0, 160.0, 170.0, 20.0]),  # nearest grids: 100 s (r 40), 200 s (r 60), -, 0 s (r 30)
        "center": np.array([[100.0, 100.0]] * 4),
        "outer": outer,
    }
    m = _mission(fire_grids=grids, perimeters={(0, 7): per})
    e = perimeter_distance_error_raster(m, 0, 7)
    assert e["t"].tolist() == [90.0, 160.0, 20.0]  # the all-unknown map is left out
    # within about a cell (2 m) of the disc, and of the offset: the worst angle finds a square's
    # corner of the hull and the sag between the 24 bins
    assert e["error_m"] == pytest.approx([0.0, 10.0, 0.0], abs=3.0)
    assert e["error_m"][1] > 8.0
    # seen from a centre 20 m off, a map of a 40 m circle is wrong by up to 20 m (and a cell)
    off = {**per, "center": np.array([[120.0, 100.0]] * 4)}
    e_off = perimeter_distance_error_raster(_mission(fire_grids=grids, perimeters={(0, 7): off}), 0, 7)
    assert 5.0 < e_off["error_m"][0] < 22.0
    assert perimeter_distance_error_raster(m, 0, 8)["t"].size == 0  # no such map
    assert (
        perimeter_distance_error_raster(_mission(perimeters={(0, 7): per}), 0, 7)["t"].size == 0
    )  # no grids
