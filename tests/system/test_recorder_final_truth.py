"""A recorder held up at the end of a mission still records the world's final ``/world/truth``.

The race behind "599 vs 600 truth messages" (test_determinism): the runner signalled the world
as soon as MISSION_COMPLETE reached it, so the world exited milliseconds after its final publish.
A reliable DDS writer repairs a lost sample only while it lives, and the loss of its last sample
shows only at its next heartbeat; a recorder that had not taken the world's last messages by then
(held up by a busy machine) never got them. Here the recorder is held up for real (SIGSTOP, as a
descheduled process, then SIGCONT 1.5 s after the world's end, or 6 s after the stop if that is
sooner) while a real world node (no fleet: it steps as fast as it can) publishes its steps, and
the runner's own end sequence follows. (On a machine so slow that the world's 50 steps take over
4.5 s the recorder is let go before the end, and the test shows less.)
Before the fix the bag lacked the world's last steps; the world now exits only once every reader
has acknowledged its messages, and the runner waits for that exit.
"""

from __future__ import annotations

import pytest
from fire_mission import runner
from fire_mission.procs import ros_run_argv
from fire_uav_common.constants import EventType
from held_up import HeldUp, wait_for_line

pytestmark = pytest.mark.system

MAX_DURATION_S = 5.0  # [s sim]: 50 steps, ~0.1 s of wall time with no fleet (~1.6 s at load 20)
STEPS = 50  # the world's steps 0..49, the last at MAX_DURATION_S
HOLD_AFTER_END_WALL_S = 1.5  # [s wall] the recorder is held up until this long after the world's end,
HOLD_MAX_WALL_S = 6.0  # [s wall] and never longer than this: beyond its DDS lease (10 s) it would
# count as a dead process, whose readers nothing waits for


def test_a_recorder_held_up_at_the_end_keeps_the_worlds_last_truth(procs, tmp_path):
    import fire_uav_recording as bag_io

    bag = tmp_path / "bag"
    scenario = runner.resolve_scenario("tiny_test")
    recorder = procs.start(
        "recorder",
        ros_run_argv("fire_uav_recording", "recorder", ["-p", f"output:={bag}", "-p", "uav_count:=0"]),
    )
    wait_for_line(procs, "recorder", "recording to", 60.0)
    procs.start(
        "world",
        ros_run_argv(
            "fire_world_sim",
            "world_node",
            [
                *("-p", f"scenario_file:={scenario}", "-p", "no_fleet:=true", "-p", "auth:=false"),
                *("-p", "wait_for_subscribers:=1", "-p", f"max_duration_s:={MAX_DURATION_S}"),
            ],
        ),
    )
    wait_for_line(procs, "world", "starting", 60.0)
    with HeldUp(procs, "recorder", HOLD_MAX_WALL_S) as held:  # the world's steps pile up unread
        wait_for_line(procs, "world", "mission complete", 120.0)
        held.release_in(HOLD_AFTER_END_WALL_S)
        # what the runner does once MISSION_COMPLETE has reached it
        runner._let_the_world_end(procs)
        codes = procs.stop_all(first=["world"])
    # (its exit code is not the point: at load ~40 a recorder still tearing down DDS after closing
    # its bag was seen to get the escalated SIGTERM, -15, in the base code too)
    assert codes["world"] == 0, procs.tail("world")

    with bag_io.open_bag(bag) as b:
        assert b.custom_data[bag_io.KEY_CLOSED] == "true"
        truths = [(msg.step, msg.header.stamp.sec) for _, _, msg in b.messages(["/world/truth"])]
        ends = [m for _, _, m in b.messages(["/world/events"]) if m.type == EventType.MISSION_COMPLETE]
    steps = [s for s, _ in truths]
    # the world's every step, in order, up to its last at the time limit
    assert steps == list(range(STEPS)), (
        f"{len(steps)} of {STEPS} truth messages; recorder log:\n{procs.tail('recorder')}"
    )
    assert truths[-1][1] == int(MAX_DURATION_S), (
        f"the bag ends at step {steps[-1]} (t = {truths[-1][1]} s), not at the mission's end "
        f"({MAX_DURATION_S:g} s); recorder log:\n{procs.tail('recorder')}"
    )
    assert [e.header.stamp.sec for e in ends] == [int(MAX_DURATION_S)]
    assert "lacks" not in procs.tail(recorder.name, 50)
