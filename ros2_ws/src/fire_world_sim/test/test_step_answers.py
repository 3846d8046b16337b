"""The world's lockstep answer gate without ROS: which answers a step takes, which it rejects
(and why), which copies it drops quietly, when it re-sends, and what a lost agent changes."""

from __future__ import annotations

import pytest
from fire_uav_common.constants import PayloadAction
from fire_world_sim.step_answers import IGNORE, TAKE, AnswerGate, AnswerVerdict
from fire_world_sim.vehicle import Command

T1 = 100_000_000  # [ns] stamp of the answers to step 0
S = 1_000_000_000  # [ns] one second of the steady clock


def started(lockstep: bool = True, uids: tuple[int, ...] = (0, 1, 2)) -> AnswerGate:
    g = AnswerGate(lockstep=lockstep)
    g.started = True
    g.start_sending(0)
    for u in uids:
        g.record_sent(u, bytes([u]))
    g.await_answers(T1, set(uids), now_ns=0)
    return g


def answer(
    g: AnswerGate, uid: int, ns: int = T1, tag: bytes | None = None
) -> tuple[AnswerVerdict, AnswerVerdict]:
    """An unsigned command and a payload request of ``uid``, taken if admitted."""
    vc = g.admit_command(uid, ns, crashed=False, world_t_ns=0)
    if vc.take:
        g.record_command(uid, Command(20.0, 0.0, 0.0))
    vp = g.admit_payload(uid, ns, crashed=False, world_t_ns=0, tag=tag)
    if vp.take:
        g.record_payload(uid, PayloadAction.NONE)
    return vc, vp


def test_the_step_completes_once_every_command_and_payload_request_is_in() -> None:
    g = started()
    for uid in (2, 0):  # out of order
        assert answer(g, uid) == (TAKE, TAKE)
        assert not g.complete
    assert g.admit_command(1, T1, crashed=False, world_t_ns=0) == TAKE
    g.record_command(1, Command(20.0, 0.0, 0.0))
    assert not g.complete  # the payload request of 1 is awaited too
    assert g.admit_payload(1, T1, crashed=False, world_t_ns=0, tag=None) == TAKE
    g.record_payload(1, PayloadAction.DROP)
    assert g.complete
    commands, payload = g.take_inputs()
    assert sorted(commands) == [0, 1, 2] and payload == {1: [int(PayloadAction.DROP)]}
    assert g.take_inputs() == ({}, {})  # handed over once


def test_a_wrong_stamp_or_a_crashed_vehicle_is_rejected_with_its_reason() -> None:
    g = started()
    assert g.admit_command(0, T1 + 1, crashed=False, world_t_ns=0) == AnswerVerdict(
        False, "stamp out of range"
    )
    assert g.admit_command(0, T1, crashed=True, world_t_ns=0) == AnswerVerdict(False, "crashed vehicle")
    assert g.waiting == {0, 1, 2}  # nothing taken


def test_before_step_0_nothing_is_a_rejection() -> None:
    g = AnswerGate(lockstep=True)
    assert g.admit_command(0, T1, crashed=False, world_t_ns=0) == IGNORE
    assert g.admit_payload(0, 0, crashed=False, world_t_ns=0, tag=None) == IGNORE


def test_a_replayed_tag_is_a_duplicate_and_tags_reset_each_step() -> None:
    g = started(uids=(0, 1))
    assert answer(g, 0, tag=b"t0")[1] == TAKE
    # a second request with the same tag (a replay by someone else) is rejected
    assert g.admit_payload(0, T1, crashed=False, world_t_ns=0, tag=b"t0") == AnswerVerdict(False, "duplicate")
    g.take_inputs()
    g.await_answers(2 * T1, {0, 1}, now_ns=0)
    assert g.admit_payload(0, 2 * T1, crashed=False, world_t_ns=0, tag=b"t0") == TAKE


def test_a_resend_names_the_late_agents_and_their_second_answer_is_dropped_quietly() -> None:
    g = started()
    answer(g, 0)
    assert g.resend_due(now_ns=4 * S, after_wall_s=5.0) is None
    assert g.resend_due(now_ns=5 * S, after_wall_s=5.0) == [1, 2]
    assert g.resend_due(now_ns=6 * S, after_wall_s=5.0) is None  # counted from the last re-send
    assert answer(g, 1, tag=b"a") == (TAKE, TAKE)
    # the agent answers the copy too: the same answer again is no rejection
    assert g.admit_payload(1, T1, crashed=False, world_t_ns=0, tag=b"a") == IGNORE
    # ... and after the world moved on, its late stamp is no rejection either
    answer(g, 2)
    g.take_inputs()
    g.await_answers(2 * T1, {0, 1, 2}, now_ns=6 * S)
    assert g.admit_command(1, T1, crashed=False, world_t_ns=0) == IGNORE
    assert g.admit_command(0, T1, crashed=False, world_t_ns=0) == AnswerVerdict(False, "stamp out of range")


def test_a_lost_agent_is_not_waited_for_now_or_later() -> None:
    g = started()
    answer(g, 0)
    answer(g, 1)
    assert not g.complete
    g.mark_lost(2)
    assert g.complete
    g.take_inputs()
    g.await_answers(2 * T1, {0, 1, 2}, now_ns=0)
    assert g.waiting == {0, 1} and g.waiting_payload == {0, 1}


def test_answers_to_the_last_bundle_are_ignored() -> None:
    g = started()
    g.finished = True
    assert answer(g, 0) == (IGNORE, IGNORE)


@pytest.mark.parametrize(
    "ns, problem", [(0, None), (T1, None), (T1 + 1, "stamp out of range"), (-1, "stamp out of range")]
)
def test_realtime_takes_any_stamp_up_to_the_world_time(ns: int, problem: str | None) -> None:
    g = AnswerGate(lockstep=False)
    assert g.stamp_problem(False, ns, world_t_ns=T1) == problem
    if problem is None:
        assert g.admit_command(0, ns, crashed=False, world_t_ns=T1) == TAKE
        g.record_command(0, None)  # a non-finite command is taken as a miss
        g.record_payload(0, PayloadAction.REFILL)
        assert g.take_inputs() == ({0: None}, {0: [int(PayloadAction.REFILL)]})
