"""fire_bench.suppression --from-runs: the summary of finished cases and the page's raster section."""

import json

import pytest
from fire_bench.markdown import _suppression_section
from fire_bench.suppression import main, parse_case, read_runs


def _section(out) -> str:
    return "\n".join(_suppression_section(json.loads((out / "suppression.json").read_text())))


def _run(sc: str, uavs: int, seed: int, tactic: str, burned: float) -> dict:
    return {
        "scenario": sc,
        "uavs": uavs,
        "seed": seed,
        "tactic": tactic,
        "duration_s": 900.0,
        "burned_area_m2": burned,
        "hit_rate": None if uavs == 0 else 1.0,
        "drops": 0 if uavs == 0 else 30,
        "water_on_burning_kg": 0.0,
        "contained_at_s": None if uavs == 0 else 170.0,
        "crashes": 0,
        "area_t_s": [0.0, 900.0],
        "area_m2": [burned / 2, burned],
        "wall_s": 10.0,
    }


def test_from_runs_summarises_into_the_raster_section(tmp_path):
    runs = tmp_path / "suppression_runs.jsonl"
    rows = [
        _run("grass_brush_hill", 0, 1, "none", 235600.0),
        _run("grass_brush_hill", 6, 1, "head", 27400.0),
        _run("grass_running", 0, 1, "none", 531600.0),
    ]
    runs.write_text("".join(json.dumps(r) + "\n" for r in rows))
    assert main(["--from-runs", str(runs), "--out", str(tmp_path / "bench")]) == 0
    text = _section(tmp_path / "bench")
    assert "| grass_brush_hill | head | 1 | 23.56 | 2.74 | 0.12 |" in text  # 27400 / 235600 = 0.116
    assert "| 0 | 53.16 |" in text  # the fleet-size table (grass_running, no fleet)
    assert (tmp_path / "bench" / "suppression_area.png").is_file()


def test_a_broken_runs_file_names_the_line(tmp_path):
    p = tmp_path / "suppression_runs.jsonl"
    p.write_text('{"scenario": "x"}\n{not json\n')
    with pytest.raises(SystemExit, match=r"suppression_runs.jsonl:2: not a JSON object"):
        read_runs(p)


def test_from_runs_needs_the_file(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        main(["--from-runs", str(tmp_path / "missing.jsonl"), "--out", str(tmp_path)])
    assert e.value.code == 2
    (line,) = capsys.readouterr().err.strip().splitlines()  # one line, no usage block
    assert "--from-runs: no file" in line


def test_case_spec():
    assert parse_case("grass_running:10:1:head") == ("grass_running", 10, 1, "head", 900.0)
    for bad, why in [
        ("grass_running:6:1", "expected SCENARIO:UAVS:SEED:TACTIC"),
        ("ff_two_fires:6:1:head", "scenario must be one of"),
        ("grass_running:6:1:frontal", "tactic must be one of"),
        ("grass_running:six:1:head", "UAVS and SEED must be integers"),
        ("grass_running:-1:1:head", "UAVS must be >= 0"),
    ]:
        with pytest.raises(SystemExit, match=why):
            parse_case(bad)


def test_the_fleet_size_table_has_a_column_per_tactic(tmp_path):
    """grass_running seed 1: the no-fleet area under both tactics, each fleet size's head and flank
    runs on one row with their containment times; other scenarios and seeds stay out of it."""
    runs = tmp_path / "suppression_runs.jsonl"
    flank3 = dict(_run("grass_running", 3, 1, "flank", 250000.0), contained_at_s=700.0)
    head3 = dict(_run("grass_running", 3, 1, "head", 450000.0), contained_at_s=None)
    rows = [
        _run("grass_running", 0, 1, "none", 531600.0),
        flank3,
        head3,
        _run("grass_running", 6, 2, "head", 111100.0),  # seed 2: not a fleet-size row
        _run("grass_brush_hill", 3, 1, "head", 99900.0),  # another scenario: neither
    ]
    runs.write_text("".join(json.dumps(r) + "\n" for r in rows))
    assert main(["--from-runs", str(runs), "--out", str(tmp_path / "bench")]) == 0
    text = _section(tmp_path / "bench")
    assert "| 0 | 53.16 | - | 53.16 | - |" in text
    assert "| 3 | 45.00 | - | 25.00 | 700.00 |" in text
    assert "11.11" not in text.split("Burned area at 900 s vs fleet size")[1] and "9.99" not in text
    assert (tmp_path / "bench" / "suppression_fleet_size.png").is_file()
