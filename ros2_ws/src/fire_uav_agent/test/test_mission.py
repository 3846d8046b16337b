"""Mission life-cycle (FF IV-D a-d). The whole fleet in the real world: test_harness.py.

After the transition tests, each test pins one documented rule at its boundary (inclusive or exclusive as the doc says):
takeoff slot, reassess order, refill threshold and full tank, drop radius, release verdict,
the post-fire sweep, peers' agreement, the stall watch, the attack run and its timeout.
Times and distances are chosen exactly representable, so an edge is tested at the edge.
"""

import pytest
from fire_uav_agent.mission import Mission, MissionConfig, MissionView, Objective
from fire_uav_agent.peer_link import FireEntry
from fire_uav_common.constants import PayloadAction, VehicleStatus

FIRE = FireEntry(1, True, 200.0, 100.0, 10.0)
FAR = FireEntry(2, True, 1000.0, 1000.0, 10.0)


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


def airborne(cfg=None, t=0.0, **kw):
    """A mission that took off at ``t`` into the objective the view ``kw`` calls for."""
    m = Mission(cfg or MissionConfig())
    m.step(view(t, **kw))
    return m


def in_refill(cfg=None):
    """A mission that has just dropped at t = 0 (REFILL, with the post-drop guard of 3 steps)."""
    m = airborne(cfg)
    d = m.step(view(0.0, pos_xy=(200.0, 100.0)))
    assert d.request == PayloadAction.DROP and d.objective == Objective.REFILL
    return m


# --- takeoff (IV-D a) --------------------------------------------------------------------------


def test_takeoff_at_the_slot_inclusive_or_when_the_world_says_airborne():
    m = Mission(MissionConfig(takeoff_time_s=8.0))
    d = m.step(view(7.5, vehicle=VehicleStatus.ON_GROUND))
    assert d.objective == Objective.GROUNDED and not d.changed and d.request is None
    d = m.step(view(8.0, vehicle=VehicleStatus.ON_GROUND))
    assert d.objective == Objective.SUPPRESS and d.changed
    # before its slot, a vehicle the world already reports airborne takes its objective
    m = Mission(MissionConfig(takeoff_time_s=8.0))
    assert m.step(view(1.0, vehicle=VehicleStatus.AIRBORNE, fires=())).objective == Objective.SEARCH


def test_a_uav_grounded_when_the_fleet_lands_stays_down():
    """IV-D d: the fleet agreed to land before this UAV's slot. Still on the ground, it goes to
    LANDED (never takes off); a vehicle the world reports airborne at its slot goes to LAND."""
    landing = {0: int(Objective.LAND), 2: int(Objective.LANDED)}
    m = Mission(MissionConfig(takeoff_time_s=8.0))
    d = m.step(view(8.0, vehicle=VehicleStatus.ON_GROUND, peer_objectives=landing))
    assert d.objective == Objective.LANDED and d.changed and d.request is None
    assert (
        m.step(view(9.0, vehicle=VehicleStatus.ON_GROUND, peer_objectives={})).objective == Objective.LANDED
    )
    m = Mission(MissionConfig(takeoff_time_s=8.0))
    d = m.step(view(8.0, vehicle=VehicleStatus.AIRBORNE, peer_objectives=landing))
    assert d.objective == Objective.LAND


def test_default_takeoff_slot_is_time_zero():
    assert Mission(MissionConfig()).step(view(0.0, vehicle=VehicleStatus.ON_GROUND)).changed


# --- reassess order (IV-D c) -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kw", "want"),
    [
        (dict(fires=()), Objective.SEARCH),
        (dict(), Objective.SUPPRESS),
        (dict(monitor_fire_id=0), Objective.MONITOR),  # fire id 0 is a real assignment
        (dict(monitor_fire_id=3, water_kg=100.0), Objective.REFILL),  # refill before monitoring
        (dict(water_kg=100.0, peer_objectives={4: Objective.LAND}), Objective.LAND),  # land first
    ],
)
def test_reassess_order_land_refill_monitor_suppress_search(kw, want):
    assert airborne(**kw).objective == want


