"""Aims by airspace (tactics.aims_taken / free_front / standoff_point): two UAVs of one layer over
one raster front do not work the same point.

worcester_vt seed 1 (5 UAVs, 4 layers) had a closest approach of 4.88 m: at
97.9 s UAVs 0 and 4, both on the 12 m layer, both aimed at the one front cell left (the aim
rule sends a UAV whose Voronoi cell holds no front cell to the heaviest front cell: the same
for everyone) and circled it at 100 m/s, where the avoider alone let them pass at 4.88 m.
Truth: distances measured by hand, the world's own closest approach of the real mission
(truth positions at every physics substep) against FF's reported closest approach (>= 10 m).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.agent_core import Agent
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.tactics import (
    TacticConfig,
    aim_on_front,
    aims_taken,
    free_front,
    shares_airspace,
    standoff_point,
)
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.codecs.sensor_bundle import Bundle, Samples
from fire_uav_common.codecs.uav_state import FireEntry, PeerState
from fire_uav_common.constants import CellState, Objective, VehicleStatus
from fire_uav_common.scenario import load_scenario

B = int(CellState.BURNING)


def front(xy) -> FrontCells:
    a = np.asarray(xy, dtype=float).reshape(-1, 2)
    n = a.shape[0]
    return FrontCells(a[:, 0], a[:, 1], np.full(n, B), np.zeros(n), np.full(n, 0.5))


CFG = TacticConfig(airspace_vertical_m=10.0)  # the defaults: 3 layers 14 m apart
OLD = TacticConfig(layers=4, layer_step_m=8.0, layer_top_m=36.0, airspace_vertical_m=10.0)  # before


def test_airspace_is_the_layers_within_the_avoiders_band():
    """Layers 8, 22, 36 m (ids modulo 3): 0 and 3 share 8 m, 0 and 1 are 14 m apart (beyond the
    avoider's 10 m band). The old stack, 12, 20, 28, 36 m: 0 and 4 share 12 m, 0 and 1 (8 m apart)
    are inside the band, 0 and 2 (16 m) are not."""
    assert [CFG.layer_height_m(i) for i in range(6)] == [8.0, 22.0, 36.0, 8.0, 22.0, 36.0]
    assert shares_airspace(3, 0, CFG) and shares_airspace(4, 1, CFG)
    assert (
        not shares_airspace(1, 0, CFG) and not shares_airspace(2, 1, CFG) and not shares_airspace(4, 0, CFG)
    )
    assert [OLD.layer_height_m(i) for i in range(6)] == [12.0, 20.0, 28.0, 36.0, 12.0, 20.0]
    assert shares_airspace(4, 0, OLD) and shares_airspace(1, 0, OLD) and shares_airspace(5, 4, OLD)
    assert (
        not shares_airspace(2, 0, OLD) and not shares_airspace(3, 1, OLD) and not shares_airspace(4, 2, OLD)
    )


def test_only_suppressing_right_of_way_peers_sharing_the_airspace_take_an_aim():
    peers = [
        (0, True, 10.0, 0.0),  # lower id, 12 m: taken
        (1, True, 20.0, 0.0),  # lower id, 20 m (8 m off): taken
        (2, True, 30.0, 0.0),  # lower id, 28 m (16 m off): free
        (0, False, 40.0, 0.0),  # refilling: free
        (5, True, 50.0, 0.0),  # higher id: it yields to us
        (1, True, math.nan, 0.0),  # nothing published
    ]
    assert aims_taken(4, peers, OLD).tolist() == [[10.0, 0.0], [20.0, 0.0]]
    assert aims_taken(4, peers, CFG).tolist() == [[20.0, 0.0]]  # only 1 shares 4's 22 m layer
    assert aims_taken(0, peers, OLD).shape == (0, 2)  # the lowest id takes what it likes


def test_the_aim_keeps_clear_of_a_taken_aim_by_hand_measured_distances():
    """Front cells on the x axis every 20 m from 0 to 200 m; a peer took (0, 0). With a 60 m clearance
    the cells at 0, 20, 40, 60 m are out (60 is not farther than 60), the nearest free to a centroid at
    (10, 0) is the one at 80 m; the own-cell rule still comes first among free cells."""
    f = front([(x, 0.0) for x in range(0, 201, 20)])
    free = free_front(f, np.array([[0.0, 0.0]]), 60.0)
    assert free.tolist() == [False] * 4 + [True] * 7
    w = np.ones(len(f))
    none_in_cell = np.zeros(len(f), bool)
    assert aim_on_front((10.0, 0.0), f, w, none_in_cell, free) == (80.0, 0.0)
    assert aim_on_front((10.0, 0.0), f, w, none_in_cell) == (0.0, 0.0)  # without the rule: the taken cell
    in_cell = np.array([x >= 160 for x in range(0, 201, 20)])
    assert aim_on_front((10.0, 0.0), f, w, in_cell, free) == (160.0, 0.0)
    assert aim_on_front((10.0, 0.0), f, w, none_in_cell, np.zeros(len(f), bool)) is None
    assert free_front(f, np.zeros((0, 2)), 60.0).all() and free_front(f, np.array([[0.0, 0.0]]), 0.0).all()


def test_standoff_is_the_clearance_from_the_nearest_taken_aim_toward_the_uav():
    taken = np.array([[0.0, 0.0], [500.0, 0.0]])
    assert standoff_point((30.0, 40.0), (1.0, 1.0), taken, 60.0) == pytest.approx((36.0, 48.0))  # 3-4-5
    assert standoff_point((500.0, 0.0), (490.0, 0.0), taken, 60.0) == pytest.approx((560.0, 0.0))  # over it


def test_a_zero_clearance_is_off_and_a_zero_band_is_the_same_layer_only():
    """``aim_clear_m`` 0 turns the rule off (its field doc) and is a valid value, as is an
    ``airspace_vertical_m`` of 0: then only UAVs of the same layer share the airspace. Layers
    exactly the band apart share it ("at most ``airspace_vertical_m`` apart")."""
    off = TacticConfig(aim_clear_m=0.0, airspace_vertical_m=0.0)
    assert TacticConfig(aim_clear_m=0.5, airspace_vertical_m=0.5).aim_clear_m == 0.5
    assert shares_airspace(3, 0, off) and not shares_airspace(1, 0, off)
    f = front([(0.0, 0.0), (20.0, 0.0)])
    assert free_front(f, np.array([[0.0, 0.0]]), off.aim_clear_m).tolist() == [True, True]
    edge = TacticConfig(layers=3, layer_step_m=10.0, layer_top_m=36.0, airspace_vertical_m=10.0)
    assert [edge.layer_height_m(i) for i in range(3)] == [16.0, 26.0, 36.0]
    assert shares_airspace(1, 0, edge) and shares_airspace(2, 1, edge) and not shares_airspace(2, 0, edge)


def test_free_cells_are_those_farther_than_the_clearance_from_every_taken_aim_by_brute_force():
    """Against distances measured one by one (math.hypot), over points off the axes; the result is a
    boolean mask (``~free`` selects the cells too close), also on the shortcuts (nothing taken, 0 m),
    and a clearance under 1 m still keeps a cell on a taken aim."""
    rng = np.random.default_rng(3)
    pts = rng.uniform(-200.0, 200.0, (300, 2))
    taken = rng.uniform(-200.0, 200.0, (3, 2))
    f = front(pts)
    for clear in (0.5, 30.0, 90.0):
        want = [all(math.hypot(px - tx, py - ty) > clear for tx, ty in taken) for px, py in pts]
        got = free_front(f, taken, clear)
        assert got.dtype == bool and got.tolist() == want
    g = front([(5.0, 5.0), (5.0, 5.6)])
    assert free_front(g, np.array([[5.0, 5.0]]), 0.5).tolist() == [False, True]
    assert f.x_m[~free_front(f, np.zeros((0, 2)), 60.0)].size == 0
    assert f.x_m[~free_front(f, taken, 0.0)].size == 0


def test_standoff_by_hand_off_the_axes_and_a_uav_just_beside_the_aim():
    """Two taken aims off the axes: the one nearest ``near_xy`` (50 m against 350 m), then 60 m
    toward the UAV (a 3-4-5 triangle); a UAV 0.5 m west of the aim is not over it: it waits west."""
    taken = np.array([[100.0, 200.0], [100.0, -200.0]])
    assert standoff_point((130.0, -160.0), (100.0, -150.0), taken, 60.0) == pytest.approx((136.0, -152.0))
    assert standoff_point((99.5, 200.0), (100.0, 190.0), taken, 60.0) == pytest.approx((40.0, 200.0))


def test_bad_airspace_fields_are_named():
    with pytest.raises(ValueError, match="tactic aim_clear_m must be >= 0, got -1.0"):
        TacticConfig(aim_clear_m=-1.0)
    with pytest.raises(ValueError, match="tactic airspace_vertical_m must be >= 0, got -1.0"):
        TacticConfig(airspace_vertical_m=-1.0)


def _last_cell_picture(uid: int):
    """Agent ``uid`` of worcester_vt's 5 (uav 3 shares uav 0's 8 m layer) seeing the fire of 97.9 s:
    one burning 30 m cell at (435, 555) among burned ones, unburned fuel east of it; its estimate
    over the cell."""
    sc = load_scenario(scenario_path("worcester_vt"))
    a = Agent(config_from_scenario(sc, uid, uav_count=5, seed=1))
    xs, ys = np.meshgrid(435.0 + 30.0 * np.arange(-2, 3), 555.0 + 30.0 * np.arange(-2, 3))
    st = np.where(xs > 435.0, int(CellState.UNBURNED), int(CellState.BURNED)).ravel()
    st[xs.size // 2] = B
    air = int(VehicleStatus.AIRBORNE)
    b = Bundle(970, 97.1, Samples(), np.zeros((0, 4)), 2000.0, air, 0.1, (xs.ravel(), ys.ravel(), st), 30.0)
    a.raster.fuse(b, VehicleStatus.AIRBORNE, b.stamp_s)
    fire = (FireEntry(0, True, 435.0, 555.0, 30.0),)
    s = np.array([440.0, 560.0, 410.0, 0.0])
    cell = np.ones(a.grid.points.shape[0], bool)  # the cell holds the front cell: the own-cell rule
    return a, b, fire, s, cell


def _peer0(aim_xy, objective=Objective.SUPPRESS) -> dict[int, PeerState]:
    return {0: PeerState(0, 1, 969, 500.0, 550.0, 408.0, 3.0, int(objective), 0, 900.0, *aim_xy)}


def test_a_uav_leaves_the_last_front_cell_to_the_right_of_way_uav_of_its_layer():
    """UAV 3 (8 m) with UAV 0 (8 m) suppressing at the one cell: it waits 60 m from that aim, farther
    than the avoider's 20 m radius, and still takes the cell when UAV 0 refills or is not there."""
    a, b, fire, s, cell = _last_cell_picture(3)
    assert a.raster.tactic.layer_height_m(3) == a.raster.tactic.layer_height_m(0) == 8.0
    _, _, xy = a.raster.target(b, s, fire, cell, 100.0, _peer0((435.0, 555.0)))
    assert xy is not None and math.hypot(xy[0] - 435.0, xy[1] - 555.0) == pytest.approx(60.0)
    for peers in ({}, None, _peer0((435.0, 555.0), Objective.REFILL), _peer0((900.0, 900.0))):
        assert a.raster.target(b, s, fire, cell, 100.0, peers)[2] == (435.0, 555.0)


