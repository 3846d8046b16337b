"""``scripts/study``'s bad input: one line naming the study file and the field, exit status 2;
a results directory of another study, or of the study before its file changed, is refused."""

from __future__ import annotations

import pytest
import yaml
from fire_study.cli import main
from fire_study.spec import load_study, mission_overrides
from fire_study.store import ResultStore

GOOD = {
    "name": "t",
    "scenarios": ["tiny_test"],
    "tactics": ["head", "flank"],
    "uavs": [2],
    "seeds": [1, 2],
    "time_limit_s": 5,
}


def _write(tmp_path, doc) -> str:
    p = tmp_path / "study.yaml"
    p.write_text(yaml.safe_dump(doc))
    return str(p)


@pytest.mark.parametrize(
    ("change", "field", "what"),
    [
        ({"scenarios": ["no_such_fire"]}, "scenarios[0]", "unknown scenario 'no_such_fire' (known: "),
        ({"tactics": ["head", "tail"]}, "tactics[1]", "unknown tactic 'tail' (known: head, flank, auto)"),
        ({"colour": "red"}, "colour", "unknown field (known: "),
        ({"tactics": []}, "tactics", "is empty: a study needs at least one value (an empty arm)"),
        ({"uavs": []}, "uavs", "is empty"),
        ({"seeds": [1, 2.5]}, "seeds[1]", "must be an integer, got 2.5"),
        ({"seeds": ["one"]}, "seeds[0]", "must be an integer, got 'one'"),
        ({"seeds": [-1]}, "seeds[0]", "must be >= 0, got -1"),
        ({"seeds": {"first": 1, "count": 0}}, "seeds.count", "must be >= 1, got 0"),
        ({"uavs": [0]}, "uavs[0]", "must be >= 1, got 0"),
        ({"measures": ["smoke"]}, "measures[0]", "unknown measure 'smoke'"),
        ({"overrides": {"mission.tactic": "head"}}, "overrides.mission.tactic", "is set by the study's"),
        ({"overrides": {"mission.no_such": 1}}, "overrides", "scenario tiny_test: "),
        ({"fire_variation": {"rain": 1}}, "fire_variation", "unknown key 'rain'"),
        ({"time_limit_s": -5}, "time_limit_s", "must be a number > 0, got -5"),
        ({"name": None}, "name", "missing"),
    ],
)
def test_bad_input_is_one_line_naming_file_and_field_exit_2(tmp_path, capsys, change, field, what) -> None:
    doc = dict(GOOD, **change)
    path = _write(tmp_path, doc)
    assert main([path, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert err.startswith(f"study: error: {path}: {field}: ")
    assert what in err
    assert not (tmp_path / "out").exists()


def test_missing_and_unparsable_study_files(tmp_path, capsys) -> None:
    assert main([str(tmp_path / "none.yaml")]) == 2
    assert "none.yaml: cannot read" in capsys.readouterr().err
    p = tmp_path / "bad.yaml"
    p.write_text("name: [unclosed\n")
    assert main([str(p)]) == 2
    err = capsys.readouterr().err.strip()
    assert "bad.yaml: invalid YAML" in err and "\n" not in err


def test_results_of_a_changed_or_other_study_are_refused(tmp_path) -> None:
    out = tmp_path / "out"
    ResultStore(out, load_study(_write(tmp_path, GOOD)))  # starts results.jsonl
    changed = load_study(_write(tmp_path, dict(GOOD, seeds=[1, 2, 3])))
    with pytest.raises(ValueError, match=r"study\.yaml: the results in .*results\.jsonl belong to this study as it "
                       r"was before the file changed .* use another --out directory"):  # fmt: skip
        ResultStore(out, changed)
    other = load_study(_write(tmp_path, dict(GOOD, name="u")))
    with pytest.raises(ValueError, match="belong to another study \\('t'\\)"):
        ResultStore(out, other)
    # a comment or the measures do not change what the missions give: not refused
    p = tmp_path / "study.yaml"
    p.write_text("# note\n" + yaml.safe_dump(dict(GOOD, measures=["crashes"])))
    ResultStore(out, load_study(p))


def test_the_tactic_fleet_size_and_airframe_never_change_the_fire_of_a_seed(tmp_path) -> None:
    doc = dict(GOOD, scenarios=["grass_running"], tactics=["head", "flank", "auto"], uavs=[3, 10],
               airframes={"default": {}, "small_tank": {"vehicle.water_capacity_kg": 1000.0}},
               fire_variation={"wind_speed_sd_mps": 0.3, "wind_direction_sd_deg": 10, "ignition_sd_m": 20})  # fmt: skip
    s = load_study(_write(tmp_path, doc))
    fire_keys = ("fires.raster.wind", "fires.raster.ignitions")
    for seed in (1, 2):
        fires = {
            repr([mission_overrides(s, "grass_running", af, n, t, seed)[k] for k in fire_keys])
            for af in ("default", "small_tank")
            for n in (3, 10)
            for t in ("head", "flank", "auto")
        }
        assert len(fires) == 1
    one = mission_overrides(s, "grass_running", "default", 3, "head", 1)
    two = mission_overrides(s, "grass_running", "default", 3, "head", 2)
    assert one["fires.raster.wind"] != two["fires.raster.wind"]  # seeds vary the fire
    assert one["fires.raster.ignitions"] != two["fires.raster.ignitions"]


def test_report_only_without_results_is_one_line_exit_2(tmp_path, capsys) -> None:
    path = _write(tmp_path, GOOD)
    assert main([path, "--out", str(tmp_path / "none"), "--report-only"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("none/results.jsonl: no such results file: nothing to report") and "\n" not in err
    assert not (tmp_path / "none").exists()


def test_a_gridded_wind_is_not_varied_one_line_exit_2(tmp_path, capsys) -> None:
    from fire_uav_agent.testing.harness import scenario_path

    sc = yaml.safe_load(scenario_path("worcester_vt").read_text())
    sample = "wind/worcester_vt/worcester_vt_270_8_120m"
    sc["fires"]["raster"]["wind"] = [
        {"start_s": -600.0, "grid": {"vel": f"{sample}_vel.asc", "ang": f"{sample}_ang.asc"}}
    ]
    (tmp_path / "gridded.yaml").write_text(yaml.safe_dump(sc))
    doc = dict(GOOD, scenarios=["gridded.yaml"], fire_variation={"wind_direction_sd_deg": 10})
    assert main([_write(tmp_path, doc)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert (
        "study.yaml: fire_variation: scenario gridded.yaml: gridded.yaml: fires.raster.wind[0] is a wind grid"
        in err
    )
    # without wind variation (ignitions only) the same scenario is accepted by the variation
    from fire_study.variation import fire_variation

    assert "fires.raster.wind" not in fire_variation(tmp_path / "gridded.yaml", 1, {"ignition_sd_m": 20.0})
