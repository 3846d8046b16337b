"""scripts/bench --only scale: each row carries one core's speed of its moment."""

import math

from fire_bench.bench import machine_probe
from fire_bench.markdown import write_markdown


def test_the_probe_gives_a_time():
    p = machine_probe(repeats=3)
    assert set(p) == {"probe_ms"}
    assert math.isfinite(p["probe_ms"]) and p["probe_ms"] > 0


def test_the_scale_table_shows_the_probe_of_each_row(tmp_path):
    rows = [
        {"uavs": 3, "steps_per_s": 90.0, "skeleton_steps_per_s": 290.0, "probe_ms": 21.5},
        {"uavs": 20, "steps_per_s": 9.5, "skeleton_steps_per_s": 18.0, "probe_ms": 33.75},
    ]
    results = {"scale": {"command": "scripts/bench --only scale", "mission_time_s": 15, "rows": rows}}
    md = tmp_path / "benchmarks.md"
    write_markdown(results, tmp_path, md)
    text = md.read_text()
    head = next(line for line in text.splitlines() if line.startswith("| UAVs"))
    cols = [c.strip() for c in head.strip("|").split("|")]
    assert cols[-1] == "probe ms"
    row20 = next(line for line in text.splitlines() if line.startswith("| 20 "))
    assert [c.strip() for c in row20.strip("|").split("|")][-1] == "33.75"


def test_an_only_run_keeps_the_pages_machine_and_labels_its_own_section(tmp_path, monkeypatch):
    """Sessions run on different hosts (AMD EPYC one day, Intel Xeon another): a --only run must
    not relabel the sections it did not run, and its own section names where it ran."""
    import argparse
    import json

    from fire_bench import bench

    (tmp_path / "results.json").write_text(json.dumps({"machine": {"cpu": "old host"}, "ekf": {"x": 1}}))
    monkeypatch.setitem(bench.BENCHES, "dummy", (lambda quick: {"y": 2}, 0.0, 0.0, "a stand-in"))
    args = argparse.Namespace(
        only=["dummy"], out=tmp_path, quick=False, no_page=True, scale_sizes=None, scale_duration=None
    )
    assert bench._run(args, ["dummy"], executor=None) == 0
    got = json.loads((tmp_path / "results.json").read_text())
    assert got["machine"] == {"cpu": "old host"} and got["ekf"] == {"x": 1}
    assert got["dummy"]["machine"]["cpu"] == bench.machine()["cpu"]
    assert got["dummy"]["machine"]["date"]
    md = tmp_path / "benchmarks.md"
    write_markdown({"scale": {"command": "c", "mission_time_s": 15, "rows": [], "machine": {"cpu": "Xeon",
                   "cores": 2, "commit": "abc1234", "date": "2026-12-03 16:57 UTC"}}}, tmp_path, md)  # fmt: skip
    assert "Ran on: Xeon, 2 cores; commit abc1234, 2026-12-03 16:57 UTC." in md.read_text()
