"""scripts/bench --only scale: each row carries the machine's speed of its moment (issue [scale])."""

import math

from fire_bench.bench import machine_probe
from fire_bench.markdown import write_markdown


def test_the_probe_gives_a_time_and_the_load_average():
    p = machine_probe(repeats=3)
    assert set(p) == {"probe_ms", "loadavg_1m"}
    assert math.isfinite(p["probe_ms"]) and p["probe_ms"] > 0
    assert math.isfinite(p["loadavg_1m"]) and p["loadavg_1m"] >= 0


def test_the_scale_table_shows_the_probe_of_each_row(tmp_path):
    rows = [
        {"uavs": 3, "steps_per_s": 90.0, "skeleton_steps_per_s": 290.0, "probe_ms": 21.5, "loadavg_1m": 1.25},
        {"uavs": 20, "steps_per_s": 9.5, "skeleton_steps_per_s": 18.0, "probe_ms": 33.75, "loadavg_1m": 12.5},
    ]
    results = {"scale": {"command": "scripts/bench --only scale", "mission_time_s": 15, "rows": rows}}
    md = tmp_path / "benchmarks.md"
    write_markdown(results, tmp_path, md)
    text = md.read_text()
    head = next(line for line in text.splitlines() if line.startswith("| UAVs"))
    cols = [c.strip() for c in head.strip("|").split("|")]
    assert cols[-2:] == ["probe ms", "load avg"]
    row20 = next(line for line in text.splitlines() if line.startswith("| 20 "))
    assert [c.strip() for c in row20.strip("|").split("|")][-2:] == ["33.75", "12.50"]