def test_refill_below_min_water_fraction_exclusive_edge():
    # default: half of a 2000 kg tank
    assert airborne(water_kg=999.5).objective == Objective.REFILL
    assert airborne(water_kg=1000.0).objective == Objective.SUPPRESS
    cfg = MissionConfig(water_capacity_kg=1000.0, min_water_fraction=0.25)
    assert airborne(cfg, water_kg=249.5).objective == Objective.REFILL
    assert airborne(cfg, water_kg=250.0).objective == Objective.SUPPRESS


def test_search_disabled_suppresses_without_a_known_fire():
    m = airborne(MissionConfig(search_enabled=False), fires=())
    assert m.objective == Objective.SUPPRESS
    d = m.step(view(1.0, fires=(), target_fire_id=7))  # the coverage target, nothing to drop on
    assert d.request is None and d.target_fire_id == 7


def test_search_and_monitor_targets():
    m = airborne(fires=())
    d = m.step(view(1.0, fires=(), target_fire_id=7))
    assert d.objective == Objective.SEARCH and d.target_fire_id == -1 and d.request is None
    d = m.step(view(2.0, monitor_fire_id=5))
    assert d.objective == Objective.MONITOR and d.target_fire_id == 5 and d.changed
    d = m.step(view(3.0, monitor_fire_id=5))
    assert not d.changed and d.request is None and not d.direct


# --- fleet agreement and landing (IV-D d) ------------------------------------------------------


def test_peers_must_all_be_land_or_landed_and_there_must_be_one():
    assert (
        airborne(peer_objectives={1: Objective.LAND, 2: Objective.SUPPRESS}).objective == Objective.SUPPRESS
    )
    assert airborne(peer_objectives={1: Objective.LANDED}).objective == Objective.LAND
    assert airborne(peer_objectives={}).objective == Objective.SUPPRESS


def test_sweep_for_default_post_search_s_inclusive_then_land():
    m = airborne(fires=(), all_out=True)  # all out since t = 0
    assert m.step(view(44.5, fires=(), all_out=True)).objective == Objective.SEARCH
    d = m.step(view(45.0, fires=(), all_out=True))
    assert d.objective == Objective.LAND and d.changed and d.target_fire_id == -1


def test_a_relapse_of_all_out_restarts_the_sweep():
    m = airborne(MissionConfig(post_search_s=30.0), fires=(), all_out=True)
    m.step(view(10.0, fires=(), all_out=False))  # picture no longer all out
    assert m.step(view(20.0, fires=(), all_out=True)).objective == Objective.SEARCH
    assert m.step(view(49.5, fires=(), all_out=True)).objective == Objective.SEARCH
    assert m.step(view(50.0, fires=(), all_out=True)).objective == Objective.LAND


def test_the_sweep_ends_when_the_area_is_covered_since_the_last_fire_went_out():
    """Session 28: the fleet lands once its sensors have covered the whole area *after* the last
    known fire went out (``swept_since_s``: the staleness map's oldest sighting), not at a fixed
    time; ``post_search_s`` stays the least it sweeps. All out from t = 0 here."""
    cfg = MissionConfig(post_search_s=30.0, post_search_max_s=200.0)
    m = airborne(cfg, fires=(), all_out=True)
    # covered all over before the fire went out (-5 s): an old sweep, not this one
    assert m.step(view(100.0, fires=(), all_out=True, swept_since_s=-5.0)).objective == Objective.SEARCH
    # covered since 0.0 exactly (the moment it went out): the sweep is complete
    d = m.step(view(100.5, fires=(), all_out=True, swept_since_s=0.0))
    assert d.objective == Objective.LAND and d.changed


def test_a_sweep_complete_early_still_waits_post_search_s():
    m = airborne(MissionConfig(post_search_s=30.0, post_search_max_s=200.0), fires=(), all_out=True)
    assert m.step(view(29.5, fires=(), all_out=True, swept_since_s=10.0)).objective == Objective.SEARCH
    assert m.step(view(30.0, fires=(), all_out=True, swept_since_s=10.0)).objective == Objective.LAND


def test_a_sweep_that_cannot_complete_ends_at_post_search_max_s():
    m = airborne(MissionConfig(post_search_s=30.0, post_search_max_s=200.0), fires=(), all_out=True)
    assert m.step(view(199.5, fires=(), all_out=True, swept_since_s=-120.0)).objective == Objective.SEARCH
    assert m.step(view(200.0, fires=(), all_out=True, swept_since_s=-120.0)).objective == Objective.LAND


