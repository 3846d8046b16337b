"""The peer gate without ROS or DDS: arrivals in any order, duplicates, a resend, a crashed peer's
final message, spoofed steps and tags, the re-sent bundle and the realtime mode."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from fire_uav_agent.agent_types import PeerPerimeter
from fire_uav_agent.errors import ConfigError
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.front_consensus import PeerFront
from fire_uav_agent.peer_gate import (
    WAIT_REPORT_NS,
    AskResend,
    PeerGate,
    PeerGone,
    Rejected,
    RepeatAnswer,
    RunStep,
    SortedInbox,
    StartWaiting,
    StillWaiting,
    inbox_order,
)
from fire_uav_agent.peer_link import PeerFires, PeerState
from fire_uav_common.lockstep import parse_schedule
from fire_uav_common.topics import ALL_TOPICS, FLEET_FRONT_SPEC, FLEET_PERIMETER_SPEC

S = 10**9  # [ns] one second of steady time


def sent(perimeter: int = 0, front: int = 0) -> tuple[int, ...]:
    c = [0] * (1 + max(s.loss_index for s in ALL_TOPICS if s.loss_index is not None))
    c[0] = c[1] = 1
    c[FLEET_PERIMETER_SPEC.loss_index] = perimeter
    c[FLEET_FRONT_SPEC.loss_index] = front
    return tuple(c)


def state(j: int, step: int, seq: int | None = None) -> PeerState:
    return PeerState(j, step + 1 if seq is None else seq, step, 10.0 * j, 0.0, 30.0, 0.0, 0)


def fires(j: int, step: int) -> PeerFires:
    return PeerFires(j, step + 1, step)


def perimeter(j: int, step: int, seq: int = 1) -> PeerPerimeter:
    return PeerPerimeter(j, seq, step, 7, {})


def front(j: int, step: int) -> PeerFront:
    z = np.zeros(1)
    return PeerFront(j, 1, step, FrontCells(z, z, np.zeros(1, dtype=np.int64), z, z), 10.0)


def on_state(g: PeerGate, j: int, step: int, final: bool = False, perim: int = 0, fr: int = 0) -> list:
    return g.on_state(b"", state(j, step), fires(j, step), sent(perim, fr), final)


def runs(decisions: list) -> list[RunStep]:
    return [d for d in decisions if isinstance(d, RunStep)]


def gate(uid: int = 0, n: int = 3, **kw) -> PeerGate:
    g: PeerGate = PeerGate(uid, n, 0.1, **kw)
    assert runs(g.on_bundle(0, "b0"))  # step 0 waits for nobody
    return g


def test_step_0_runs_at_once_and_step_1_waits_for_every_live_peer() -> None:
    g: PeerGate = PeerGate(0, 3, 0.1)
    (d,) = g.on_bundle(0, "b0")
    assert d == RunStep(0, "b0", ())
    assert g.on_bundle(1, "b1", now_ns=5) == [StartWaiting(1)]
    assert g.pending_step == 1
    assert on_state(g, 1, 0) == []
    (d,) = on_state(g, 2, 0)
    assert isinstance(d, RunStep) and d.step == 1 and d.bundle == "b1"
    assert d.inbox == (state(1, 0), fires(1, 0), state(2, 0), fires(2, 0))
    assert g.pending_step is None and g.last_step == 1


def test_out_of_order_arrivals_give_one_inbox_order() -> None:
    """Whatever order DDS delivers them in (perimeter before the state that announces it, the
    higher id first), the agent is handed the same inbox, in (step, sender, kind, sequence)."""
    msgs = [
        ("state", 1),
        ("state", 2),
        ("perimeter", 1),
        ("front", 2),
    ]
    inboxes = set()
    for order in itertools.permutations(msgs):
        g = gate()
        g.on_bundle(1, "b1")
        got: list = []
        for kind, j in order:
            if kind == "state":
                got += on_state(g, j, 0, perim=int(j == 1), fr=int(j == 2))
            elif kind == "perimeter":
                got += g.on_perimeter(b"", perimeter(j, 0))
            else:
                got += g.on_front(j, 0, front(j, 0))
        (run,) = runs(got)
        assert run.inbox == tuple(sorted(run.inbox, key=inbox_order))
        assert isinstance(run.inbox, SortedInbox)  # so the agent does not sort it again
        inboxes.add(tuple((type(m).__name__, m.uav_id) for m in run.inbox))
    assert inboxes == {
        (
            ("PeerState", 1),
            ("PeerFires", 1),
            ("PeerPerimeter", 1),
            ("PeerState", 2),
            ("PeerFires", 2),
            ("PeerFront", 2),
        )
    }


def test_messages_of_the_step_being_waited_on_stay_for_the_next_step() -> None:
    g = gate(n=2)
    on_state(g, 1, 0)
    on_state(g, 1, 1)  # the peer is a step ahead (it got its bundle first)
    (run,) = runs(g.on_bundle(1, "b1"))
    assert [m.step for m in run.inbox] == [0, 0]
    assert [m.step for m in g.inbox()] == [1, 1]
    (run,) = runs(g.on_bundle(2, "b2"))
    assert [m.step for m in run.inbox] == [1, 1]


def test_a_duplicate_is_dropped_with_the_fires_it_carries() -> None:
    g = gate()
    g.on_bundle(1, "b1")
    on_state(g, 1, 0, perim=1)
    assert on_state(g, 1, 0, perim=1) == []  # a resent copy of the state: not counted twice
    assert g.on_perimeter(b"", perimeter(1, 0)) == []
    assert g.on_perimeter(b"", perimeter(1, 0)) == []
    (run,) = runs(on_state(g, 2, 0))
    assert [(type(m).__name__, m.uav_id) for m in run.inbox] == [
        ("PeerState", 1), ("PeerFires", 1), ("PeerPerimeter", 1), ("PeerState", 2), ("PeerFires", 2)
    ]  # fmt: skip
    assert g.resend.copies_dropped == 2
    # a copy that arrives after its step ran is older than the step run: rejected at admission
    assert g.on_perimeter(b"", perimeter(1, 0)) == [Rejected("/fleet/perimeter", 1, 0, "stale step")]
    assert list(g.inbox()) == []


def test_a_blocked_step_asks_the_missing_peer_to_resend_once_per_interval() -> None:
    g = gate()
    g.on_bundle(1, "b1", now_ns=0)
    on_state(g, 1, 0)
    alive = lambda: {1, 2}  # noqa: E731
    assert g.on_liveness(WAIT_REPORT_NS // 2, alive) == []  # not long enough to report
    got = g.on_liveness(WAIT_REPORT_NS + 1, alive)
    assert isinstance(got[0], StillWaiting) and got[0].step == 1 and "uav 2" in got[0].missing
    assert got[1:] == [AskResend(2, 0, got[0].waited_s)]
    assert [d for d in g.on_liveness(WAIT_REPORT_NS + S, alive) if isinstance(d, AskResend)] == []
    later = g.on_liveness(2 * WAIT_REPORT_NS + 2, alive)
    assert AskResend(2, 0, later[0].waited_s) in later  # asked again after the interval
    (run,) = runs(on_state(g, 2, 0))  # the resent copy arrives
    assert run.step == 1


def test_the_sender_keeps_its_messages_and_resends_them_once_per_interval() -> None:
    g = gate()
    g.keep(3, ["state-3", "perimeter-3"])
    assert g.to_resend(3, 0) == ["state-3", "perimeter-3"]
    assert g.to_resend(3, S) is None  # one copy serves every peer that asked meanwhile
    assert g.to_resend(3, 3 * S) == ["state-3", "perimeter-3"]
    assert g.to_resend(2, 3 * S) is None  # never sent
    for s in range(4, 8):
        g.keep(s, [f"state-{s}"])
    assert g.to_resend(3, 10 * S) is None  # too old


def test_a_crashed_peers_final_message_ends_the_wait_for_it() -> None:
    g = gate()
    for k in (1, 2):
        g.on_bundle(k, f"b{k}")
        on_state(g, 1, k - 1)
        final = k == 2
        got = on_state(g, 2, k - 1, final=final)
        assert runs(got)
    # peer 2 sent its final state at step 1 (its vehicle crashed): step 3 waits for peer 1 only
    assert g.on_bundle(3, "b3") == [StartWaiting(3)]
    (run,) = runs(on_state(g, 1, 2))
    assert run.step == 3 and {m.uav_id for m in run.inbox} == {1}


def test_a_peer_whose_process_is_gone_is_no_longer_waited_for() -> None:
    g = gate()
    g.on_bundle(1, "b1")
    on_state(g, 1, 0)
    got = g.on_liveness(1, lambda: {1})
    assert got[0] == PeerGone(2, 1) and runs(got)[0].step == 1
    assert runs(g.on_bundle(2, "b2")) == [] and runs(on_state(g, 1, 1))  # 2 stays gone


@pytest.mark.parametrize(
    ("claimed_step", "reason"),
    [(-1, "negative step"), (7, "implausible step"), (10**9, "implausible step")],
)
def test_a_spoofed_step_is_rejected_and_never_waited_for(claimed_step: int, reason: str) -> None:
    """A forged state of a far step cannot make the agent wait for (or count) anything."""
    g = gate(n=2)
    g.on_bundle(1, "b1")
    got = g.on_state(b"", state(1, claimed_step, seq=1), fires(1, claimed_step), sent(perimeter=5), False)
    assert got == [Rejected("/fleet/state", 1, claimed_step, reason)]
    (run,) = runs(on_state(g, 1, 0))  # the genuine one still runs the step
    assert [m.step for m in run.inbox] == [0, 0] and list(g.inbox()) == []


def test_a_stale_step_is_rejected_in_lockstep_only() -> None:
    g = gate(n=2)
    for k in (1, 2, 3):
        g.on_bundle(k, f"b{k}")
        on_state(g, 1, k - 1)
    assert g.last_step == 3
    assert g.on_state(b"", state(1, 1), fires(1, 1), sent(), False)[0].reason == "stale step"
    rt: PeerGate = PeerGate(0, 2, 0.1, lockstep=False)
    for k in (0, 1, 2, 3):
        rt.on_bundle(k, f"b{k}")
    assert rt.on_state(b"", state(1, 1), fires(1, 1), sent(), False) == []


def test_a_front_of_a_stale_step_is_rejected_as_a_state_is_and_never_handed_on() -> None:
    """The front is admitted as the state and the map are (but for the tag: fronts are unsigned).
    Before, it skipped admission: this stale one was handed to the next step, the far one below
    stayed in the inbox for good, neither counted."""
    calls, check = _recording_tag_check()
    g = gate(n=2, check_tag=check)
    for k in (1, 2, 3):
        g.on_bundle(k, f"b{k}")
        g.on_state(b"signed", state(1, k - 1), fires(1, k - 1), sent(), False)
    assert g.last_step == 3
    assert g.on_front(1, 1, front(1, 1)) == [Rejected("/fleet/front", 1, 1, "stale step")]
    assert g.on_front(1, 10**9, front(1, 10**9)) == [Rejected("/fleet/front", 1, 10**9, "implausible step")]
    assert g.on_front(7, 3, front(7, 3)) == [Rejected("/fleet/front", 7, 3, "unknown id")]
    assert g.on_front(1, -1, None) == [Rejected("/fleet/front", 1, -1, "negative step")]
    assert list(g.inbox()) == []
    assert g.on_front(1, 3, front(1, 3)) == []  # the step this agent last ran: admitted, unsigned
    assert [c[1] for c in calls].count("/fleet/front") == 0
    g.on_bundle(4, "b4")
    (run,) = runs(g.on_state(b"signed", state(1, 3), fires(1, 3), sent(front=1), False))
    assert [(type(m).__name__, m.step) for m in run.inbox] == [
        ("PeerState", 3),
        ("PeerFires", 3),
        ("PeerFront", 3),
    ]
    assert list(g.inbox()) == []
    rt: PeerGate = PeerGate(0, 2, 0.1, lockstep=False)  # realtime: an old step is no rejection
    for k in (0, 1, 2, 3):
        rt.on_bundle(k, f"b{k}")
    assert rt.on_front(1, 1, front(1, 1)) == [] and [m.step for m in rt.inbox()] == [1]


def _recording_tag_check():
    """``(calls, check)``: a tag check that passes only ``b"signed"`` and records what it was asked."""
    calls: list[tuple] = []

    def check(data: bytes, topic: str, sender: int, auth_step: int) -> bool:
        calls.append((data, topic, sender, auth_step))
        return data == b"signed"

    return calls, check


def test_the_tag_check_is_passed_in_and_runs_after_the_cheap_checks() -> None:
    calls, check = _recording_tag_check()
    g = gate(n=2, check_tag=check)
    g.on_bundle(1, "b1")
    assert g.on_state(b"forged", state(1, 0), fires(1, 0), sent(), False) == [
        Rejected("/fleet/state", 1, 0, "bad auth")
    ]
    assert g.on_state(b"x", state(5, 0), fires(5, 0), sent(), False)[0].reason == "unknown id"
    assert calls == [(b"forged", "/fleet/state", 1, 0)]  # not asked for the unknown sender
    (run,) = runs(g.on_state(b"signed", state(1, 0), fires(1, 0), sent(), False))
    assert run.step == 1


def test_a_scheduled_offline_agent_accepts_peers_that_ran_ahead() -> None:
    """Agent 0 frozen for steps 10..14: its peers ran on, so their messages are up to 6 steps
    ahead of its last step, and genuine."""
    g: PeerGate = PeerGate(0, 2, 0.1, schedule=parse_schedule("0@1.0:1.5"))
    g.on_bundle(0, "b0")
    assert g.on_state(b"", state(1, 6), fires(1, 6), sent(), False) == []
    assert g.on_state(b"", state(1, 8), fires(1, 8), sent(), False)[0].reason == "implausible step"


def test_a_resent_bundle_of_the_answered_step_repeats_the_answer() -> None:
    g = gate(n=2)
    assert g.on_bundle(0, "b0 again") == [RepeatAnswer(0)]
    g.on_bundle(1, "b1")
    assert g.on_bundle(1, "b1 again") == []  # not answered yet: still waiting
    runs(on_state(g, 1, 0))
    assert g.on_bundle(1, "b1 again") == [RepeatAnswer(1)]
    assert g.on_bundle(0, "old") == []  # only the newest bundle is answered


def test_realtime_runs_every_newest_bundle_at_once() -> None:
    g: PeerGate = PeerGate(0, 2, 0.1, lockstep=False)
    assert [d.step for d in runs(g.on_bundle(0, "b0"))] == [0]
    assert [d.step for d in runs(g.on_bundle(2, "b2"))] == [2]
    assert g.on_bundle(1, "late") == []


def test_bad_configuration_names_the_field() -> None:
    with pytest.raises(ConfigError, match="uav_id 3 outside 0..2"):
        PeerGate(3, 3, 0.1)
    with pytest.raises(ConfigError, match="crash_threshold_steps must be >= 1, got 0"):
        PeerGate(0, 3, 0.1, crash_threshold_steps=0)


# --- edges named by the mutation run (docs/testing.md): each against the rule the docs state --------
def test_the_inbox_order_is_total_on_fuzzed_fields_and_sorts_them_first() -> None:
    """Module doc: a field that is not an int sorts as -1 (before every genuine id and sequence,
    which are >= 0); a message of another type sorts after the four kinds; the sequence decides
    between messages of one sender, step and kind."""
    a = PeerState(2, 5, 0, 0.0, 0.0, 30.0, 0.0, 0)
    b = PeerState(0, 5, 0, 0.0, 0.0, 30.0, 0.0, 0)
    fuzzed_id = PeerState(None, 5, 0, 0.0, 0.0, 30.0, 0.0, 0)  # type: ignore[arg-type]
    assert sorted([a, fuzzed_id, b], key=inbox_order) == [fuzzed_id, b, a]
    late, early = state(1, 0, seq=9), state(1, 0, seq=0)
    fuzzed_seq = PeerState(1, None, 0, 10.0, 0.0, 30.0, 0.0, 0)  # type: ignore[arg-type]
    assert sorted([late, early], key=inbox_order) == [early, late]
    assert sorted([late, fuzzed_seq, early], key=inbox_order) == [fuzzed_seq, early, late]

    class Other:  # not one of the four peer message types
        uav_id, sequence, step = 1, 1, 0

    got = sorted([Other(), front(1, 0), perimeter(1, 0)], key=inbox_order)  # type: ignore[list-item]
    assert [type(m).__name__ for m in got] == ["PeerPerimeter", "PeerFront", "Other"]


def test_a_threshold_of_one_step_is_accepted() -> None:
    """crash_threshold_steps must be >= 1 (the error says so): 1 itself is a valid threshold."""
    g: PeerGate = PeerGate(0, 3, 0.1, crash_threshold_steps=1)
    assert g.crash_threshold_steps == 1


def test_a_peers_scheduled_offline_steps_are_not_waited_for() -> None:
    """Peer 1 is offline for steps 10..14 (1.0 s to 1.5 s at 0.1 s): step 11 needs nothing of it."""
    g: PeerGate = PeerGate(0, 2, 0.1, schedule=parse_schedule("1@1.0:1.5"))
    g.on_bundle(0, "b0")
    for k in range(1, 11):
        g.on_bundle(k, f"b{k}")
        assert runs(on_state(g, 1, k - 1))
    assert [d.step for d in runs(g.on_bundle(11, "b11"))] == [11]


def test_only_the_agents_own_offline_windows_widen_the_plausible_steps() -> None:
    """A peer's offline window makes that peer fall behind, never run ahead of this agent."""
    g: PeerGate = PeerGate(0, 2, 0.1, schedule=parse_schedule("1@1.0:1.5"))
    g.on_bundle(0, "b0")
    assert g.on_state(b"", state(1, 2), fires(1, 2), sent(), False)[0].reason == "implausible step"


