"""The messaging skeleton of the scale benchmark has the fleet's processes and topics.

The scale target is a ratio to "the messaging-only skeleton (the same processes and topics, no
algorithms)". Here a 3-UAV FF mission without a recorder (as the benchmark runs it) and the
full-fidelity skeleton (``fire_bench.skeleton --fidelity full``) run one after the other on one
private domain, each under a probe that counts every message on every fleet topic; the skeleton
must publish on the same topics, from as many nodes, at the same rate per step, with messages of
comparable size. The minimal skeleton (``--fidelity minimal``) fails this test (no payload, truth, /tf,
markers, runner).
"""

from __future__ import annotations

import json
import signal
import sys
import time
from pathlib import Path

import pytest
from mission_util import run_mission

pytestmark = [pytest.mark.system, pytest.mark.slow]

HERE = Path(__file__).resolve().parent
UAVS, STEPS = 3, 150  # the scale benchmark's 15 s of mission time
#: topics whose traffic follows events, not steps (start-up handshakes, drops, extinctions)
EVENT_TOPICS = {"/fleet/events", "/world/events"}


def _probe(procs, name: str, out: Path):
    procs.start(name, [sys.executable, str(HERE / "traffic_probe.py"), str(UAVS), str(out)])
    time.sleep(2.0)  # the probe's participant is discovered before the traffic starts
    assert procs.children[name].alive(), f"the probe died:\n{procs.tail(name)}"


def _stop_probe(procs, name: str, out: Path) -> dict:
    time.sleep(1.0)  # the last messages in flight arrive
    procs.signal(name, signal.SIGINT)
    t_end = time.monotonic() + 20
    while procs.children[name].alive() and time.monotonic() < t_end:
        time.sleep(0.1)
    assert out.is_file(), f"the probe wrote nothing:\n{procs.tail(name)}"
    return json.loads(out.read_text())


def _per_step(traffic: dict) -> dict[str, tuple[float, float, tuple[str, ...]]]:
    """pattern -> (messages per step, mean bytes per message, namespaces of the publishing nodes)."""
    return {
        k: (
            round(v["messages"] / STEPS, 3),
            round(v["bytes"] / max(v["messages"], 1)),
            tuple(v["publishers"]),
        )
        for k, v in traffic.items()
    }


def _run_skeleton(procs, ros_env: dict[str, str]) -> None:
    base = [sys.executable, "-m", "fire_bench.skeleton"]
    for k in range(UAVS):
        procs.start(f"sk_agent_{k}", [*base, "agent", "--uav-id", str(k), "--uavs", str(UAVS)])
    procs.start("sk_supervisor", [*base, "supervisor", "--uavs", str(UAVS)])
    # the world starts once the supervisor and the probe hear /world/truth (the probe subscribes to it
    # last), else the probe can miss the first steps of a skeleton that starts faster than the fleet
    world = [*base, "world", "--uavs", str(UAVS), "--steps", str(STEPS), "--wait-for-subscribers", "2"]
    w = procs.start("sk_world", world)
    t_end = time.monotonic() + 120
    while w.alive() and time.monotonic() < t_end:
        time.sleep(0.2)
    assert not w.alive(), f"the skeleton did not finish {STEPS} steps:\n{procs.tail('sk_world')}"
    assert '"steps_per_s"' in procs.tail("sk_world", 5), procs.tail("sk_world")


def test_full_skeleton_has_the_fleets_topics_rates_and_sizes(procs, ros_env, tmp_path):
    assert "FIRE_UAV_DOMAIN_ID" in ros_env  # the runner takes the test's domain, so the probe hears it
    _probe(procs, "probe_fleet", tmp_path / "fleet.json")
    summary, err = run_mission(
        tmp_path / "run", ros_env, "ff_two_fires", "--uavs", str(UAVS), "--seed", "1",
        "--max-duration", str(STEPS / 10), "--no-record", timeout_s=300,
    )  # fmt: skip
    assert summary["outcome"] == "time_limit", f"{summary['outcome']}: {err[-2000:]}"
    fleet = _per_step(_stop_probe(procs, "probe_fleet", tmp_path / "fleet.json"))

    _probe(procs, "probe_skeleton", tmp_path / "skeleton.json")
    _run_skeleton(procs, ros_env)
    skeleton = _per_step(_stop_probe(procs, "probe_skeleton", tmp_path / "skeleton.json"))

    report = "\n".join(
        f"{k}: fleet {fleet.get(k)} skeleton {skeleton.get(k)}" for k in sorted({*fleet, *skeleton})
    )
    # the same topics have publishers, in the same namespaces (/uav_k: agents; /: world, runner)
    assert {k: v[2] for k, v in skeleton.items()} == {k: v[2] for k, v in fleet.items()}, report
    for k, (rate, size, _) in fleet.items():
        if k in EVENT_TOPICS:
            continue
        s_rate, s_size, _ = skeleton[k]
        if rate == 0:  # a topic the FF mission has endpoints on and never uses (/fleet/front, ...)
            assert s_rate == 0, f"{k}: the fleet sends nothing, the skeleton {s_rate:.2f} per step\n{report}"
            continue
        # the skeleton may not send more than the fleet (that would flatter the ratio), nor much less
        assert 0.8 * rate <= s_rate <= 1.05 * rate, f"{k}: {s_rate:.2f} against {rate:.2f} per step\n{report}"
        assert 0.5 * size <= s_size <= 1.1 * size, f"{k}: {s_size:.0f} against {size:.0f} bytes\n{report}"


def test_skeleton_refuses_a_full_run_on_another_wire():
    from fire_bench import skeleton

    with pytest.raises(SystemExit):
        skeleton.main(["agent", "--uavs", "2", "--wire", "messages"])
