"""The runner waits for its helper nodes (recorder, perimeter viewer, Foxglove bridge) while their
processes run, not for a fixed 20 s: under load a Python node's imports alone took longer, and
the mission failed before step 0 with nothing wrong. It still stops at once when the process
exits, and at the run's --wall-timeout. A fake clock stands for time.monotonic: no test waits."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from fire_mission import runner
from fire_mission.procs import MissionError


class _Clock:
    def __init__(self) -> None:
        self.t_s = 1000.0

    def __call__(self) -> float:
        return self.t_s


def _setup(monkeypatch, appears_at_s: float | None, exits_at_s: float | None = None):
    """A supervisor whose graph shows the node from ``appears_at_s`` on, a process that exits at
    ``exits_at_s``; each spin advances the fake clock by its timeout."""
    clock = _Clock()
    t0 = clock.t_s
    monkeypatch.setattr(runner.time, "monotonic", clock)

    def names() -> list[str]:
        seen = appears_at_s is not None and clock.t_s - t0 >= appears_at_s
        return ["world", "recorder"] if seen else ["world"]

    def spin_once(timeout_sec: float) -> None:
        clock.t_s += timeout_sec

    sup = SimpleNamespace(
        node=SimpleNamespace(get_node_names=names), executor=SimpleNamespace(spin_once=spin_once)
    )
    child = SimpleNamespace(alive=lambda: exits_at_s is None or clock.t_s - t0 < exits_at_s)
    procs = SimpleNamespace(children={"recorder": child}, tail=lambda name: f"<{name}'s log>")
    return clock, t0, sup, procs


def test_a_node_slower_than_20_s_to_start_is_waited_for_with_progress_lines(monkeypatch, capsys):
    clock, t0, sup, procs = _setup(monkeypatch, appears_at_s=35.0)
    runner._wait_for_node(sup, "recorder", procs, t0 + 1800.0, quiet=False)
    assert 35.0 <= clock.t_s - t0 < 35.2
    lines = [ln for ln in capsys.readouterr().err.splitlines() if "waiting for recorder" in ln]
    assert [ln.split(": ")[1].split(" s")[0] for ln in lines] == ["10", "20", "30"]


def test_quiet_waits_without_lines(monkeypatch, capsys):
    _clock, t0, sup, procs = _setup(monkeypatch, appears_at_s=25.0)
    runner._wait_for_node(sup, "recorder", procs, t0 + 1800.0, quiet=True)
    assert capsys.readouterr().err == ""


def test_a_node_whose_process_exits_ends_the_wait_at_once_with_its_log(monkeypatch):
    clock, t0, sup, procs = _setup(monkeypatch, appears_at_s=None, exits_at_s=3.0)
    with pytest.raises(MissionError, match=r"recorder exited at start:\n<recorder's log>"):
        runner._wait_for_node(sup, "recorder", procs, t0 + 1800.0, quiet=True)
    assert clock.t_s - t0 < 3.2


def test_a_node_that_never_appears_ends_the_wait_at_the_runs_wall_timeout(monkeypatch):
    clock, t0, sup, procs = _setup(monkeypatch, appears_at_s=None)
    with pytest.raises(
        MissionError,
        match=r"recorder did not appear on the ROS graph within 60 s \(the run's --wall-timeout\)",
    ):
        runner._wait_for_node(sup, "recorder", procs, t0 + 60.0, quiet=True)
    assert 60.0 <= clock.t_s - t0 < 60.2
