"""The relay of two monitors at the head (split.relay_split, MonitorConfig.split = "relay").

References are hand-made perimeters of 360 cells (index 0 the UAV's cell, growing against the
flying direction) with a fast stretch whose centre, the head, is known by construction; which
monitor holds the head follows from the two distances to it, counted by hand.
"""

import numpy as np
import pytest
from fire_perimeter_monitor.errors import InputError
from fire_perimeter_monitor.planner import ImportanceMonitor, MonitorConfig
from fire_perimeter_monitor.split import head_index, relay_split

M = 360
SPACING_M = 5.0


def _ros(head: int, half_cells: int = 5, fast: float = 4.0, slow: float = 0.5) -> np.ndarray:
    """Slow everywhere, 0.75 x fast over +-half_cells about ``head``, fast on +-2 cells about it
    (so the +-2-cell average peaks at ``head`` exactly)."""
    r = np.full(M, slow)
    r[[(head + d) % M for d in range(-half_cells, half_cells + 1)]] = 0.75 * fast
    r[[(head + d) % M for d in range(-2, 3)]] = fast
    return r


def test_head_is_the_fast_stretch_not_a_single_spike():
    """One cell at 10 m/s among slow ones against 31 cells at 3-4 m/s centred on 100: averaged
    over +-2 cells the spike is (10 + 4 x 0.5) / 5 = 2.4 < 4, so the head is in the stretch (the
    plain argmax would say 5)."""
    r = _ros(100, half_cells=15)
    r[5] = 10.0
    assert 85 <= head_index(r) <= 115


def test_the_peer_nearer_the_head_holds_it_and_we_own_the_rest():
    """Head at 100, the peer at 180 (80 cells from it), us at 0 (100 cells): the peer holds.
    The head arc is +-10 cells (50 m); we own every other cell."""
    owned = relay_split(_ros(100), SPACING_M, 180, 50.0, mine_on_tie=True)
    head_arc = np.zeros(M, dtype=bool)
    head_arc[90:111] = True
    assert np.array_equal(owned, ~head_arc)


def test_we_hold_the_head_when_we_are_nearer_and_the_roles_swap_with_positions():
    """Same peer cell, head moved to cell 20 (us 20 cells away, the peer 160): we hold cells
    10..30 only. A rule that fixed the roles (e.g. by id) would fail one of these two tests."""
    owned = relay_split(_ros(20), SPACING_M, 180, 50.0, mine_on_tie=False)
    expect = np.zeros(M, dtype=bool)
    expect[10:31] = True
    expect[0] = True  # our own cell
    assert np.array_equal(owned, expect)


def test_distance_counts_round_the_closed_perimeter():
    """Head at 340: 20 cells from us going the other way round (not 340), 160 from the peer."""
    owned = relay_split(_ros(340), SPACING_M, 180, 50.0, mine_on_tie=False)
    assert owned[330:351].all() and owned.sum() == 21 + 1


def test_tie_goes_to_the_flag():
    """Head at 90, us at 0 and the peer at 180: 90 cells each."""
    assert relay_split(_ros(90), SPACING_M, 180, 50.0, mine_on_tie=True).sum() == 21 + 1
    assert relay_split(_ros(90), SPACING_M, 180, 50.0, mine_on_tie=False).sum() == M - 21


@pytest.mark.parametrize("seed", range(20))
def test_the_two_monitors_cover_every_cell_once(seed):
    """Each monitor computes its mask alone, from its own cell; the peer's view is the same
    perimeter rolled to start at its cell. Every cell but the two UAVs' own is owned by exactly
    one of them, whatever the rates and positions."""
    rng = np.random.default_rng(seed)
    r = rng.uniform(0.0, 4.0, M)
    k = int(rng.integers(1, M))
    half = float(rng.uniform(0.0, 600.0))
    mine = relay_split(r, SPACING_M, k, half, mine_on_tie=True)
    theirs = np.roll(relay_split(np.roll(r, -k), SPACING_M, M - k, half, mine_on_tie=False), k)
    rest = np.ones(M, dtype=bool)
    rest[[0, k]] = False
    assert np.all(mine[rest] ^ theirs[rest])


def test_the_holder_never_owns_more_than_half():
    owned = relay_split(_ros(20), SPACING_M, 180, 1e6, mine_on_tie=False)
    assert owned.sum() <= M // 2 + 1


def test_the_arc_widens_to_the_fast_stretch():
    """A fast stretch of +-40 cells about 100 and a head arc of +-10: with fast_fraction 0.5 the
    holder's arc is the stretch (an arc of fixed length would leave its flanks to the peer)."""
    owned = relay_split(_ros(100, half_cells=40), SPACING_M, 300, 50.0, mine_on_tie=True, fast_fraction=0.5)
    # we are 100 cells from the head, the peer at 300 is 160: we hold
    assert owned[60:141].all() and not owned[150:350].any()
    narrow = relay_split(_ros(100, half_cells=40), SPACING_M, 300, 50.0, mine_on_tie=True)
    assert not narrow[60:85].any()


def test_bad_input_is_named():
    with pytest.raises(InputError, match="peer cell"):
        relay_split(_ros(0), SPACING_M, 0, 50.0, mine_on_tie=True)
    with pytest.raises(InputError, match="spacing_m"):
        relay_split(_ros(0), 0.0, 5, 50.0, mine_on_tie=True)
    with pytest.raises(ValueError, match="relay_fast_fraction"):
        MonitorConfig(cell_size_m=5.0, speed_mps=50.0, split="relay", relay_fast_fraction=2.0)


def test_monitor_relay_holds_the_fast_arc_when_nearer():
    """Through the monitor: a 500 m circle, us at 0 deg flying CCW (cells index clockwise), the
    peer opposite, the fast arc on cells 30..89 (nearer us): we hold it, the slow far side is the
    peer's."""
    m = ImportanceMonitor(
        MonitorConfig(cell_size_m=5.0, speed_mps=50.0, center_x_m=0.0, center_y_m=0.0, split="relay")
    )
    m.merge(
        {"center_x_m": 0.0, "center_y_m": 0.0, "outer_distance_m": np.full(M, 500.0),
         "outer_visit_time_s": np.full(M, 10.0)},
        peer_id=1, peer_pos_m=(-500.0, 0.0), t_s=10.0,
    )  # fmt: skip
    m.uav_xy, m.t_s = (500.0, 0.0), 10.0
    th = -np.radians(np.arange(M))
    cells = 500.0 * np.column_stack([np.cos(th), np.sin(th)])
    r = np.full(M, 0.5)
    r[30:90] = 4.0
    owned = m._peer_weight(cells, r) > 0
    assert owned[30:90].all() and not owned[135:330].any()
