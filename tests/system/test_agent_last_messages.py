"""A recorder held up when the agents are signalled still records every message they published.

The agents' side of the race in test_recorder_final_truth.py: a reliable DDS writer repairs a lost
sample only while it lives, and the loss of its last sample shows only at its next heartbeat, so
an agent that exits at SIGINT right after its last step can take with it messages a recorder held
up (a busy machine) has not got yet. Here the recorder is held up for real (SIGSTOP, as a
descheduled process) over the last steps of a real lockstep mission (world and two agents, no
runner), and the agents get the runner's SIGINT while it is still stopped; it is let go (SIGCONT)
1.5 s later, or 6 s after the stop if that is sooner (its DDS lease is 10 s: a reader silent for
longer is dropped, and nothing waits for it any more).

The truth: each agent logs at its exit how many messages it published on each topic (``published:
...``); the bag must hold exactly as many on each reliable topic only the agents publish on. Before
the fix the agents exited at once and the bag lacked their last messages; an agent now exits once
every matched reader has acknowledged every message it published (``fire_uav_common.final_acks``).
"""

from __future__ import annotations

import re
import time

import pytest
from fire_mission import runner
from fire_mission.procs import ros_run_argv
from held_up import HeldUp, wait_for_line

pytestmark = [pytest.mark.system, pytest.mark.slow]

UAVS = 2
MAX_DURATION_S = 4.0  # [s sim]: 40 lockstep steps
HOLD_AFTER_SIGINT_WALL_S = 1.5  # [s wall] held up until this long after the agents' SIGINT,
HOLD_MAX_WALL_S = 6.0  # [s wall] and never longer than this (below its 10 s lease)
DISCOVERY_SETTLE_WALL_S = 3.0  # [s wall] after the agents are up, before the world starts
# reliable topics only the agents publish on (/tf: the world too; /uav_k/viz: best effort)
AGENT_TOPICS = re.compile(r"/fleet/(state|events|perimeter|front)|/uav_\d+/(cmd|payload)")


def _published(log: str) -> dict[str, int]:
    """The agent's exit line ``published: /a 3, /b 0`` as {topic: count}."""
    line = [ln for ln in log.splitlines() if "published: " in ln][-1]
    counts = line.split("published: ", 1)[1]
    return {t: int(n) for t, n in (item.rsplit(" ", 1) for item in counts.split(", "))}


def test_a_recorder_held_up_when_the_agents_are_signalled_keeps_their_last_messages(procs, tmp_path):
    import fire_uav_recording as bag_io

    bag = tmp_path / "bag"
    scenario = runner.resolve_scenario("tiny_test")
    recorder = procs.start(
        "recorder",
        ros_run_argv("fire_uav_recording", "recorder", ["-p", f"output:={bag}", "-p", f"uav_count:={UAVS}"]),
    )
    wait_for_line(procs, "recorder", "recording to", 60.0)
    common = ["-p", f"scenario_file:={scenario}", "-p", f"uav_count:={UAVS}", "-p", "auth:=false"]
    agents = [f"agent_{k}" for k in range(UAVS)]
    for k, name in enumerate(agents):
        procs.start(
            name,
            ros_run_argv(
                "fire_uav_agent", "uav_agent", ["-r", f"__ns:=/uav_{k}", "-p", f"uav_id:={k}", *common]
            ),
        )
    # The recorder must hear every agent's writers before the first step: the 40 steps take well
    # under a second, and a writer that has not yet matched the recorder's reader (discovery
    # between the two, which the world's wait for /world/truth subscribers does not cover) sends
    # it nothing (volatile) and, at exit, has no reader of it to wait for. Seen once in a
    # fresh-clone CI under load: the bag held none of uav_0's cmd, payload or state. So let each
    # agent come up, then give discovery time before the world starts the steps.
    for name in agents:
        wait_for_line(procs, name, "mode=lockstep", 60.0)
    time.sleep(DISCOVERY_SETTLE_WALL_S)
    procs.start(
        "world",
        ros_run_argv(
            "fire_world_sim",
            "world_node",
            [*common, "-p", "wait_for_subscribers:=1", "-p", f"max_duration_s:={MAX_DURATION_S}"],
        ),
    )
    wait_for_line(procs, "world", "starting", 120.0)
    with HeldUp(procs, "recorder", HOLD_MAX_WALL_S) as held:  # the last steps' messages pile up unread
        wait_for_line(procs, "world", "mission complete", 120.0)
        # what the runner does once the world is done (it waits for the world's exit first, which
        # here waits for the stopped recorder too: the agents' side is the point)
        held_at_sigint = held.release_in(HOLD_AFTER_SIGINT_WALL_S)
        codes = procs.stop(agents, grace_s=runner.AGENT_STOP_GRACE_WALL_S)
        runner._let_the_world_end(procs)
        codes.update(procs.stop_all(first=["world"]))
    assert all(codes[a] == 0 for a in agents), {a: procs.tail(a) for a in agents}
    assert codes["world"] == 0, procs.tail("world")
    assert held_at_sigint < HOLD_MAX_WALL_S, (
        f"the mission took {held_at_sigint:.1f} s: the recorder was let go"
    )

    sent: dict[str, int] = {}
    for a in agents:
        for topic, n in _published(procs.tail(a, 400)).items():
            if AGENT_TOPICS.fullmatch(topic):
                sent[topic] = sent.get(topic, 0) + n
    # the agents ran the mission (one state per step answered; the last bundle may come after SIGINT)
    assert sent.get("/fleet/state", 0) >= UAVS * 0.75 * MAX_DURATION_S / 0.1, sent
    with bag_io.open_bag(bag) as b:
        assert b.custom_data[bag_io.KEY_CLOSED] == "true"
        recorded = {t: 0 for t in sent}
        for conn, _, _ in b.raw_messages(list(sent)):
            recorded[conn.topic] += 1
    missing = {t: f"{recorded[t]} of {n}" for t, n in sent.items() if recorded[t] != n}
    assert not missing, (
        f"the bag lacks agents' messages (recorded of published): {missing}; "
        f"agent log:\n{procs.tail(agents[0], 15)}\nrecorder log:\n{procs.tail(recorder.name, 15)}"
    )
