"""The runner's end: the recorder is signalled only once every agent has exited, and an agent that
takes its time to exit (waiting for its readers' acknowledgements) is not cut short; one that
ignores the signals is still killed. Stand-in processes (no ROS): each logs when it is signalled
and when it exits, on the one monotonic clock of the host."""

from __future__ import annotations

import sys
import textwrap
import time
from pathlib import Path

from fire_mission import runner
from fire_mission.procs import ProcessGroup

# a stand-in: at SIGINT/SIGTERM it writes "sig <t>", works for EXIT_AFTER s, writes "exit <t>", exits 0;
# EXIT_AFTER < 0: it ignores both signals
STANDIN = textwrap.dedent(
    """
    import signal, sys, time
    log, exit_after = sys.argv[1], float(sys.argv[2])
    def note(what):
        with open(log, "a") as f:
            f.write(f"{what} {time.monotonic()!r}\\n")
    def on_signal(signum, frame):
        note("sig")
        if exit_after >= 0:
            time.sleep(exit_after)
            note("exit")
            sys.exit(0)
    handler = on_signal if exit_after >= 0 else signal.SIG_IGN
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, handler)
    if exit_after < 0:
        note("ignoring")
    note("ready")
    while True:
        time.sleep(1)
    """
)


def _start(procs: ProcessGroup, tmp_path: Path, name: str, exit_after_s: float) -> Path:
    log = tmp_path / f"{name}.times"
    procs.start(name, [sys.executable, "-c", STANDIN, str(log), str(exit_after_s)])
    return log


def _times(log: Path, what: str) -> list[float]:
    return [float(ln.split()[1]) for ln in log.read_text().splitlines() if ln.split()[0] == what]


def _wait_ready(logs: list[Path]) -> None:
    deadline = time.monotonic() + 30.0
    while not all(log.exists() and _times(log, "ready") for log in logs):
        assert time.monotonic() < deadline, "a stand-in did not start"
        time.sleep(0.02)


def test_the_recorder_is_signalled_after_every_agent_has_exited(tmp_path: Path) -> None:
    # the group's own grace (8 s in the runner; 1 s here) would SIGTERM the slow agent at 0.5 s
    with ProcessGroup(tmp_path / "logs", grace_s=1.0) as procs:
        logs = {
            "recorder": _start(procs, tmp_path, "recorder", 0.0),
            "agent_0": _start(procs, tmp_path, "agent_0", 0.0),
            "agent_1": _start(procs, tmp_path, "agent_1", 1.5),  # waits for its acknowledgements
            "world": _start(procs, tmp_path, "world", 0.0),
        }
        _wait_ready(list(logs.values()))
        codes = runner._stop_in_order(procs, ["agent_0", "agent_1", "agent_2"], agent_grace_s=6.0)
    assert codes == {"agent_0": 0, "agent_1": 0, "world": 0, "recorder": 0}
    assert len(_times(logs["agent_1"], "sig")) == 1  # one signal: its wait was not cut short
    last_agent_exit = max(_times(logs[a], "exit")[0] for a in ("agent_0", "agent_1"))
    assert _times(logs["world"], "sig")[0] >= last_agent_exit
    assert _times(logs["recorder"], "sig")[0] >= last_agent_exit


def test_an_agent_that_ignores_the_signals_is_still_killed(tmp_path: Path) -> None:
    with ProcessGroup(tmp_path / "logs", grace_s=1.0) as procs:
        logs = {
            "recorder": _start(procs, tmp_path, "recorder", 0.0),
            "agent_0": _start(procs, tmp_path, "agent_0", -1.0),
        }
        _wait_ready(list(logs.values()))
        codes = runner._stop_in_order(procs, ["agent_0"], agent_grace_s=1.0)
    assert codes == {"agent_0": -9, "recorder": 0}
    assert _times(logs["recorder"], "sig")
