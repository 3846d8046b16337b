"""Peer link under random hostile messages: a property test, kept in its own
file because it takes seconds (the mutation run of peer_link uses the deterministic tests)."""

from fire_uav_agent.peer_link import FireEntry, PeerFires, PeerLink, PeerState, Verdict
from hypothesis import given, settings
from hypothesis import strategies as st

U32 = 2**32 - 1


def genuine(j: int, step: int, x: float = 1.0) -> PeerState:
    return PeerState(j, step + 1, step, x, 2.0, 30.0, 0.1, 1)


# --- fuzz ------------------------------------------------------------------------------------
ints = st.one_of(st.integers(-5, 12), st.integers(-(2**63), 2**64), st.just(U32))
floats = st.floats(allow_nan=True, allow_infinity=True)
hostile_state = st.builds(PeerState, ints, ints, ints, floats, floats, floats, floats, st.integers(-1, 300))
hostile_fires = st.builds(
    PeerFires,
    ints,
    ints,
    ints,
    st.lists(
        st.builds(FireEntry, ints, st.booleans(), floats, floats, floats, floats, floats, floats), max_size=4
    ).map(tuple),
)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.lists(st.one_of(hostile_state, hostile_fires), max_size=6), min_size=1, max_size=30),
    st.floats(0.0, 0.3),
)
def test_fuzz_no_message_poisons_the_link(batches, loss):
    """Random messages between genuine ones: no crash, every message counted once, and a genuine
    message is rejected only as the duplicate of a forged one of the same sender, topic and step."""
    n = 3
    link = PeerLink(0, n, seed=7, loss_probability=loss, control_period_s=0.1, crash_threshold_steps=1000)
    forged_accepted: set[tuple[int, bool, int]] = set()
    total = 0
    for k, batch in enumerate(batches, start=1):
        inbox: list = list(batch) + [genuine(j, k - 1) for j in (1, 2)]
        inbox += [PeerFires(j, k, k - 1, (FireEntry(1, True, 1.0, 2.0, 3.0),)) for j in (1, 2)]
        for m in inbox:
            fires = isinstance(m, PeerFires)
            v = link.receive_fires(m, now_step=k) if fires else link.receive_state(m, now_step=k)
            total += 1
            is_genuine = m.sequence == m.step + 1 == k and m in inbox[len(batch) :]
            if is_genuine:
                assert v != Verdict.REJECTED or (m.uav_id, fires, m.step) in forged_accepted
            elif v == Verdict.ACCEPTED:
                forged_accepted.add((m.uav_id, fires, m.step))
        link.end_step(k)
        assert link.crashed_ids() == []
    assert link.received + link.lost + link.rejected == total
    assert sum(link.reject_reasons.values()) == link.rejected
