"""The agent's aim over a raster fire (fire_uav_agent.raster_role.RasterSuppression.target), called
directly on hand-made fronts and own cells.

Truths: a front cell belongs to the own cell when its *nearest grid point* does (found by brute
force over the grid's points, FF Eqs. 6-7 on the grid); the written rules of ``target`` and of the
tactics module doc: the front as of the bundle's time (``max_age_s``), the flank anchor chosen
once, the aim nearest the Eq. 9 centroid (not the UAV), the layers that share an airspace with the
avoider's own vertical band, the standoff point (by hand: a 3-4-5 triangle), and the re-centring
of the active fire entry nearest the aim point.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from fire_uav_agent.agent_core import Agent, AgentConfig
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.separation import SeparationConfig
from fire_uav_common.codecs.sensor_bundle import Bundle, Samples
from fire_uav_common.codecs.uav_state import FireEntry, PeerState
from fire_uav_common.constants import CellState, Objective, VehicleStatus

AREA = (0.0, 300.0, 0.0, 300.0)  # a 60 x 60 coverage grid of 5 m
AIR = VehicleStatus.AIRBORNE
B = int(CellState.BURNING)
FIRE = (FireEntry(1, True, 150.0, 150.0, 30.0),)


def _agent(uid: int = 1, n: int = 2, tactic: str = "head", **kw) -> Agent:
    a = Agent(AgentConfig(uav_id=uid, uav_count=n, area_m=AREA, loss_probability=0.0, **kw))
    a.raster.tactic = dataclasses.replace(a.raster.tactic, tactic=tactic)
    return a


class _Picture:
    """A front picture that shows a given front (target reads only ``front(t_s)``)."""

    def __init__(self, front: FrontCells) -> None:
        self.shown = front

    def front(self, t_s: float | None = None) -> FrontCells:
        return self.shown


def _front(xy, ros=None) -> FrontCells:
    a = np.asarray(xy, dtype=float).reshape(-1, 2)
    n = a.shape[0]
    r = np.full(n, np.nan) if ros is None else np.asarray(ros, dtype=float)
    return FrontCells(a[:, 0], a[:, 1], np.full(n, B), np.zeros(n), r)


def _bundle(stamp_s: float = 10.0, cells=None, cell_size_m: float = 5.0) -> Bundle:
    return Bundle(
        int(stamp_s * 10), stamp_s, Samples(), np.zeros((0, 4)), 2000.0, int(AIR), 0.1, cells, cell_size_m
    )


def _aim(a: Agent, front: FrontCells, cell, s=(150.0, 150.0), aim=FIRE, peers=None):
    a.raster.front = _Picture(front)
    s4 = np.array([s[0], s[1], 30.0, 0.0])
    return a.raster.target(_bundle(), s4, aim, np.asarray(cell, bool), 20.0, peers)


def _nearest_point_in(a: Agent, cell: np.ndarray, x: float, y: float) -> bool:
    d = np.hypot(a.grid.points[:, 0] - x, a.grid.points[:, 1] - y)
    return bool(cell[int(np.argmin(d))])


@pytest.mark.parametrize(("axis", "k"), [(0, 0), (0, 30), (0, 59), (1, 0), (1, 30), (1, 59)])
def test_a_front_cell_is_in_the_own_cell_when_its_nearest_grid_point_is(axis, k) -> None:
    """The own cell is one grid column (axis 0) or row (axis 1), ``k`` (edges included). One front
    cell A lies 1.5 m off that line's points (inside), five lie 1.5 m off the neighbouring line's
    points toward it (outside: their nearest points are the neighbour's), 200 m along from A. Only A
    is in the cell, so the aim is A, though the centroid lies by the five."""
    a = _agent()
    ny, nx = a.grid.shape
    assert (ny, nx, a.grid.resolution_m) == (60, 60, 5.0)
    line = a.grid.xs if axis == 0 else a.grid.ys
    kn = k + 1 if k + 1 < len(line) else k - 1  # the neighbouring line
    across_a = line[k] + 1.5 if kn > k else line[k] - 1.5
    across_n = line[kn] - 1.5 if kn > k else line[kn] + 1.5
    along = [(250.0, True)] + [(50.0 + 3.0 * m, False) for m in range(5)]
    pts = [(across_a if mine else across_n, y) for y, mine in along]
    if axis == 1:
        pts = [(y, x) for x, y in pts]
    gi, gj = np.divmod(np.arange(nx * ny), nx)
    cell = (gj if axis == 0 else gi) == k
    assert [_nearest_point_in(a, cell, x, y) for x, y in pts] == [True] + [False] * 5  # brute force
    _, _, xy = _aim(a, _front(pts), cell)
    assert xy == pytest.approx(pts[0])


def test_the_aim_is_the_own_cell_front_cell_nearest_the_centroid_not_the_uav() -> None:
    """Eq. 9's centroid of the density (five cells near (200, 200), one at (50, 50)) lies by the
    five; the UAV over the lone cell still aims at one of the five."""
    a = _agent()
    five = [(200.0 + 5.0 * m, 200.0) for m in range(5)]
    _, _, xy = _aim(a, _front([(50.0, 50.0), *five]), np.ones(3600, bool), s=(50.0, 50.0))
    assert tuple(xy) in {tuple(p) for p in five}


def test_the_front_is_the_one_at_the_bundles_time() -> None:
    """A front seen at 1 s is still aimed at within ``max_age_s`` and gone after it (fire_front): a
    bundle stamped later than that has no front to aim at, and no release."""
    a = _agent()
    xs, ys = np.meshgrid(150.0 + 5.0 * np.arange(-2, 3), 150.0 + 5.0 * np.arange(-2, 3))
    st = np.where((np.abs(xs - 150.0) <= 5.0) & (np.abs(ys - 150.0) <= 5.0), B, int(CellState.UNBURNED))
    a.raster.fuse(_bundle(1.0, (xs.ravel(), ys.ravel(), st.ravel())), AIR, 1.0)
    s4 = np.array([150.0, 150.0, 30.0, 0.0])
    cell = np.ones(3600, bool)
    assert a.raster.target(_bundle(2.0), s4, FIRE, cell, 20.0)[2] is not None
    late = 1.0 + a.front.cfg.max_age_s + 10.0
    assert a.raster.target(_bundle(late), s4, FIRE, cell, 20.0) == (FIRE, False, None)


def test_the_flank_anchor_is_chosen_once() -> None:
    """Flank attack (tactics doc): the anchor is the slowest front cell when the attack starts, kept
    after. A later front whose slowest cells are 200 m east still weighs the west cells (near the
    first anchor) most, so the centroid and the aim stay west."""
    a = _agent(tactic="flank")
    cell = np.ones(3600, bool)
    _aim(a, _front([(50.0, 150.0), (60.0, 150.0)], ros=[0.05, 0.4]), cell)
    assert a.raster.anchor == (50.0, 150.0)
    west = [(50.0 + 5.0 * m, 150.0) for m in range(3)]
    east = [(250.0 + 5.0 * m, 150.0) for m in range(3)]
    _, _, xy = _aim(a, _front(west + east, ros=[0.5] * 3 + [0.01] * 3), cell)
    assert tuple(xy) in set(west)
    assert a.raster.anchor == (50.0, 150.0)


def _peer0(aim_xy) -> dict[int, PeerState]:
    return {
        0: PeerState(0, 1, 99, aim_xy[0], aim_xy[1], 30.0, 0.0, int(Objective.SUPPRESS), 1, 2000.0, *aim_xy)
    }


def test_the_standoff_is_60_m_from_the_taken_aim_toward_the_uav() -> None:
    """UAV 3 of 5 shares UAV 0's layer; UAV 0 works the only front cell (150, 150): UAV 3 at
    (180, 110) waits 60 m from it toward itself, (186, 102) (3-4-5)."""
    a = _agent(uid=3, n=5)
    _, _, xy = _aim(
        a, _front([(150.0, 150.0)]), np.ones(3600, bool), s=(180.0, 110.0), peers=_peer0((150.0, 150.0))
    )
    assert xy == pytest.approx((186.0, 102.0))


def test_the_airspace_band_is_the_avoiders_vertical_band() -> None:
    """With ``separation.vertical_m`` 5 m the stack has 4 layers 9 m apart (tactics.raster_layers):
    UAV 1 (9 m above UAV 0) does not share UAV 0's airspace and takes the front cell UAV 0 works;
    UAV 4 (UAV 0's layer) waits."""
    sep = SeparationConfig(vertical_m=5.0)
    a = _agent(uid=1, n=5, separation=sep)
    assert (a.raster.tactic.layers, a.raster.tactic.layer_step_m) == (4, 9.0)
    cell_xy = (150.0, 150.0)
    _, _, xy = _aim(a, _front([cell_xy]), np.ones(3600, bool), s=(180.0, 110.0), peers=_peer0(cell_xy))
    assert xy == pytest.approx(cell_xy)
    b = _agent(uid=4, n=5, separation=sep)
    _, _, xy = _aim(b, _front([cell_xy]), np.ones(3600, bool), s=(180.0, 110.0), peers=_peer0(cell_xy))
    assert xy == pytest.approx((186.0, 102.0))


def test_the_active_fire_nearest_the_aim_point_is_recentred_there() -> None:
    """The aim point (250, 50); of four fire entries, A (254, 54) is nearest (5.7 m; nearest in x
    alone is B, in y alone C, and D is nearest were y measured from -50): A alone is re-centred on
    the aim point with extent 0, the others are returned as they were."""
    b = FireEntry(2, True, 251.0, 150.0, 20.0)
    c = FireEntry(3, True, 60.0, 51.0, 20.0)
    d = FireEntry(4, True, 250.0, 0.0, 20.0)
    a_ = FireEntry(5, True, 254.0, 54.0, 20.0)
    ag = _agent()
    aim, _, xy = _aim(ag, _front([(250.0, 50.0)]), np.ones(3600, bool), aim=(b, c, d, a_))
    assert xy == (250.0, 50.0)
    assert aim == (b, c, d, dataclasses.replace(a_, x_m=250.0, y_m=50.0, extent_m=0.0))


def _with_t_obs(f: FrontCells, t_s: float) -> FrontCells:
    return FrontCells(f.x_m.copy(), f.y_m.copy(), f.state.copy(), np.full(len(f), t_s), f.ros_mps.copy())


@pytest.mark.parametrize("tactic", ["head", "flank", "auto"])
def test_the_aim_follows_every_change_of_the_front_step_after_step(tactic) -> None:
    """One agent aims at a sequence of fronts (the weights and density of an unchanged front are
    kept between steps, :meth:`RasterSuppression._weighted`); at every step its answer is a fresh
    agent's on that front alone, and its weights and density are the tactics functions' on that
    front. The sequence: the same cells seen again later (kept), the ROS of the two ends swapped (and
    seen again), one cell moved north, then east, a cell gone, a cell moved, the first front again."""
    from fire_uav_agent.tactics import front_density, front_weights

    west = [(50.0 + 5.0 * m, 50.0) for m in range(4)]
    east = [(230.0 + 5.0 * m, 250.0) for m in range(4)]
    f1 = _front(west + east, ros=[0.9, 0.8, 0.7, 0.6, 0.05, 0.06, 0.07, 0.08])
    swapped = _front(west + east, ros=[0.05, 0.06, 0.07, 0.08, 0.9, 0.8, 0.7, 0.6])
    gone = _front(west[1:] + east, ros=[0.8, 0.7, 0.6, 0.05, 0.06, 0.07, 0.08])
    moved = _front([(20.0, 280.0)] + west[1:] + east, ros=[0.9, 0.8, 0.7, 0.6, 0.05, 0.06, 0.07, 0.08])
    north = _front([(50.0, 70.0)] + west[1:] + east, ros=swapped.ros_mps)  # one cell moved in y only
    east_x = _front([(40.0, 70.0)] + west[1:] + east, ros=swapped.ros_mps)  # then in x only
    seq = [f1, _with_t_obs(f1, 5.0), swapped, _with_t_obs(swapped, 7.0), north, east_x, gone, moved, f1]
    cell = np.zeros(3600, bool)
    cell[:1800] = True  # the southern half: the west cells are in it, the east ones not
    a = _agent(tactic=tactic)
    for f in seq:
        got = _aim(a, f, cell)
        fresh = _agent(tactic=tactic)
        fresh.raster.anchor = a.raster.anchor  # flank: the anchor is chosen once, at the first front
        assert got == _aim(fresh, f, cell)
        w, dens, _ = a.raster._weighted(f)
        np.testing.assert_array_equal(w, front_weights(f, a.raster.tactic, a.raster.anchor))
        np.testing.assert_array_equal(dens, front_density(a.grid, f, w, a.raster.tactic.sigma_m))
