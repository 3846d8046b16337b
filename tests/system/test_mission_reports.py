"""Reports of real missions, with their sections: an FF, a monitoring (monitor_grass) and a search
(search_area) mission through the real runner; each report has the sections of the capabilities
the mission used and no other, and every figure it lists exists and is non-empty (the browser
test, tests/test_report_browser.py, checks that figures load in Chromium)."""

from __future__ import annotations

import pytest
from fire_report import write_report
from fire_uav_recording import KEY_LOG_TIME_OFFSET_NS, open_bag
from mission_util import assert_no_survivors, run_mission

PM_HEADING, CP_HEADING = "<h2>Perimeter monitoring (PM)</h2>", "<h2>Coverage search (CP)</h2>"
FF_FIGURES = {"voronoi_phases.png", "tracks.png", "ekf_error.png", "drops.png"}


def _report(tmp_path, ros_env, scenario: str, *args: str, timeout_s: float) -> tuple[dict, str, set[str]]:
    summary, err = run_mission(tmp_path / "run", ros_env, scenario, *args, timeout_s=timeout_s)
    assert_no_survivors(summary)
    bag = tmp_path / "run" / "bag"
    with open_bag(bag) as b:
        topics = set(b.topics)
        custom = dict(b.custom_data)
    assert "/viz/perimeter" in topics, f"perimeter_viewer's topic not recorded: {sorted(topics)}"
    metrics = write_report(bag, tmp_path / "report")
    page = (tmp_path / "report" / "index.html").read_text(encoding="utf8")
    for name in metrics["figures"]:
        f = tmp_path / "report" / name
        assert f.is_file() and f.stat().st_size > 0, f"figure {name} missing or empty"
        assert f'src="{name}"' in page
    metrics["_custom"] = custom
    return metrics, page, set(metrics["figures"])


@pytest.mark.system
@pytest.mark.slow
def test_ff_report_has_the_ff_figures_only(tmp_path, ros_env, procs):
    m, page, figs = _report(tmp_path, ros_env, "tiny_test", "--wall-epoch", timeout_s=600.0)
    assert FF_FIGURES <= figs, sorted(figs)
    assert PM_HEADING not in page and CP_HEADING not in page and m["sections"] == {}
    # --wall-epoch: the recorder stamped the bag from the wall clock (offset stored, taken off on read)
    assert int(m["_custom"].get(KEY_LOG_TIME_OFFSET_NS, "0")) > 1_600_000_000 * 10**9
    assert m["mission_duration_s"] < 1e6  # sim seconds, not the epoch


@pytest.mark.system
@pytest.mark.slow
def test_monitoring_report_has_the_pm_section(tmp_path, ros_env, procs):
    m, page, figs = _report(tmp_path, ros_env, "monitor_grass", timeout_s=900.0)
    assert PM_HEADING in page and CP_HEADING not in page
    assert {"pm_track.png", "pm_distance_error.png", "pm_direction.png"} <= figs
    mon = m["sections"]["pm"]["monitors"]
    assert mon, "no monitor in the PM section"
    for key, v in mon.items():
        assert v["distance_error_samples"] > 0, key
        assert v["average_max_distance_error_m"] >= 0.0


@pytest.mark.system
@pytest.mark.slow
def test_search_report_has_the_cp_section(tmp_path, ros_env, procs):
    m, page, figs = _report(tmp_path, ros_env, "search_area", timeout_s=1800.0)
    assert CP_HEADING in page
    assert {"cp_partition.png", "cp_cost.png"} <= figs
    cp = m["sections"]["cp"]
    assert cp["evaluations"] >= 2 and cp["best"]["cost"] <= cp["first_cost"]
    assert set(cp["planned_paths"]) == set(cp["partition"]) == {"0", "1", "2"}
    assert cp["partition_max_relative_area_error"] < 0.2  # balanced cells (CP Eq. 8), recomputed
