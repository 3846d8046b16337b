"""fire_report on a synthetic bag whose answer is known (no ROS processes)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from fire_report import compute_metrics, load_mission, write_report
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


def test_outcome_incomplete_without_completion_event(tmp_path):
    spec = SyntheticMission(duration_s=2.0, drops=(), extinguished=(), crash=None, peer_crashed=None)
    path = tmp_path / "m"
    write_synthetic_mission(path, spec)
    mission = load_mission(path)
    mission.world_events = [e for e in mission.world_events if e.type != 10]
    m = compute_metrics(mission)
    assert m["outcome"] == "incomplete" and m["drop_count"] == 0 and m["mean_inter_drop_interval_s"] is None


def test_report_writes_every_figure_and_page(synthetic, tmp_path):
    path, _ = synthetic
    metrics = write_report(path, tmp_path / "out")
    out = tmp_path / "out"
    html = (out / "index.html").read_text()
    assert (out / "metrics.json").is_file()
    names = set(metrics["figures"])
    assert {
        "voronoi_phases.png",
        "ekf_error.png",
        "covariance_trace.png",
        "tracks.png",
        "drops.png",
        "fire_0_estimates.png",
        "fire_1_estimates.png",
        "perimeter.png",
        "faults.png",
    } <= names
    for name in names:
        assert (out / name).stat().st_size > 1000
        assert f'src="{name}"' in html


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
