"""Mission life-cycle (FF IV-D). The whole fleet in the real world: test_harness.py."""

from fire_uav_agent.mission import Mission, MissionConfig, MissionView, Objective
from fire_uav_agent.peer_link import FireEntry
from fire_uav_common.constants import VehicleStatus

FIRE = FireEntry(1, True, 200.0, 100.0, 10.0)


def view(t, **kw):
    base = dict(
        t_s=t,
        vehicle=VehicleStatus.AIRBORNE,
        water_kg=2000.0,
        pos_xy=(0.0, 0.0),
        fires=(FIRE,),
        all_out=False,
        peer_objectives={},
        over_lake=False,
        centroid_xy=(50.0, 50.0),
        target_fire_id=1,
    )
    base.update(kw)
    return MissionView(**base)


def test_transitions_takeoff_suppress_drop_refill_land():
    m = Mission(MissionConfig(takeoff_time_s=4.0))
    assert m.step(view(1.0, vehicle=VehicleStatus.ON_GROUND)).objective == Objective.GROUNDED
    d = m.step(view(4.0, vehicle=VehicleStatus.ON_GROUND))
    assert d.objective == Objective.SUPPRESS and d.changed
    # within the estimated sigma (10 m) but outside min_drop_radius_m (3 m): no release, the
    # estimate may not have seen the last hit yet
    d = m.step(view(4.9, pos_xy=(195.0, 100.0)))
    assert d.request is None and d.objective == Objective.SUPPRESS
    d = m.step(view(5.0, pos_xy=(198.0, 100.0)))  # within min_drop_radius_m: drop
    assert d.request == 1 and d.target_fire_id == 1 and d.objective == Objective.REFILL
    for k in range(3):
        assert m.step(view(5.1 + k, water_kg=0.0)).objective == Objective.REFILL
    d = m.step(view(9.0, water_kg=0.0, over_lake=True))
    assert d.request == 2
    d = m.step(view(10.0, water_kg=2000.0, over_lake=True))
    assert d.objective == Objective.SUPPRESS  # reassess after refill: fire still burning
    # every known fire out: sweep the area for post_search_s before landing
    assert m.step(view(11.0, fires=(), all_out=True)).objective == Objective.SEARCH
    assert m.step(view(11.0 + 44.9, fires=(), all_out=True)).objective == Objective.SEARCH
    assert m.step(view(11.0 + 45.0, fires=(), all_out=True)).objective == Objective.LAND
    assert (
        m.step(view(57.0, vehicle=VehicleStatus.LANDED, fires=(), all_out=True)).objective == Objective.LANDED
    )


def test_a_fire_found_during_the_sweep_resets_it():
    m = Mission(MissionConfig(post_search_s=30.0))
    m.step(view(0.0, vehicle=VehicleStatus.ON_GROUND))
    assert m.step(view(1.0, fires=(), all_out=True)).objective == Objective.SEARCH
    # a new fire appears at 20 s: suppress it, and the sweep starts again when it is out
    assert m.step(view(20.0)).objective == Objective.SUPPRESS
    assert m.step(view(40.0, fires=(), all_out=True)).objective == Objective.SEARCH
    assert m.step(view(69.9, fires=(), all_out=True)).objective == Objective.SEARCH
    assert m.step(view(70.0, fires=(), all_out=True)).objective == Objective.LAND


def test_land_when_all_alive_peers_land_and_search_without_fires():
    m = Mission(MissionConfig())
    assert m.step(view(0.0, fires=())).objective == Objective.SEARCH
    d = m.step(view(1.0, peer_objectives={1: Objective.LAND, 2: Objective.LANDED}))
    assert d.objective == Objective.LAND


def test_deadlock_breaker_switches_to_attack_run():
    m = Mission(MissionConfig(deadlock_timeout_s=20.0))
    m.step(view(0.0, vehicle=VehicleStatus.ON_GROUND))
    directs = [
        m.step(view(0.1 * k, pos_xy=(100.0, 100.0), centroid_xy=(150.0, 100.0))).direct for k in range(1, 300)
    ]
    assert not any(directs[:190]) and all(directs[205:])
