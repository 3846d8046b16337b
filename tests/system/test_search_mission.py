"""End to end: the coverage search runs inside the agents, finds the fire, and the fleet puts it out.

Needs ``fire_uav_agent.search_io`` wired into ``agent_node.py`` (``attach_search`` in ``__init__``,
``SearchLink.on_step`` after every ``Agent.step``); before that the agents search with the default
staleness planner and the search assertions below fail.
"""

from __future__ import annotations

import pytest
from fire_uav_common.constants import EventType
from mission_util import assert_no_survivors, run_mission

pytestmark = [pytest.mark.system, pytest.mark.slow]

TYPE_FIRE_DETECTED = EventType.FIRE_DETECTED


def test_search_area_fire_is_found_then_extinguished(ros_env, tmp_path):
    summary, err = run_mission(
        tmp_path / "run", ros_env, "search_area", "--uavs", "3", "--seed", "0", timeout_s=900
    )
    assert summary["outcome"] == "complete", f"mission did not complete: {summary}\n{err[-3000:]}"
    detected = [e for e in summary["events"] if e["type"] == TYPE_FIRE_DETECTED]
    assert detected, "no UAV reported detecting the fire"
    assert summary["fires_total"] == 1
    assert len(summary["extinguished"]) == 1
    assert summary["fires_active_at_end"] == 0
    assert detected[0]["t_s"] < summary["extinguished"][0]["t_s"]
    assert sorted(summary["landed"]) == [0, 1, 2]
    # the agents ran the search: every one logged an agreed plan
    logs = list((tmp_path / "run").rglob("*.log"))
    text = "".join(p.read_text(errors="replace") for p in logs)
    assert text.count("search: plan for uavs [0, 1, 2] ready") >= 3, "agents did not agree on a coverage plan"
    assert "search: MST over messages" in text
    assert_no_survivors(summary)
