"""Front sharing (front_consensus) against independent truth (mutation testing).

Truths: the module doc's message contents (the active front, then the cells sent last time that
left it, with their newer state and time), checked on hand-built rasters; and its convergence
claim, checked against one picture that saw every sighting: after as many rounds as the graph's
diameter, every agent of a line of three holds that picture's front.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.fire_front import FrontCells, FrontConfig, FrontPicture
from fire_uav_agent.front_consensus import FrontSharing, PeerFront, concat
from fire_uav_common.constants import CellState
from hypothesis import example, given, settings
from hypothesis import strategies as st

B, N, U = int(CellState.BURNING), int(CellState.BURNED), int(CellState.UNBURNED)
CS = 10.0


def pic(nx: int = 6, ny: int = 3) -> FrontPicture:
    return FrontPicture(FrontConfig((0.0, nx * CS, 0.0, ny * CS), CS, min_cells_for_centre=10**6))


def xy(cells: list[tuple[int, int]]) -> tuple[np.ndarray, np.ndarray]:
    a = np.array(cells, dtype=float).reshape(-1, 2)
    return (a[:, 1] + 0.5) * CS, (a[:, 0] + 0.5) * CS  # (row, col) -> centres


def keyset(p: FrontPicture, c: FrontCells) -> list[tuple[int, int, int, float]]:
    i, j, _ = p.index(c.x_m, c.y_m)
    return sorted(
        (int(a), int(b), int(s), float(t)) for a, b, s, t in zip(i, j, c.state, c.t_obs_s, strict=True)
    )


def test_messages_carry_the_front_then_retract_what_left_it_once() -> None:
    p = pic()
    cells = [(1, 1), (1, 2), (1, 3)]
    p.observe(*xy(cells), np.array([B, B, B]), 1.0)
    sh = FrontSharing(recent_s=0.5)  # recent sightings: see the next test
    m1 = sh.message(p, 1.0)
    assert keyset(p, m1) == keyset(p, p.front(1.0)) and len(m1) == 3
    p.observe(*xy([(1, 2)]), np.array([N]), 2.0)  # the middle cell put out
    m2 = sh.message(p, 2.0)
    assert keyset(p, m2) == [(1, 1, B, 1.0), (1, 2, N, 2.0), (1, 3, B, 1.0)]  # no cell twice
    assert m2.state.dtype == np.int64
    m3 = sh.message(p, 3.0)  # the retraction was sent: not again
    assert keyset(p, m3) == [(1, 1, B, 1.0), (1, 3, B, 1.0)]
    # a receiver that got only the first message learns the drop from the second
    q = pic()
    q.merge(m1)
    q.merge(m2)
    assert keyset(q, q.front(2.0)) == keyset(p, p.front(2.0))


def test_a_recent_sighting_off_the_front_is_repeated_for_recent_s_then_dropped() -> None:
    """A cell first seen BURNED (never on this agent's front) is in every message for
    ``recent_s`` after its sighting, so a peer that misses one message still learns it."""
    p = pic()
    p.observe(*xy([(1, 1)]), np.array([B]), 1.0)
    p.observe(*xy([(1, 4)]), np.array([N]), 2.0)  # seen burnt; never on the front
    sh = FrontSharing(recent_s=3.0)
    for t in (2.0, 3.0, 5.0):
        assert (1, 4, N, 2.0) in keyset(p, sh.message(p, t)), t
    assert (1, 4, N, 2.0) not in keyset(p, sh.message(p, 5.5))
    # an interior burning cell (every neighbour burning or burnt) is shared while it is recent
    q = pic(3, 3)
    q.observe(*xy([(r, c) for r in range(3) for c in range(3)]), np.full(9, B), 1.0)
    q.observe(*xy([(0, 0)]), np.array([N]), 1.5)
    msg = keyset(q, FrontSharing(recent_s=3.0).message(q, 2.0))
    assert [k for k in msg if k[:2] == (1, 1)] == [(1, 1, B, 1.0)]
    with pytest.raises(ValueError, match="recent_s"):
        FrontSharing(recent_s=-1.0)
    with pytest.raises(ValueError, match="recent_s"):
        FrontSharing(recent_s=float("nan"))
    # a zero window still shares what was seen at the message's own time
    assert (1, 4, N, 2.0) in keyset(p, FrontSharing(recent_s=0.0).message(p, 2.0))
    # the default window is the documented 3 s; shared sightings carry no rate of spread (NaN)
    d = FrontSharing().message(p, 5.0)
    k = keyset(p, d).index((1, 4, N, 2.0))
    assert np.isnan(d.ros_mps[k]) and d.ros_mps.dtype == float
    assert (1, 4, N, 2.0) not in keyset(p, FrontSharing().message(p, 5.01))


def test_a_cell_that_aged_off_the_front_is_retracted_with_its_old_sighting() -> None:
    """A front cell not seen for ``max_age_s`` leaves the front; the message still names it (with
    the time it was last seen), so a receiver holding a newer sighting keeps its own."""
    p = FrontPicture(FrontConfig((0.0, 30.0, 0.0, 10.0), CS, max_age_s=5.0, min_cells_for_centre=10**6))
    p.observe(*xy([(0, 0), (0, 1)]), np.array([B, U]), 1.0)
    sh = FrontSharing()
    assert len(sh.message(p, 1.0)) == 1
    m = sh.message(p, 7.0)
    assert keyset(p, m) == [(0, 0, B, 1.0)]
    assert len(sh.message(p, 8.0)) == 0


def test_concat_keeps_every_column_in_order() -> None:
    a = FrontCells(np.array([1.0]), np.array([2.0]), np.array([B]), np.array([3.0]), np.array([0.4]))
    b = FrontCells(
        np.array([5.0, 6.0]),
        np.array([7.0, 8.0]),
        np.array([N, U]),
        np.array([9.0, 10.0]),
        np.array([np.nan, 1.5]),
    )
    c = concat(a, b)
    assert c.x_m.tolist() == [1.0, 5.0, 6.0] and c.y_m.tolist() == [2.0, 7.0, 8.0]
    assert c.state.tolist() == [B, N, U] and c.state.dtype == np.int64
    assert c.t_obs_s.tolist() == [3.0, 9.0, 10.0]
    assert c.ros_mps[0] == 0.4 and np.isnan(c.ros_mps[1]) and c.ros_mps[2] == 1.5
    pf = PeerFront(3, 7, 11, c, 30.0)
    assert (pf.uav_id, pf.sequence, pf.step, len(pf.cells), pf.cell_size_m) == (3, 7, 11, 3, 30.0)


@settings(max_examples=12, deadline=None)
@given(
    sightings=st.lists(
        st.tuples(st.integers(0, 2), st.integers(0, 5), st.sampled_from([U, B, N])), min_size=1, max_size=14
    ),
)
@example(sightings=[(2, 4, N), (0, 0, U), (1, 4, B), (1, 5, B), (2, 5, B)])
def test_one_agents_front_reaches_the_far_end_of_a_line_of_three(sightings) -> None:
    """Agent 0 sees random cells of a 3 x 6 raster at t = 1, 2, ... (any order of states); then,
    with no new sightings, each round every agent merges its neighbours' messages (line
    0 - 1 - 2). After two rounds (the diameter) agents 1 and 2 hold agent 0's front, which is
    the front of everything seen. (Several observers: the next test.)

    The messages start only after the last sighting, so their window of recent sightings spans
    them all (agents send one every step, each carrying the sightings of its last ``recent_s``).
    With the default 3 s window the example above failed: cell (2, 4), seen BURNED at t = 1 and
    never on the front, was in no message, so the peers kept its burning neighbour (2, 5) on
    their front (a test error, not the module's: agents share from their first sighting on)."""
    agents = [pic(), pic(), pic()]
    for t, (i, j, s) in enumerate(sightings, start=1):
        x, y = xy([(i, j)])
        agents[0].observe(x, y, np.array([s]), float(t))
    t_end = float(len(sightings))
    sharing = [FrontSharing(recent_s=t_end) for _ in range(3)]
    for _ in range(2):
        msgs = [sharing[k].message(agents[k], t_end) for k in range(3)]
        for k, nbrs in ((0, (1,)), (1, (0, 2)), (2, (1,))):
            for n in nbrs:
                agents[k].merge(msgs[n])
    expect = keyset(agents[0], agents[0].front(t_end))
    for a in agents[1:]:
        assert keyset(a, a.front(t_end)) == expect


def test_a_cell_seen_burnt_by_one_agent_leaves_the_front_of_a_peer_that_saw_it_burning() -> None:
    """UAV 1 sees cell X burning at t = 1 s; UAV 0 passes at t = 2 s, after a drop put X out, and
    sees it BURNED. Newest wins per cell, so after they exchange messages neither should hold X
    on its front."""
    a0, a1 = pic(), pic()
    x, y = xy([(1, 1), (1, 2)])
    a1.observe(x, y, np.array([B, U]), 1.0)
    a0.observe(x[:1], y[:1], np.array([N]), 2.0)
    s0, s1 = FrontSharing(), FrontSharing()
    for _ in range(3):
        m0, m1 = s0.message(a0, 3.0), s1.message(a1, 3.0)
        a0.merge(m1)
        a1.merge(m0)
    assert len(a0.front(3.0)) == 0
    assert len(a1.front(3.0)) == 0


@settings(max_examples=15, deadline=None)
@given(
    sightings=st.lists(
        st.tuples(st.integers(0, 2), st.integers(0, 2), st.integers(0, 5), st.integers(0, 2)),
        min_size=1,
        max_size=16,
    ),
)
def test_several_observers_fronts_converge_on_the_front_of_everything_seen(sightings) -> None:
    """Random agents of a line 0 - 1 - 2 see random cells at t = 1, 2, ...; each cell's states
    follow the fire's own order (UNBURNED, then BURNING, then BURNED: a fire never un-burns).
    After two rounds of messages every agent's front is the front of one picture that saw
    every sighting (module doc). Before sharing recent sightings, a cell first seen BURNED by
    one agent stayed on the front of a peer that had seen it BURNING."""
    order = (U, B, N)
    agents, ref = [pic(), pic(), pic()], pic()
    last: dict[tuple[int, int], int] = {}
    for t, (k, i, j, r) in enumerate(sightings, start=1):
        r = max(r, last.get((i, j), 0))
        last[(i, j)] = r
        x, y = xy([(i, j)])
        agents[k].observe(x, y, np.array([order[r]]), float(t))
        ref.observe(x, y, np.array([order[r]]), float(t))
    t_end = float(len(sightings))
    sharing = [FrontSharing(recent_s=100.0) for _ in range(3)]
    for _ in range(2):
        msgs = [sharing[k].message(agents[k], t_end) for k in range(3)]
        for k, nbrs in ((0, (1,)), (1, (0, 2)), (2, (1,))):
            for n in nbrs:
                agents[k].merge(msgs[n])
    expect = keyset(ref, ref.front(t_end))
    for a in agents:
        assert keyset(a, a.front(t_end)) == expect


def test_the_same_cell_size_is_one_rasters_within_float32_rounding():
    from fire_uav_agent.front_consensus import same_cell_size

    assert same_cell_size(30.48, float(np.float32(30.48)))  # 100 ft, as the wire's float32 carries it
    assert not same_cell_size(30.0, 10.0) and not same_cell_size(10.0, 10.001)
    assert not same_cell_size(math.nan, 10.0) and not same_cell_size(0.0, 0.0)
    assert same_cell_size(0.5, 0.5)  # any positive side is a raster's, a sub-metre one too