def test_a_max_at_or_below_post_search_s_is_the_fixed_time_sweep():
    """``post_search_max_s <= post_search_s``: the sweep before session 28, post_search_s alone."""
    m = airborne(MissionConfig(post_search_s=30.0, post_search_max_s=0.0), fires=(), all_out=True)
    assert m.step(view(29.5, fires=(), all_out=True, swept_since_s=-120.0)).objective == Objective.SEARCH
    assert m.step(view(30.0, fires=(), all_out=True, swept_since_s=-120.0)).objective == Objective.LAND


def test_a_relapse_restarts_the_sweep_and_what_was_covered_before_does_not_count():
    m = airborne(MissionConfig(post_search_s=30.0, post_search_max_s=200.0), fires=(), all_out=True)
    m.step(view(10.0, all_out=False))  # a new fire: suppress it
    assert m.step(view(50.0, fires=(), all_out=True, swept_since_s=20.0)).objective == Objective.SEARCH
    # covered since 20 s, the picture all out since 50 s: not swept since; at 250 s the cap
    assert m.step(view(249.5, fires=(), all_out=True, swept_since_s=20.0)).objective == Objective.SEARCH
    assert m.step(view(250.0, fires=(), all_out=True, swept_since_s=20.0)).objective == Objective.LAND


def test_without_search_land_as_soon_as_all_out():
    m = airborne(MissionConfig(search_enabled=False))
    assert m.step(view(1.0, fires=(), all_out=True)).objective == Objective.LAND


def test_land_is_terminal_and_landed_needs_land_first():
    m = airborne(peer_objectives={1: Objective.LAND})
    d = m.step(view(1.0, water_kg=0.0, monitor_fire_id=2))  # fires, no agreement, empty tank
    assert d.objective == Objective.LAND and not d.changed and d.request is None
    d = m.step(view(2.0, vehicle=VehicleStatus.LANDED))
    assert d.objective == Objective.LANDED and d.changed
    d = m.step(view(3.0, vehicle=VehicleStatus.AIRBORNE))
    assert d.objective == Objective.LANDED and not d.changed
    # the world's "landed" does not make a suppressing UAV LANDED
    m = airborne()
    assert m.step(view(1.0, vehicle=VehicleStatus.LANDED)).objective == Objective.SUPPRESS


def test_crashed_freezes_the_mission():
    m = airborne()
    m.step(view(1.0, target_fire_id=1))
    d = m.step(view(2.0, vehicle=VehicleStatus.CRASHED, pos_xy=(200.0, 100.0), peer_objectives={1: 3}))
    assert (d.objective, d.target_fire_id, d.request, d.direct, d.changed) == (
        Objective.SUPPRESS,
        1,
        None,
        False,
        False,
    )
    assert m.drops == 0 and m.objective == Objective.SUPPRESS


# --- suppress: target and release (IV-D c) -----------------------------------------------------


def test_drop_radius_inclusive_edge_default_and_configured():
    m = airborne()
    assert m.step(view(1.0, pos_xy=(196.5, 100.0))).request is None  # 3.5 m out
    d = m.step(view(2.0, pos_xy=(200.0, 97.0)))  # exactly 3 m
    assert d.request == PayloadAction.DROP and m.drops == 1
    m = airborne(MissionConfig(min_drop_radius_m=8.0))
    assert m.step(view(1.0, pos_xy=(191.5, 100.0))).request is None
    assert m.step(view(2.0, pos_xy=(192.0, 100.0))).request == PayloadAction.DROP


def test_drop_leads_to_refill_and_keeps_the_dropped_fire_as_target():
    m = airborne()
    d = m.step(view(1.0, pos_xy=(200.0, 100.0)))
    assert (d.objective, d.target_fire_id, d.request, d.direct, d.changed) == (
        Objective.REFILL,
        1,
        PayloadAction.DROP,
        False,
        True,
    )
    d = m.step(view(2.0, water_kg=0.0))
    assert d.target_fire_id == -1 and d.request is None and not d.changed
    assert m.drops == 1


