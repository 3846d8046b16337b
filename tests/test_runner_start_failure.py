"""The runner ends a mission at once when an agent exits with an error before step 0.

The lockstep world waits for every agent's AGENT_READY with no timeout, so before this check a
broken agent (a TypeError in its constructor) left a benchmark waiting for 20 minutes. A fault
plan's kills end agents by signal (a negative return code) and only after step 0: not an error.
"""

from __future__ import annotations

import signal
import sys
import time

import pytest
from fire_mission.procs import MissionError, ProcessGroup
from fire_mission.runner import _fail_on_agent_error_before_start

PY = sys.executable


def _wait_exited(group: ProcessGroup, names: list[str]) -> None:
    end = time.monotonic() + 20
    while any(group.children[n].alive() for n in names) and time.monotonic() < end:
        time.sleep(0.05)


def test_an_agent_that_failed_at_start_ends_the_mission_with_its_log(tmp_path):
    with ProcessGroup(tmp_path) as g:
        g.start("agent_0", [PY, "-c", "import time; time.sleep(30)"])
        g.start("agent_1", [PY, "-c", "raise TypeError(\"'bool' object is not callable\")"])
        _wait_exited(g, ["agent_1"])
        with pytest.raises(MissionError, match=r"agent_1 exited \(code 1\) before step 0") as err:
            _fail_on_agent_error_before_start(g, 2)
        assert "'bool' object is not callable" in str(err.value)  # its log's tail


def test_agents_ended_by_a_signal_or_still_running_are_not_an_error(tmp_path):
    with ProcessGroup(tmp_path) as g:
        g.start("agent_0", [PY, "-c", "import time; time.sleep(30)"])
        killed = g.start("agent_1", [PY, "-c", "import time; time.sleep(30)"])
        g.start("agent_2", [PY, "-c", "pass"])  # exit code 0
        killed.popen.send_signal(signal.SIGKILL)
        _wait_exited(g, ["agent_1", "agent_2"])
        assert killed.popen.returncode == -signal.SIGKILL
        _fail_on_agent_error_before_start(g, 3)  # no exception