def test_in_realtime_a_peer_may_run_ahead_by_the_crash_threshold() -> None:
    """Without the wait a peer keeps running while this agent misses steps: up to
    ``crash_threshold_steps`` beyond the next step before it would count this one crashed."""
    rt: PeerGate = PeerGate(0, 2, 0.1, lockstep=False, crash_threshold_steps=4)
    rt.on_bundle(0, "b0")
    assert rt.on_state(b"", state(1, 5), fires(1, 5), sent(), False) == []
    assert rt.on_state(b"", state(1, 6), fires(1, 6), sent(), False)[0].reason == "implausible step"


def test_in_realtime_a_repeated_bundle_is_not_run_again() -> None:
    rt: PeerGate = PeerGate(0, 2, 0.1, lockstep=False)
    rt.on_bundle(0, "b0")
    assert [d.step for d in runs(rt.on_bundle(2, "b2"))] == [2]
    assert rt.on_bundle(2, "b2 again") == []


def test_a_newer_bundle_runs_the_one_it_overtook_first() -> None:
    g = gate(n=2)
    assert g.on_bundle(1, "b1") == [StartWaiting(1)]
    got = g.on_bundle(2, "b2")
    assert got[0] == RunStep(1, "b1", ()) and got[1:] == [StartWaiting(2)]