def test_release_verdict_overrides_the_distance_rule():
    m = airborne()
    assert m.step(view(1.0, pos_xy=(200.0, 100.0), release=False)).request is None
    assert m.step(view(2.0, pos_xy=(0.0, 0.0), release=True)).request == PayloadAction.DROP


def test_no_drop_with_an_empty_tank():
    m = airborne(MissionConfig(min_water_fraction=0.0), water_kg=0.0)
    assert m.objective == Objective.SUPPRESS
    d = m.step(view(1.0, water_kg=0.0, pos_xy=(200.0, 100.0)))
    assert d.request is None and d.objective == Objective.SUPPRESS and m.drops == 0


def test_unknown_target_falls_back_to_the_nearest_fire():
    m = airborne(fires=(FAR, FIRE), target_fire_id=9)
    d = m.step(view(1.0, fires=(FAR, FIRE), target_fire_id=9, pos_xy=(201.0, 100.0)))
    assert d.target_fire_id == 1 and d.request == PayloadAction.DROP
    # from near the far fire, the far one is nearest (and is not within the drop radius)
    m = airborne(fires=(FIRE, FAR), target_fire_id=9)
    d = m.step(view(1.0, fires=(FIRE, FAR), target_fire_id=9, pos_xy=(990.0, 1000.0)))
    assert d.target_fire_id == 2 and d.request is None
    # the y offset counts too: (201, 150) is 50 m from FIRE but would be 1 m off on x alone
    m = airborne(fires=(FIRE,), target_fire_id=9)
    assert m.step(view(1.0, target_fire_id=9, pos_xy=(201.0, 150.0))).request is None
    # the coverage target, when known, wins over the nearer fire
    m = airborne(fires=(FIRE, FAR), target_fire_id=2)
    d = m.step(view(1.0, fires=(FIRE, FAR), target_fire_id=2, pos_xy=(200.0, 100.0)))
    assert d.target_fire_id == 2 and d.request is None


# --- refill (IV-D b) ---------------------------------------------------------------------------


def test_refill_requested_over_a_lake_until_the_tank_is_full():
    m = in_refill()
    assert m.step(view(1.0, water_kg=500.0, over_lake=False)).request is None
    assert m.step(view(2.0, water_kg=500.0, over_lake=True)).request == PayloadAction.REFILL
    assert m.step(view(3.0, water_kg=1990.0, over_lake=True)).request == PayloadAction.REFILL
    # the guard has passed: 1990 kg is above full_fraction (0.98 * 2000 = 1960): reassess
    d = m.step(view(4.0, water_kg=1990.0, over_lake=True))
    assert d.objective == Objective.SUPPRESS and d.changed and d.request is None


def test_full_fraction_inclusive_edge():
    m = in_refill()
    for k in range(1, 4):
        m.step(view(float(k), water_kg=0.0))
    assert m.step(view(4.0, water_kg=1959.5, over_lake=True)).objective == Objective.REFILL
    assert m.step(view(5.0, water_kg=1960.0, over_lake=True)).objective == Objective.SUPPRESS
    m = in_refill(MissionConfig(water_capacity_kg=1000.0, full_fraction=0.75))
    for k in range(1, 4):
        m.step(view(float(k), water_kg=0.0))
    assert m.step(view(4.0, water_kg=749.5, over_lake=True)).objective == Objective.REFILL
    assert m.step(view(5.0, water_kg=750.0, over_lake=True)).objective == Objective.SUPPRESS


def test_no_refill_request_with_a_full_tank():
    # during the post-drop guard the mission stays in REFILL even with a full tank: no request then
    cfg = MissionConfig(water_capacity_kg=1000.0)
    m = in_refill(cfg)
    assert m.step(view(1.0, water_kg=1000.0, over_lake=True)).request is None  # guard step, full
    assert m.step(view(2.0, water_kg=999.5, over_lake=True)).request == PayloadAction.REFILL


def test_the_post_drop_guard_holds_refill_for_three_steps():
    m = in_refill()
    for k in range(1, 4):  # the world has not yet reported the drop: the tank still reads full
        d = m.step(view(float(k), water_kg=2000.0, peer_objectives={1: Objective.LAND}))
        assert d.objective == Objective.REFILL
    d = m.step(view(4.0, water_kg=0.0, peer_objectives={1: Objective.LAND}))
    assert d.objective == Objective.LAND and d.changed and d.request is None


