"""One fixed-wing at a time low over the lake (fire_uav_agent.lake_sequence; issue #36).

On ``ff_two_fires`` with 5 J3Cubs (``jsbsim``, seed 1) UAV 0 leaving the lake climbing and UAV 3
coming down to it met nearly head-on at 8.7 m (docs/airframes.md). Truth here: the rule's own
cases written out by hand (who is low, who waits, who is gone), and the command the agent's
guidance gives in that geometry against its command alone (the descent FF IV-D b asks for).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.agent_core import Agent
from fire_uav_agent.guidance import Guidance, Situation
from fire_uav_agent.lake_sequence import LakeSequenceConfig, LakeUser, hold_rank, lake_holder, on_lake
from fire_uav_agent.mission import Decision
from fire_uav_agent.testing.harness import refill_situation, scenario_path
from fire_uav_common.codecs.uav_state import PeerState
from fire_uav_common.constants import Objective, VehicleStatus
from fire_uav_common.scenario import load_scenario

LAKE = (0.0, 0.0)
CFG = LakeSequenceConfig(radius_m=500.0, clear_radius_m=160.0, low_agl_m=19.5)


def _u(uid: int, x_m: float, agl_m: float, refilling: bool = True) -> LakeUser:
    return LakeUser(uid, x_m, 0.0, agl_m, refilling)


def test_nobody_refilling_nobody_holds():
    assert lake_holder([], LAKE, CFG) is None
    assert lake_holder([_u(0, 100.0, 23.0, refilling=False)], LAKE, CFG) is None


def test_the_lowest_id_waiting_within_the_radius_holds_and_the_others_stack_by_id():
    users = [_u(4, 50.0, 23.0), _u(2, 400.0, 37.0), _u(1, 600.0, 23.0)]  # 1 is outside 500 m
    assert lake_holder(users, LAKE, CFG) == 2
    assert hold_rank(4, users, LAKE, CFG) == 1  # the rung above 2's, whatever their heights now
    assert hold_rank(1, users, LAKE, CFG) == 0  # 1 arriving would take rung 0 (and the lake)


def test_a_uav_on_the_lake_keeps_it_against_a_lower_id_waiting():
    # 3 is on its scoop run at 7.5 m; 0 arrives on its layer: 0 waits on rung 0
    users = [_u(3, 20.0, 7.5), _u(0, 300.0, 23.0)]
    assert lake_holder(users, LAKE, CFG) == 3
    assert hold_rank(0, users, LAKE, CFG) == 0
    # 3 began its descent (below 19.5 m): already on the lake
    assert lake_holder([_u(3, 450.0, 19.0), _u(0, 300.0, 23.0)], LAKE, CFG) == 3
    # still at 20 m: not yet, and 0 (the lower id) holds it; 3 climbs back to rung 1
    users = [_u(3, 450.0, 20.0), _u(0, 300.0, 23.0)]
    assert lake_holder(users, LAKE, CFG) == 0
    assert hold_rank(3, users, LAKE, CFG) == 1


def test_a_uav_climbing_away_holds_the_lake_until_it_is_clear():
    # 0 refilled (no longer REFILL) and climbs from the lake: 2 waits while 0 is low within 160 m
    assert lake_holder([_u(0, 100.0, 12.0, refilling=False), _u(2, 300.0, 23.0)], LAKE, CFG) == 0
    # beyond 160 m, or above 19.5 m, it no longer counts
    assert lake_holder([_u(0, 200.0, 12.0, refilling=False), _u(2, 300.0, 23.0)], LAKE, CFG) == 2
    assert lake_holder([_u(0, 100.0, 21.0, refilling=False), _u(2, 300.0, 23.0)], LAKE, CFG) == 2
    # a low UAV that does not refill farther out (FF's takeoff column, 200 m) does not hold it
    assert not on_lake(_u(1, 200.0, 5.0, refilling=False), LAKE, CFG)


def test_two_on_the_lake_at_once_the_lower_id_keeps_it_the_other_climbs_to_its_rung():
    # both went low on one step (each saw the other's state of the step before)
    users = [_u(4, 100.0, 18.0), _u(2, -100.0, 18.0), _u(0, 400.0, 23.0)]
    assert lake_holder(users, LAKE, CFG) == 2
    assert hold_rank(4, users, LAKE, CFG) == 1  # above 0 (rung 0)


def test_a_holder_gone_from_the_peer_states_frees_the_lake():
    users = [_u(1, 0.0, 7.5), _u(3, 300.0, 37.0), _u(4, 200.0, 23.0)]
    assert lake_holder(users, LAKE, CFG) == 1
    assert lake_holder(users[1:], LAKE, CFG) == 3  # 1 declared crashed: out of alive_states
    assert hold_rank(4, users[1:], LAKE, CFG) == 1


def test_every_agent_names_the_same_holder_and_distinct_rungs_whatever_the_order():
    users = [_u(i, 60.0 * i, 23.0 + 14.0 * (i % 3), refilling=i != 2) for i in range(6)]
    holders = {lake_holder(users[k:] + users[:k], LAKE, CFG) for k in range(len(users))}
    assert holders == {0}
    rungs = [hold_rank(i, users, LAKE, CFG) for i in (1, 3, 4, 5)]
    assert len(set(rungs)) == len(rungs)


@pytest.mark.parametrize("bad", [{"radius_m": 0.0}, {"clear_radius_m": math.nan}, {"low_agl_m": -1.0}])
def test_bad_config_is_refused(bad):
    with pytest.raises(ValueError, match=next(iter(bad))):
        LakeSequenceConfig(**{"radius_m": 500.0, "clear_radius_m": 160.0, "low_agl_m": 19.5, **bad})


# --- the agent's guidance on ff_two_fires (lake (50, 50) m, 90 m across; layers 23 / 37 m) ----

STEP = 1630  # 163.0 s
AT = (50.0 + 120.0 / math.sqrt(2), 50.0 + 120.0 / math.sqrt(2))  # 120 m NE of the lake centre
HEADING = -0.75 * math.pi  # toward the lake


def _refilling(
    uid: int, z_m: float, peers: list[PeerState], model: str = "jsbsim", sequence: str = "stack"
) -> float:
    return _guide(uid, z_m, peers, model, sequence=sequence).command[1]


def _guide(
    uid: int,
    z_m: float,
    peers: list[PeerState],
    model: str = "jsbsim",
    cell_x_min_m: float = -math.inf,
    sequence: str = "stack",
) -> Guidance:
    """The guidance of UAV ``uid`` of ff_two_fires's 5 (loss off; ``mission.lake_sequence`` =
    ``sequence``, opt-in) in REFILL at ``AT`` (inside the lake zone), ``z_m`` above the flat
    ground, heading for the lake, having heard ``peers`` at the step before; its Voronoi cell the
    grid points east of ``cell_x_min_m``."""
    sc = load_scenario(
        scenario_path("ff_two_fires"),
        overrides={"uavs.vehicle_model": model, "mission.lake_sequence": sequence},
    )
    a = Agent(config_from_scenario(sc, uid, uav_count=5, seed=1, loss_probability=0.0))
    for p in peers:
        a.link.receive_state(p, now_step=STEP)
    s = np.array([AT[0], AT[1], z_m, HEADING])
    return a.guide.run(
        refill_situation(a, a.grid.points[:, 0] > cell_x_min_m), VehicleStatus.AIRBORNE, s, STEP - 1
    )


def _peer(
    uid: int, xy: tuple[float, float], z_m: float, objective: Objective = Objective.REFILL
) -> PeerState:
    return PeerState(uid, 1, STEP - 1, xy[0], xy[1], z_m, HEADING, int(objective), -1, 0.0)


@pytest.mark.parametrize("model", ["jsbsim", "coordinated_turn"])
def test_a_fixed_wing_holds_its_rung_while_a_peer_is_on_the_lake(model):
    """UAV 3 refilling 120 m from the lake centre, 23 m up (rung 0 of the stack, the lowest FF
    layer): alone it descends to the scoop height (FF IV-D b); with UAV 0 scooping over the lake,
    or climbing away from it after its refill, it holds 23 m (v_z >= 0); with UAV 0 waiting (the
    lower id holds the lake) it climbs to rung 1, 37 m. On the code before, it descended onto
    them (the first two fail there)."""
    assert _refilling(3, 23.0, [], model) < 0.0
    assert _refilling(3, 23.0, [_peer(0, (50.0, 50.0), 7.5)], model) >= 0.0
    assert _refilling(3, 23.0, [_peer(0, (110.0, 50.0), 12.0, Objective.SUPPRESS)], model) >= 0.0
    assert _refilling(3, 23.0, [_peer(0, (50.0, 50.0), 23.0)], model) > 0.0
    # UAV 4 waiting above the lake: 3 is the lower id and goes down
    assert _refilling(3, 23.0, [_peer(4, (50.0, 50.0), 23.0)], model) < 0.0
    # a landing peer low near the takeoff column is not on the lake
    assert _refilling(3, 23.0, [_peer(0, (50.0, 250.0), 5.0, Objective.LAND)], model) < 0.0


def test_the_holder_flies_at_the_lakes_centre_even_outside_its_own_cell():
    """The holder's cell does not hold the lake (a peer waiting above it does): it flies at the
    lake's centre (50, 50), not at the centroid of Eq. 14 in its cell (east of x = 100 m), where
    it flew along the cell's edge on the code before (coordinated_turn seed 1: 450 s, 229 s
    without the sequencing). FF's unicycle keeps Eq. 14."""
    assert _guide(3, 23.0, [], "jsbsim", cell_x_min_m=100.0).target_xy == (50.0, 50.0)
    tx, _ = _guide(3, 23.0, [], "ff_paper", cell_x_min_m=100.0).target_xy or (math.nan, math.nan)
    assert tx > 100.0