def test_the_right_of_way_uav_and_other_airspaces_keep_the_cell():
    a0, b, fire, s, cell = _last_cell_picture(0)
    peer3 = {
        3: PeerState(3, 1, 969, 500.0, 550.0, 408.0, 3.0, int(Objective.SUPPRESS), 0, 900.0, 435.0, 555.0)
    }
    assert a0.raster.target(b, s, fire, cell, 100.0, peer3)[2] == (435.0, 555.0)  # 0 has the right of way
    a1, b, fire, s, cell = _last_cell_picture(1)  # 22 m: 14 m above UAV 0's layer
    assert a1.raster.target(b, s, fire, cell, 100.0, _peer0((435.0, 555.0)))[2] == (435.0, 555.0)


@pytest.mark.slow
def test_worcester_vt_seed_1_keeps_ffs_10_m_through_the_endgame_of_97_9_s():
    """The defect's own mission to 100 s: the world's closest 3-D approach of two airborne UAVs
    (checked at every physics substep) was 4.88 m at 97.9 s (UAVs 0 and 4, one layer)."""
    from fire_mission.inprocess import run_inprocess

    d = run_inprocess("worcester_vt", seed=1, overrides={"timing.max_duration_s": 100.0})
    assert d["collisions"] == 0
    assert d["min_separation_m"] >= 10.0, d["min_separation_m"]
