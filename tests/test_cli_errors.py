"""A user's mistake on the command line gives one line on stderr and exit status 2, no traceback:
launch_agent, replay, report, the in-process runner and the benchmarks."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def one_line(r: subprocess.CompletedProcess, prefix: str, *words: str) -> str:
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert "Traceback" not in r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith(prefix), lines[0]
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]


def script(name: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(ROOT / "scripts" / name), *args], capture_output=True, text=True, timeout=120, check=False
    )


@pytest.mark.parametrize(
    ("args", "words"),
    [
        ((), ["UAV id"]),
        (("x",), ["UAV id", "got 'x'"]),
        (("3",), ["no parameters", "--params-file", "agent_3.yaml"]),
        (
            ("3", "--params-file", "/nonexistent/agent_3.yaml"),
            ["params file not found: /nonexistent/agent_3.yaml"],
        ),
        (("3", "--params-file"), ["--params-file needs a file"]),
    ],
)
def test_launch_agent_errors(args: tuple[str, ...], words: list[str]) -> None:
    one_line(script("launch_agent", *args), "launch_agent: error: ", *words)


def test_launch_agent_names_a_missing_scenario(tmp_path: Path) -> None:
    f = tmp_path / "agent_0.yaml"
    f.write_text("/**:\n  ros__parameters:\n    scenario_file: /nonexistent/s.yaml\n    uav_count: 2\n")
    one_line(
        script("launch_agent", "0", "--params-file", str(f)),
        "launch_agent: error: ",
        "scenario_file /nonexistent/s.yaml does not exist",
    )
    f.write_text("/**: [unclosed\n")
    one_line(script("launch_agent", "0", "--params-file", str(f)), "launch_agent: error: ", "is not YAML")


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("/nonexistent/bag",), ["bag not found: /nonexistent/bag"]),
        (("bag", "--rate"), ["--rate needs a value"]),
        (("bag", "--speed", "2"), ["unknown option --speed"]),
        (("a", "b"), ["one bag only"]),
    ],
)
def test_replay_errors(args: tuple[str, ...], words: list[str]) -> None:
    one_line(script("replay", *args), "replay: error: ", *words)


def test_report_without_a_bag_is_one_line() -> None:
    r = subprocess.run(
        [sys.executable, "-m", "fire_report"], capture_output=True, text=True, timeout=60, check=False
    )
    one_line(r, "report: error: ", "bag", "see report --help")


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("tiny_test", "--set", "nonsense"), ["expected FIELD=VALUE"]),
        (("no_such_scenario",), ["no scenario 'no_such_scenario'"]),
        (("tiny_test", "--set", "fires.model=bogus"), ["tiny_test.yaml", "fires.model", "'bogus'"]),
        (("tiny_test", "--uavs", "999"), ["uav_count must be in 0..255, got 999"]),
        (("tiny_test", "--set", "uavs.vehicle_model=glider"), ["uavs.vehicle_model", "'glider'"]),
        (
            ("tiny_test", "--set", "uavs.vehicle_model=coordinated_turn", "--set", "uavs.airframe=blimp"),
            ["uavs.airframe", "unknown airframe 'blimp'"],
        ),
        (
            (
                "tiny_test",
                "--set",
                "uavs.vehicle_model=coordinated_turn",
                "--set",
                "uavs.airframe.bank_max_deg=85",
            ),
            ["uavs.airframe.bank_max_deg", "(0, 80]", "85"],
        ),
        (
            (
                "tiny_test",
                "--set",
                "uavs.vehicle_model=coordinated_turn",
                "--set",
                "uavs.airframe.v_stall_mps=40",
            ),
            ["uavs.airframe.v_stall_mps", "must be < v_max_mps (30), got 40"],
        ),
        (
            ("tiny_test", "--set", "fires.drop_model=splash"),
            ["tiny_test.yaml", "fires.drop_model", "'splash'"],
        ),
        (
            ("tiny_test", "--set", "vehicle.drop_flow_lps=0"),
            ["tiny_test.yaml", "vehicle.drop_flow_lps", "> 0"],
        ),
        (
            (
                "tiny_test",
                "--set",
                "uavs.vehicle_model=coordinated_turn",
                "--set",
                "uavs.airframe.drop_flow_lps=-5",
            ),
            ["uavs.airframe.drop_flow_lps", "> 0", "-5"],
        ),
        (
            ("tiny_test", "--set", "uavs.vehicle_model=coordinated_turn", "--set", "uavs.airframe=tanker"),
            [
                "tiny_test.yaml",
                "lakes[0].diameter_m",
                "90 m is shorter than the tanker preset's 702 m scoop run",
            ],
        ),
        (
            ("grass_running_tanker", "--set", "lakes=[{x_m: 900, y_m: 4700, diameter_m: 700}]"),
            [
                "grass_running_tanker.yaml",
                "lakes[0].diameter_m",
                "700 m is shorter than the tanker preset's 702 m",
            ],
        ),
        (
            ("grass_running_tanker", "--set", "mission.prior_fires=known"),
            ["grass_running_tanker.yaml", "mission.prior_fires", "analytic fires only", "'raster'"],
        ),
    ],
)
def test_inprocess_errors(args: tuple[str, ...], words: list[str]) -> None:
    r = subprocess.run(
        [sys.executable, "-m", "fire_mission.inprocess", *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    one_line(r, "fire_mission.inprocess: error: ", *words)


def test_bench_bad_option_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    from fire_bench import bench

    with pytest.raises(SystemExit) as e:
        bench.main(["--only", "no_such_benchmark"])
    assert e.value.code == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("bench: error: argument --only: invalid choice: 'no_such_benchmark'")
