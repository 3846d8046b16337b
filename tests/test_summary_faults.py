"""The summary's "faults injected" lists every fault: the supervisor's signals and the link
outages the agents apply themselves (from --outage, else the scenario's comms.outages)."""

from __future__ import annotations

import argparse

from fire_mission.runner import _parse_outage, applied_outages
from fire_mission.summary import LiveSummary, table
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import load_scenario


def test_outages_that_began_are_listed_after_the_signals() -> None:
    s = LiveSummary(uav_count=3)
    s.faults.append("kill uav 1 at 30 s (offline from step 300)")
    s.outages = [(2, 0, 50.0, 60.0), (0, 1, 3.0, 9.0), (1, 2, 200.0, 210.0)]
    s.mission_time_s = 100.0
    d = s.as_dict(outcome="complete", wall_s=1.0, steps=1000)
    assert d["faults_injected"] == [
        "kill uav 1 at 30 s (offline from step 300)",
        "outage 0>1 from 3 s to 9 s (link dropped by the agents)",
        "outage 2>0 from 50 s to 60 s (link dropped by the agents)",
    ]  # the outage at 200 s never began: the mission ended at 100 s
    assert "outage 0>1 from 3 s to 9 s" in table(d)
    assert d["faults"] == [
        {"kind": "outage", "from": 0, "to": 1, "start_s": 3.0, "end_s": 9.0},
        {"kind": "outage", "from": 2, "to": 0, "start_s": 50.0, "end_s": 60.0},
    ]  # the kill above was appended as text only: the records are the runner's own


def test_the_signal_plan_carries_each_faults_own_time_and_kind() -> None:
    import signal

    from fire_mission.runner import _SIGNAL_KIND, _parse_freeze, _parse_kill, signal_plan

    args = argparse.Namespace(kill=[_parse_kill("2@20")], freeze=[_parse_freeze("1@5:6.5")])
    plan = signal_plan(args, 0.1)
    got = [(_SIGNAL_KIND[sig], uav, t) for _, _, _, uav, sig, t in plan]
    assert got == [("freeze", 1, 5.0), ("resume", 1, 6.5), ("kill", 2, 20.0)]
    assert {signal.SIGKILL, signal.SIGSTOP, signal.SIGCONT} == set(_SIGNAL_KIND)


def test_the_command_line_outages_replace_the_scenarios() -> None:
    sc = load_scenario(
        scenario_path("fault_drill"),
        overrides={"comms.outages": [{"from": 0, "to": 2, "start_s": 1.0, "end_s": 5.0}]},
    )
    none = argparse.Namespace(outage=[])
    assert applied_outages(none, sc, 3) == [(0, 2, 1.0, 5.0)]
    given = argparse.Namespace(outage=[_parse_outage("1>0@3:9")])
    assert applied_outages(given, sc, 3) == [(1, 0, 3.0, 9.0)]
    assert applied_outages(given, sc, 0) == []  # no fleet, no agent to apply it


def test_printed_numbers_are_rounded() -> None:
    s = LiveSummary(uav_count=0)
    s.mission_time_s = 137.10000000000002
    d = s.as_dict(outcome="time_limit", wall_s=3.0, steps=1371)
    d["hit_rate"] = 0.967741935483871
    d["contained_at_s"] = 137.10000000000002
    text = table(d)
    assert "0.97" in text and "137.10" in text
    assert "0.9677" not in text and "137.1000" not in text