def test_refill_lands_when_the_fleet_agrees():
    m = in_refill(MissionConfig(search_enabled=False))
    for k in range(1, 4):
        m.step(view(float(k), water_kg=0.0))
    assert m.step(view(4.0, water_kg=0.0, fires=(), all_out=True)).objective == Objective.LAND


# --- stall watch, attack run (FF V-D deadlock) -------------------------------------------------


def suppressing(cfg=None, **kw):
    """Suppressing from t = 0, far from the fire (no drop), with a frozen centroid by default."""
    m = airborne(cfg, **kw)
    assert m.objective == Objective.SUPPRESS
    return m


def directs(m, times, **kw):
    return [m.step(view(t, **kw)).direct for t in times]


def test_frozen_centroid_attacks_at_the_timeout_inclusive():
    m = suppressing()
    assert directs(m, [5.0, 10.0, 19.5]) == [False, False, False]
    assert directs(m, [20.0]) == [True]  # default deadlock_timeout_s: 20 s


def test_configured_deadlock_timeout():
    m = suppressing(MissionConfig(deadlock_timeout_s=8.0))
    assert directs(m, [4.0, 7.5, 8.0]) == [False, False, True]


def test_centroid_moving_the_threshold_is_not_frozen():
    # moves 10 m (default deadlock_centroid_move_m) along x: not frozen; 9.5 m: frozen
    m = suppressing(centroid_xy=(50.0, 50.0))
    assert directs(m, [10.0, 20.0], centroid_xy=(60.0, 50.0)) == [False, False]
    m = suppressing(centroid_xy=(50.0, 50.0))
    assert directs(m, [10.0, 20.0], centroid_xy=(59.5, 50.0)) == [False, True]
    # the y extent counts: 8 m on x and 6 m on y is a 10 m move
    m = suppressing(centroid_xy=(50.0, 50.0))
    assert directs(m, [10.0, 20.0], centroid_xy=(58.0, 56.0)) == [False, False]
    m = suppressing(MissionConfig(deadlock_centroid_move_m=30.0), centroid_xy=(50.0, 50.0))
    assert directs(m, [10.0, 20.0], centroid_xy=(75.0, 50.0)) == [False, True]


def test_only_centroids_within_the_window_count():
    # the move at t = 0 is older than the 20 s window seen from t = 30 s; at t = 20 s it is inside
    m = suppressing(centroid_xy=(0.0, 0.0))
    out = directs(m, [10.0, 20.0], centroid_xy=(100.0, 0.0))
    assert out == [False, False]
    assert directs(m, [30.0], centroid_xy=(100.0, 0.0)) == [True]


def test_a_single_centroid_in_the_window_is_not_a_stall():
    m = suppressing(centroid_xy=None)
    assert directs(m, [20.0, 25.0], centroid_xy=None) == [False, False]  # no centroids at all
    m = suppressing(centroid_xy=None)
    assert directs(m, [20.0], centroid_xy=(50.0, 50.0)) == [False]  # one
    assert directs(m, [21.0], centroid_xy=(50.0, 50.0)) == [True]  # two


def test_moving_centroid_attacks_after_the_stuck_factor_times_the_timeout():
    # a centroid that keeps moving is never frozen; no drop for 2 * 20 s attacks all the same
    m = suppressing(centroid_xy=(0.0, 0.0))
    out = directs(m, [5.0 * k for k in range(1, 9)], centroid_xy=None)
    assert out == [False] * 8  # only one centroid
    m = suppressing(centroid_xy=(0.0, 0.0))
    ts = [5.0 * k for k in range(1, 9)]  # 5 .. 40 s
    out = [m.step(view(t, centroid_xy=(t * 10.0, 0.0))).direct for t in ts]
    assert out == [False] * 7 + [True]
    m = suppressing(MissionConfig(deadlock_stuck_factor=3.0), centroid_xy=(0.0, 0.0))
    ts = [5.0 * k for k in range(1, 13)]  # 5 .. 60 s
    out = [m.step(view(t, centroid_xy=(t * 10.0, 0.0))).direct for t in ts]
    assert out == [False] * 11 + [True]