def test_ffs_unicycle_descends_as_the_paper_says():
    """``ff_paper`` (no airframe) keeps FF IV-D b's descent whoever is on the lake (its missions
    stay the paper's)."""
    assert _refilling(3, 23.0, [_peer(0, (50.0, 50.0), 7.5)], "ff_paper") < 0.0


@pytest.mark.parametrize("model", ["jsbsim", "coordinated_turn"])
def test_by_default_a_fixed_wing_refills_as_at_the_base(model):
    """``mission.lake_sequence`` is opt-in: by default (none) a fixed-wing refills as FF IV-D b
    and the base 2a7ab88 fly it, whoever is on the lake: it descends from 23 m with UAV 0
    scooping below it or waiting above the lake, and flies at the centroid of Eq. 14 in its own
    cell (east of x = 100 m), not at the lake's centre (50, 50). With the sequencing on by
    default (c853c90) the first three fail."""
    sc = load_scenario(scenario_path("ff_two_fires"))
    assert sc.mission.lake_sequence == "none"
    guided = _guide(3, 23.0, [_peer(0, (50.0, 50.0), 7.5)], model, sequence=sc.mission.lake_sequence)
    assert guided.command[1] < 0.0
    assert _refilling(3, 23.0, [_peer(0, (50.0, 50.0), 23.0)], model, sequence="none") < 0.0
    tx, _ = _guide(3, 23.0, [], model, cell_x_min_m=100.0, sequence="none").target_xy or (math.nan, math.nan)
    assert tx > 100.0


