"""The recorder loses nothing queued when it is stopped: a burst SIGINTed at once is all in the bag.

A 20-UAV mission puts ~20 messages per step on ``/fleet/state`` and on ``/tf``; a recorder
that takes one message per topic per wake falls behind, and whatever its DDS reader histories
still hold when it is stopped must still reach the bag (the project's rule: nothing recorded
is lost).
"""

from __future__ import annotations

import signal
import sys
from pathlib import Path

import pytest
from fire_mission.procs import ros_run_argv
from held_up import wait_for_line

HERE = Path(__file__).resolve().parent

pytestmark = pytest.mark.system

BURST = 3000  # messages, fewer than the recorder's /fleet/state depth (5000)


@pytest.mark.parametrize("stop_signal", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_recorder_stop_keeps_every_queued_message(procs, tmp_path, stop_signal):
    import fire_uav_recording as bag_io

    bag = tmp_path / "bag"
    recorder = procs.start(
        "recorder",
        ros_run_argv("fire_uav_recording", "recorder", ["-p", f"output:={bag}", "-p", "uav_count:=20"]),
    )
    procs.start("burst", [sys.executable, str(HERE / "burst_publisher.py"), str(BURST)])
    wait_for_line(
        procs, "burst", f"acked {BURST}", 60.0, lines=5, poll_s=0.01
    )  # all in the recorder's reader history
    procs.signal("recorder", stop_signal)
    assert recorder.popen.wait(timeout=20) == 0, procs.tail("recorder")

    with bag_io.open_bag(bag) as b:
        assert b.warnings == []
        assert b.custom_data[bag_io.KEY_CLOSED] == "true"
        got = [msg.sequence for _, _, msg in b.messages(["/fleet/state"])]
    assert len(got) == BURST, f"{BURST - len(got)} of {BURST} lost; recorder log:\n{procs.tail('recorder')}"
    assert sorted(got) == list(range(BURST))
    assert got == sorted(got)  # in publication order