def test_attack_run_lasts_attack_timeout_inclusive_then_the_watch_restarts():
    m = suppressing()
    assert directs(m, [20.0]) == [True]  # attack starts at 20 s
    assert directs(m, [35.0, 50.0]) == [True, True]  # 30 s later: still attacking
    assert directs(m, [50.5]) == [False]  # over: the watch restarts at 50.5 s
    assert directs(m, [60.0, 70.0]) == [False, False]
    assert directs(m, [70.5]) == [True]  # a fresh 20 s of frozen centroid
    m = suppressing(MissionConfig(attack_timeout_s=5.0))
    assert directs(m, [20.0, 25.0, 25.5, 30.0]) == [True, True, False, False]


def test_a_drop_ends_the_attack_run():
    m = suppressing()
    assert directs(m, [20.0]) == [True]
    d = m.step(view(21.0, pos_xy=(200.0, 100.0)))
    assert d.request == PayloadAction.DROP and not d.direct and d.objective == Objective.REFILL


def test_a_new_objective_restarts_the_stall_watch():
    m = suppressing()
    m.step(view(15.0, monitor_fire_id=1))  # MONITOR at 15 s
    m.step(view(16.0))  # back to SUPPRESS at 16 s: the watch starts again
    assert directs(m, [35.5, 36.0]) == [False, True]


def test_stalled_refill_steers_straight_to_the_lake():
    m = in_refill()
    out = directs(m, [5.0, 10.0, 19.5, 20.0], water_kg=0.0)
    assert out == [False, False, False, True]
    # refill progress over a lake restarts the watch
    m = in_refill()
    directs(m, [5.0, 10.0], water_kg=0.0)
    assert directs(m, [15.0], water_kg=100.0, over_lake=True) == [False]
    assert directs(m, [34.5, 35.0], water_kg=100.0) == [False, True]


def test_stuck_factor_counts_from_the_start_of_the_watch_not_from_time_zero():
    # takeoff at 30 s: the watch starts then; a moving centroid attacks at 30 + 40 s, not before
    m = Mission(MissionConfig(takeoff_time_s=30.0))
    m.step(view(30.0, vehicle=VehicleStatus.ON_GROUND, centroid_xy=(0.0, 0.0)))
    ts = [30.0 + 5.0 * k for k in range(1, 9)]  # 35 .. 70 s
    out = [m.step(view(t, centroid_xy=(t * 10.0, 0.0))).direct for t in ts]
    assert out == [False] * 7 + [True]


@pytest.mark.parametrize(
    ("pos", "fires", "want"),
    [
        # nearest by distance is B; nearest on y alone would be A
        ((0.0, 0.0), (FireEntry(11, True, 100.0, 10.0, 5.0), FireEntry(12, True, 30.0, 50.0, 5.0)), 12),
        # nearest by distance is B; nearest on x alone would be A
        ((0.0, 0.0), (FireEntry(11, True, 10.0, 100.0, 5.0), FireEntry(12, True, 50.0, 30.0, 5.0)), 12),
        # from (0, 100): A is 100 m off, B 60 m (a mix-up of x and y would put A at 0 m)
        ((0.0, 100.0), (FireEntry(11, True, 100.0, 100.0, 5.0), FireEntry(12, True, 0.0, 160.0, 5.0)), 12),
    ],
)
def test_fallback_target_is_the_nearest_fire_in_the_plane(pos, fires, want):
    m = airborne(fires=fires, target_fire_id=9)
    d = m.step(view(1.0, fires=fires, target_fire_id=9, pos_xy=pos))
    assert d.target_fire_id == want and d.request is None


def test_any_water_left_is_released():
    m = airborne(MissionConfig(min_water_fraction=0.0), water_kg=0.5)
    assert m.step(view(1.0, water_kg=0.5, pos_xy=(200.0, 100.0))).request == PayloadAction.DROP


def test_drops_are_counted():
    m = airborne()
    for k in range(3):
        t0 = 10.0 * k
        assert m.step(view(t0 + 1.0, pos_xy=(200.0, 100.0))).request == PayloadAction.DROP
        for j in range(2, 6):  # the guard, then a full tank: back to SUPPRESS
            m.step(view(t0 + j, water_kg=2000.0))
        assert m.objective == Objective.SUPPRESS
    assert m.drops == 3
