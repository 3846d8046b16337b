"""End-to-end missions through the real runner: world + recorder + agent processes.

Each test runs a whole mission in lockstep mode on a private ROS_DOMAIN_ID and checks the
outcome the runner saw live (summary.json). They are slow (tens of seconds each).
"""

from __future__ import annotations

import pytest
from mission_util import assert_no_survivors, run_mission

pytestmark = [pytest.mark.system, pytest.mark.slow]

SMALL = "fault_drill"  # one big fire: drops, refills and reassessment in about a minute of mission time


def _complete(summary: dict, stderr: str) -> None:
    assert summary["outcome"] == "complete", f"mission did not complete: {summary}\n{stderr[-3000:]}"
    assert summary["fires_active_at_end"] == 0


def test_ff_two_fire_mission_with_five_uavs(ros_env, tmp_path):
    summary, err = run_mission(
        tmp_path / "run", ros_env, "ff_two_fires", "--uavs", "5", "--seed", "1", timeout_s=900
    )
    _complete(summary, err)
    assert summary["fires_total"] == 2
    assert len(summary["extinguished"]) == 2
    assert summary["landed"] == [0, 1, 2, 3, 4]
    assert summary["drops_total"] >= 2
    assert_no_survivors(summary)


def test_killed_agent_is_detected_and_mission_completes(ros_env, tmp_path):
    victim, n = 1, 3
    summary, err = run_mission(
        tmp_path / "run", ros_env, SMALL, "--uavs", str(n), "--seed", "2", "--kill", f"{victim}@4"
    )
    _complete(summary, err)
    period = summary["control_period_s"]
    survivors = [k for k in range(n) if k != victim]
    # the world logs the fall of the vehicle whose agent died
    assert [c["uav_id"] for c in summary["crashes"]] == [victim]
    # every survivor declares it crashed within 10 communication steps of its last message
    declared = summary["declared_crashed"].get(str(victim), [])
    assert sorted(d["by"] for d in declared) == survivors, declared
    last_heard = summary["last_state_t_s"][str(victim)]
    for d in declared:
        delay_steps = (d["t_s"] - last_heard) / period
        assert 9.5 <= delay_steps <= 11.5, f"uav {d['by']} declared after {delay_steps:.1f} steps"
    # and no longer partitions with it
    for k in survivors:
        assert victim not in summary["alive_view"][str(k)]
    assert sorted(summary["landed"]) == survivors
    assert_no_survivors(summary)


def test_two_agents_killed_at_once_one_carrying_water(ros_env, tmp_path):
    n = 4
    summary, err = run_mission(
        tmp_path / "run", ros_env, SMALL, "--uavs", str(n), "--seed", "3", "--kill", "1@4", "--kill", "2@4"
    )
    _complete(summary, err)
    assert sorted(c["uav_id"] for c in summary["crashes"]) == [1, 2]
    assert any(w > 0 for w in summary["water_at_fault_kg"].values()), summary["water_at_fault_kg"]
    for victim in (1, 2):
        assert sorted(d["by"] for d in summary["declared_crashed"][str(victim)]) == [0, 3]
    assert sorted(summary["landed"]) == [0, 3]
    assert_no_survivors(summary)


def test_mission_completes_with_20_percent_loss(ros_env, tmp_path):
    summary, err = run_mission(
        tmp_path / "run", ros_env, SMALL, "--uavs", "3", "--seed", "4", "--loss", "0.2"
    )
    _complete(summary, err)
    total = summary["packets_received"] + summary["packets_lost"]
    assert total > 0
    assert 0.12 < summary["packets_lost"] / total < 0.28, summary
    assert summary["crashes"] == []
    assert summary["declared_crashed"] == {}
    assert_no_survivors(summary)


def test_frozen_agent_that_resumes_rejoins(ros_env, tmp_path):
    # frozen for 1.5 s of mission time: > 10 steps (peers declare it crashed), < the world's 3 s fall timeout
    summary, err = run_mission(
        tmp_path / "run", ros_env, SMALL, "--uavs", "3", "--seed", "5", "--freeze", "2@6:7.5"
    )
    _complete(summary, err)
    assert summary["crashes"] == [], "a frozen agent's vehicle must not fall within the command timeout"
    assert sorted(d["by"] for d in summary["declared_crashed"].get("2", [])) == [0, 1]
    assert sorted(r["by"] for r in summary["rejoined"] if r["uav_id"] == 2) == [0, 1]
    assert sorted(summary["landed"]) == [0, 1, 2]
    for k in (0, 1):
        assert 2 in summary["alive_view"][str(k)]
    assert_no_survivors(summary)