def _landing_climb(sequence: str, peer_objective: Objective | None) -> float:
    """The climb rate [m/s] UAV 2 (the 23 m layer, with 0 and 4) of ff_two_fires's 5 J3Cubs
    commands in LAND, 23 m up, three turn radii east of its landing entry and heading west at it,
    having heard UAV 0 (same layer, lower id) at 23 m at UAV 2's entry with ``peer_objective``
    (None: not heard)."""
    sc = load_scenario(
        scenario_path("ff_two_fires"),
        overrides={"uavs.vehicle_model": "jsbsim", "mission.lake_sequence": sequence},
    )
    a = Agent(config_from_scenario(sc, 2, uav_count=5, seed=1, loss_probability=0.0))
    ap = a.guide.approach
    assert ap is not None
    ex, ey = ap.entry_xy
    if peer_objective is not None:
        a.link.receive_state(
            PeerState(0, 1, STEP - 1, ex, ey, 23.0, math.pi, int(peer_objective), -1, 0.0), now_step=STEP
        )
    sit = Situation(Decision(Objective.LAND, -1, None, False, False), (), a.lakes[0], None, None)  # type: ignore[arg-type]
    s = np.array([ex + 3.0 * ap.turn_radius_m, ey, 23.0, math.pi])
    return a.guide.run(sit, VehicleStatus.AIRBORNE, s, STEP - 1).command[1]


def test_a_fixed_wing_yields_its_layers_landing_entry_to_a_lower_id_with_the_stack_only():
    """With ``mission.lake_sequence: stack`` UAV 2 climbs above every FF layer while UAV 0, of its
    layer and landing, is in its entry area (their turns onto the finals overlapped: the tanker's
    seed 1 came to 5.0 m there); not for a peer that is not landing, nor by default (none), where
    it keeps its layer as at 2a7ab88. Fails on the code before (no yield)."""
    assert _landing_climb("stack", Objective.LAND) > 0.5
    assert abs(_landing_climb("stack", None)) < 0.5
    assert abs(_landing_climb("stack", Objective.SUPPRESS)) < 0.5
    assert abs(_landing_climb("none", Objective.LAND)) < 0.5
