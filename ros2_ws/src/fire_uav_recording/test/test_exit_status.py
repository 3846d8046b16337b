"""Exit status of the recording package's nodes (their ``main``, in this process, on a private ROS
domain; no other process): a bad parameter is one error line naming it and status 2, the
project's rule for every bad input; a bag error (the recorder's output exists already, a bag that
cannot be opened) keeps status 1."""

from __future__ import annotations

import importlib

import pytest

pytest.importorskip("rclpy")


def _main(module: str, args: list[str], domain: int, monkeypatch) -> int:
    monkeypatch.setenv("ROS_DOMAIN_ID", str(domain))  # main() inits rclpy's context from the environment
    return importlib.import_module(f"fire_uav_recording.{module}").main(["--ros-args", *args])


def _one_error_line(stderr: str, needle: str) -> None:
    lines = [ln for ln in stderr.splitlines() if "[ERROR]" in ln]
    assert len(lines) == 1 and needle in lines[0], stderr
    assert "Traceback" not in stderr, stderr


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["-p", "uav_count:=256"], "uav_count: must be <= 255"),  # the node's own check
        (["-p", "stop_drain_wall_s:=61.0"], "stop_drain_wall_s"),
        (["-p", "seed:=-1"], "seed"),  # refused by rclpy against the declared range
        (["-p", "flush_period_wall_s:=fast"], "flush_period_wall_s"),  # refused by rclpy: type
    ],
)
def test_the_recorder_exits_2_on_a_bad_parameter_and_makes_no_bag(
    args, needle, tmp_path, own_domain, monkeypatch, capfd
):
    bag = tmp_path / "bag"
    assert _main("recorder_node", ["-p", f"output:={bag}", *args], own_domain, monkeypatch) == 2
    _one_error_line(capfd.readouterr().err, needle)
    assert not bag.exists()


def test_a_scenario_file_the_recorder_cannot_read_is_a_bad_parameter_and_leaves_no_bag(
    tmp_path, own_domain, monkeypatch, capfd
):
    """Before: the bag was made before the scenario's landscape was read, so the error left an
    unclosed bag directory behind, and the same command run again was refused as "exists already"."""
    scenario = tmp_path / "broken.yaml"
    scenario.write_text("fire: [\n", encoding="utf8")
    bag = tmp_path / "bag"
    args = ["-p", f"output:={bag}", "-p", f"scenario_file:={scenario}"]
    assert _main("recorder_node", args, own_domain, monkeypatch) == 2
    _one_error_line(capfd.readouterr().err, "parameter scenario_file")
    assert not bag.exists()


def test_the_recorder_refuses_an_existing_output_with_status_1(tmp_path, own_domain, monkeypatch, capfd):
    bag = tmp_path / "bag"
    bag.mkdir()
    assert _main("recorder_node", ["-p", f"output:={bag}"], own_domain, monkeypatch) == 1
    _one_error_line(capfd.readouterr().err, "exists already")
    assert list(bag.iterdir()) == []  # untouched


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["-p", "discovery_period_wall_s:=0.0"], "discovery_period_wall_s"),
        (["-p", "port:=70000"], "port"),  # refused by rclpy against the declared range
        (["-p", "scenario_file:=/nonexistent/scenario.yaml"], "parameter scenario_file"),
    ],
)
def test_the_foxglove_bridge_exits_2_on_a_bad_parameter(args, needle, own_domain, monkeypatch, capfd):
    pytest.importorskip("foxglove")
    assert _main("foxglove_bridge_node", args, own_domain, monkeypatch) == 2
    _one_error_line(capfd.readouterr().err, needle)


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        ([], "parameter bag: required"),
        (["-p", "bag:=/x", "-p", "start_s:=-1.0"], "start_s"),
        (["-p", "bag:=/x", "-p", "rate:=0.0"], "rate"),  # refused by rclpy against the declared range
    ],
)
def test_the_replay_exits_2_on_a_bad_parameter(args, needle, own_domain, monkeypatch, capfd):
    assert _main("replay_node", args, own_domain, monkeypatch) == 2
    _one_error_line(capfd.readouterr().err, needle)


def test_the_replay_exits_1_on_a_bag_it_cannot_open(tmp_path, own_domain, monkeypatch, capfd):
    missing = tmp_path / "no_bag"
    assert _main("replay_node", ["-p", f"bag:={missing}"], own_domain, monkeypatch) == 1
    _one_error_line(capfd.readouterr().err, str(missing))