def test_a_perimeters_tag_is_checked_on_its_bytes_and_step() -> None:
    calls, check = _recording_tag_check()
    g = gate(n=2, check_tag=check)
    g.on_bundle(1, "b1")
    assert g.on_perimeter(b"forged", perimeter(1, 0)) == [Rejected("/fleet/perimeter", 1, 0, "bad auth")]
    assert g.on_perimeter(b"signed", perimeter(1, 0)) == []
    assert calls == [(b"forged", "/fleet/perimeter", 1, 0), (b"signed", "/fleet/perimeter", 1, 0)]


def test_a_coverage_message_the_state_announced_is_waited_for() -> None:
    """The state says the peer sent one message on /fleet/coverage/weights (loss index 3)."""
    g = gate(n=2)
    g.on_bundle(1, "b1")
    counts = list(sent())
    counts[3] = 1
    assert g.on_state(b"", state(1, 0), fires(1, 0), tuple(counts), False) == []
    assert g.on_arrival(1, 1, 3) == []  # the peer's next step: not this one's
    assert g.on_arrival(1, 0, 4) == []  # another topic
    assert [d.step for d in runs(g.on_arrival(1, 0, 3))] == [1]


def test_the_wait_is_measured_from_the_bundles_arrival() -> None:
    g = gate(n=2)
    g.on_bundle(1, "b1", now_ns=10 * S)
    assert g.on_liveness(12 * S, lambda: {1}) == []  # 2 s: not long enough to report
    got = g.on_liveness(15 * S + S // 2, lambda: {1})
    assert got[0] == StillWaiting(1, 5.5, g.wait.describe(1))
    assert got[1:] == [AskResend(1, 0, 5.5)]


def test_a_peer_marked_gone_is_not_waited_for() -> None:
    g = gate()
    g.mark_gone(2)
    g.on_bundle(1, "b1")
    assert [d.step for d in runs(on_state(g, 1, 0))] == [1]


def test_peer_0_is_a_fleet_member_and_the_fleet_size_is_not() -> None:
    g = gate(uid=1, n=2)
    g.on_bundle(1, "b1")
    assert g.on_state(b"", state(2, 0), fires(2, 0), sent(), False)[0].reason == "unknown id"
    assert [d.step for d in runs(on_state(g, 0, 0))] == [1]
