"""A fixed-wing scoops on one straight pass: a scenario's lake shorter than the airframe's scoop
run is refused with one line naming the file and the field; a landscape's water body that short
is left out with a note, and a fleet left with no lake at all is refused."""

from __future__ import annotations

from pathlib import Path

import pytest
from fire_uav_common.scenario import AIRFRAMES, ScenarioError, load_scenario

ROOT = Path(__file__).resolve().parents[4]
SCENARIOS = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios"
FF = SCENARIOS / "ff_two_fires.yaml"
WORCESTER = SCENARIOS / "worcester_vt.yaml"
FIXED_WING = {"uavs.vehicle_model": "coordinated_turn"}


def test_the_presets_scoop_runs() -> None:
    # the scoop time water / rate flown at 1.3 V_S: small_uav 10 kg / 2 kg/s x 15.6 m/s,
    # tanker 3000 kg / 200 kg/s x 46.8 m/s
    assert AIRFRAMES["small_uav"].scoop_run_m == pytest.approx(78.0)
    assert AIRFRAMES["tanker"].scoop_run_m == pytest.approx(702.0)


def test_ff_lake_serves_ff_paper_and_the_small_uav() -> None:
    assert [lk.diameter_m for lk in load_scenario(FF).lakes] == [90.0]
    assert [lk.diameter_m for lk in load_scenario(FF, overrides=FIXED_WING).lakes] == [90.0]


def test_ff_lake_is_too_short_for_the_tanker() -> None:
    with pytest.raises(ScenarioError) as e:
        load_scenario(FF, overrides={**FIXED_WING, "uavs.airframe": "tanker"})
    assert str(e.value) == (
        f"{FF}: lakes[0].diameter_m: 90 m is shorter than the tanker preset's 702 m scoop run "
        "(a fixed-wing scoops on one straight pass over the water)"
    )


def test_the_threshold_is_the_scoop_run_and_names_the_short_lake() -> None:
    lakes = [{"x_m": 50.0, "y_m": 50.0, "diameter_m": 78.0}, {"x_m": 500.0, "y_m": 500.0, "diameter_m": 77.0}]
    ok = load_scenario(FF, overrides={**FIXED_WING, "lakes": lakes[:1]})
    assert [lk.diameter_m for lk in ok.lakes] == [78.0]  # exactly the run: usable
    with pytest.raises(
        ScenarioError, match=r"lakes\[1\]\.diameter_m: 77 m is shorter than the small_uav preset's 78 m"
    ):
        load_scenario(FF, overrides={**FIXED_WING, "lakes": lakes})
    # ff_paper hovers over the water: any lake serves
    assert len(load_scenario(FF, overrides={"lakes": lakes}).lakes) == 2


def test_a_preset_with_fields_replaced_names_uavs_airframe() -> None:
    # half the refill rate doubles the run: 156 m > the 90 m lake
    with pytest.raises(
        ScenarioError, match=r"lakes\[0\]\.diameter_m: 90 m is shorter than uavs.airframe's 156 m scoop run"
    ):
        load_scenario(FF, overrides={**FIXED_WING, "uavs.airframe.refill_rate_kgps": 1.0})


def _tanker(refill_rate_kgps: float) -> dict:
    return {**FIXED_WING, "uavs.airframe": {"preset": "tanker", "refill_rate_kgps": refill_rate_kgps}}


def test_a_landscape_pond_counts_by_its_longest_run_not_its_disc() -> None:
    pond = load_scenario(WORCESTER).lakes[0]
    disc, run = pond.diameter_m, pond.longest_run.length_m
    assert disc == pytest.approx(270.0) and run > 400.0
    # a scoop run between the disc and the run: the pond serves
    rate = 3000.0 * 46.8 / (0.5 * (disc + run))
    s = load_scenario(WORCESTER, overrides=_tanker(rate))
    assert len(s.lakes) == 1 and s.notes == ()


def test_no_lake_left_for_the_tanker_is_one_line() -> None:
    with pytest.raises(ScenarioError) as e:
        load_scenario(WORCESTER, overrides={**FIXED_WING, "uavs.airframe": "tanker"})
    msg = str(e.value)
    assert "\n" not in msg
    assert msg.startswith(f"{WORCESTER}: fires.raster.landscape: no lake left for refills")
    assert "the tanker preset's 702 m scoop run" in msg


def test_a_short_pond_is_left_out_with_a_note_when_a_written_lake_serves() -> None:
    big = [{"x_m": 1150.0, "y_m": 900.0, "diameter_m": 560.0}]  # a disc: its run is its diameter
    rate = 3000.0 * 46.8 / 500.0  # a 500 m scoop run: longer than the pond's run
    s = load_scenario(WORCESTER, overrides={**_tanker(rate), "lakes": big})
    assert [lk.diameter_m for lk in s.lakes] == [560.0]
    (note,) = s.notes
    assert note.startswith("fires.raster.landscape: open water at")
    assert "is shorter than uavs.airframe's 500 m scoop run" in note
