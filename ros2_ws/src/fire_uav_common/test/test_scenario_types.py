"""The scenario's value types (fire_uav_common.scenario.types): their derived values by hand.

Truths: plain geometry for the area and the start line, B&M (Beard & McLain, *Small Unmanned
Aircraft*, 2012) Eq. 9.14 for the coordinated turn and lift = n W at C_L,max for the stall speed
(the Airframe doc), the docs' bounds for outages. Fast (the mutation selection of
``fire_uav_common.scenario.types`` runs it once per mutant).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from fire_uav_common.errors import ArgumentError, ScheduleError
from fire_uav_common.scenario import AIRFRAMES, Scenario
from fire_uav_common.scenario import types as t

SMALL = AIRFRAMES["small_uav"]


def test_the_area_off_the_origin():
    a = t.Area(10.0, 70.0, -20.0, 80.0)
    assert (a.width_m, a.height_m) == (60.0, 100.0)
    for x, y in [(10.0, -20.0), (70.0, 80.0), (10.0, 80.0), (70.0, -20.0), (40.0, 30.0)]:
        assert a.contains(x, y), (x, y)  # the edges belong to it
    for x, y in [(9.999, 0.0), (70.001, 0.0), (40.0, -20.001), (40.0, 80.001), (-40.0, 30.0), (40.0, -30.0)]:
        assert not a.contains(x, y), (x, y)


@pytest.mark.parametrize(
    ("control", "physics", "n"), [(0.1, 0.01, 10), (0.25, 0.05, 5), (0.1, 0.03, 3), (0.1, 0.04, 2)]
)
def test_substeps_are_the_nearest_whole_number(control, physics, n):
    # 0.1 / 0.01 is 9.999999999999998 in floats: truncation would give 9
    assert t.Timing(control, physics).substeps == n


def test_the_lowest_commanded_speed_and_the_scoop_run():
    af = dataclasses.replace(
        SMALL, v_stall_mps=12.0, min_speed_factor=1.5, water_capacity_kg=30.0, refill_rate_kgps=6.0
    )
    assert af.v_min_mps == pytest.approx(18.0)
    # 30 kg at 6 kg/s: 5 s over the water at 18 m/s
    assert af.scoop_run_m == pytest.approx(90.0)
    assert dataclasses.replace(af, min_speed_factor=1.3).v_min_mps == pytest.approx(15.6)


@pytest.mark.parametrize(("bank_deg", "v"), [(45.0, 20.0), (30.0, 15.0), (60.0, 40.0)])
def test_the_coordinated_turn_rate_is_b_and_m_eq_9_14(bank_deg, v):
    af = dataclasses.replace(SMALL, bank_max_deg=bank_deg)
    assert af.bank_max_rad == pytest.approx(bank_deg * math.pi / 180.0)
    assert af.turn_rate_max_radps(v) == pytest.approx(9.80665 * math.tan(math.radians(bank_deg)) / v)


def test_the_turn_rate_at_rest_is_finite():
    af = dataclasses.replace(SMALL, bank_max_deg=45.0)
    assert af.turn_rate_max_radps(0.0) == pytest.approx(9.80665 / 1e-6)
    assert af.turn_rate_max_radps(-5.0) == pytest.approx(9.80665 / 1e-6)
    assert af.turn_rate_max_radps(2e-6) == pytest.approx(9.80665 / 2e-6)


def test_the_stall_speed_with_the_load_and_the_load_factor():
    af = dataclasses.replace(SMALL, v_stall_mps=12.0, empty_mass_kg=10.0, water_capacity_kg=30.0)
    assert af.stall_speed_mps(30.0) == pytest.approx(12.0)  # the 1 g stall at full load
    assert af.stall_speed_mps(0.0) == pytest.approx(12.0 * math.sqrt(10.0 / 40.0))  # empty tank
    assert af.stall_speed_mps(10.0) == pytest.approx(12.0 * math.sqrt(20.0 / 40.0))
    assert af.stall_speed_mps(30.0, 2.0) == pytest.approx(12.0 * math.sqrt(2.0))  # a 60 deg bank
    assert af.stall_speed_mps(10.0, 4.0) == pytest.approx(12.0 * math.sqrt(4.0 * 20.0 / 40.0))
    assert af.stall_speed_mps(-5.0) == pytest.approx(af.stall_speed_mps(0.0))  # no negative water
    assert af.stall_speed_mps(30.0, -1.0) == 0.0  # no negative load


def test_an_outage_may_last_no_time_but_not_end_before_it_starts():
    assert t.LinkOutage(0, 0, 5.0, 5.0).end_s == 5.0
    with pytest.raises(ScheduleError, match=r"^outage end_s 4.0 before start_s 5.0$"):
        t.LinkOutage(0, 1, 5.0, 4.0)
    with pytest.raises(ScheduleError, match=r"^outage end_s nan before start_s 5.0$"):
        t.LinkOutage(0, 1, 5.0, math.nan)


@pytest.mark.parametrize(("a", "b"), [(-1, 0), (0, -1), (-2, -3)])
def test_an_outage_between_negative_ids_is_named(a, b):
    with pytest.raises(ScheduleError, match=rf"^outage ids must be >= 0, got {a} -> {b}$"):
        t.LinkOutage(a, b, 0.0, 1.0)


def _line(count: int = 4) -> Scenario:
    uavs = t.Uavs(
        count=count, first=t.Pose(12.5, 34.5, 1.5, 0.3), spacing=t.Spacing(4.0, -30.0), takeoff_interval_s=2.5
    )
    return Scenario(name="line", area=t.Area(0.0, 1.0, 0.0, 1.0), uavs=uavs)


def test_the_start_poses_line_up_from_the_first_by_the_spacing():
    s = _line()
    want = [(12.5 + 4.0 * i, 34.5 - 30.0 * i, 1.5, 0.3) for i in range(4)]
    assert s.uav_start_poses() == want
    assert s.uav_start_poses(6) == want + [(12.5 + 4.0 * i, 34.5 - 30.0 * i, 1.5, 0.3) for i in (4, 5)]
    assert s.uav_start_poses(1) == want[:1] and s.uav_start_poses(0) == []
    assert _line(0).uav_start_poses() == []


def test_a_negative_count_of_start_poses_is_named():
    with pytest.raises(ArgumentError, match=r"^count must be >= 0, got -1$"):
        _line().uav_start_poses(-1)


def test_takeoff_slots_every_interval():
    s = _line()
    assert [s.takeoff_time_s(i) for i in range(4)] == [0.0, 2.5, 5.0, 7.5]


def _energy(margin: float = 1.0) -> t.ExcessPower:
    return t.ExcessPower(
        speeds_mps=(40.0, 50.0, 70.0),
        water_kg=(0.0, 1000.0),
        climb_mps=((2.0, 6.0, 4.0), (0.0, 3.0, 1.0)),
        power_mps=((4.0, 6.0, 4.0), (2.0, 3.0, 1.0)),
        margin=margin,
    )


def test_the_energy_tables_are_bilinear_between_their_points():
    e = _energy()
    for v in (35.0, 40.0, 44.0, 50.0, 63.0, 70.0, 90.0):  # the end values beyond the axis
        for w, row in ((0.0, 0), (1000.0, 1)):
            assert e.power_at(v, w) == pytest.approx(float(np.interp(v, e.speeds_mps, e.power_mps[row])))
        lo = float(np.interp(v, e.speeds_mps, e.climb_mps[0]))
        hi = float(np.interp(v, e.speeds_mps, e.climb_mps[1]))
        assert e.climb_max_at(v, 250.0) == pytest.approx(0.75 * lo + 0.25 * hi)
    assert _energy(0.9).power_at(50.0, 0.0) == pytest.approx(5.4)


@pytest.mark.parametrize(
    ("v", "climb_c", "accel_c"),
    [
        (45.0, 5.0, 1.0),
        (50.0, 2.0, 1.0),
        (50.0, 2.0, 0.1),
        (60.0, -3.0, 1.0),
        (70.0, 5.0, -0.5),
        (80.0, 1.0, 0.5),
    ],
)
def test_the_energy_split_spends_no_more_than_the_excess_power_and_climbs_first(v, climb_c, accel_c):
    """Energy conservation (Lambregts 1983): climb + (v / g) dv/dt <= P_s; the climb gets what it is
    commanded up to its limit before the speed gets any (climb first); a descent is never limited."""
    e = _energy()
    w = 0.0
    climb, accel = e.split(v, w, climb_c, accel_c)
    assert climb + v * accel / t.G_MPS2 <= e.power_at(v, w) + 1e-9 or accel == accel_c
    assert accel <= accel_c
    assert climb == (climb_c if climb_c <= 0.0 else min(climb_c, max(e.climb_max_at(v, w), 0.0)))
    if accel < accel_c:  # the speed short: the power is spent, no more
        assert climb + v * accel / t.G_MPS2 == pytest.approx(e.power_at(v, w))


def test_the_energy_split_of_the_modelled_climb_and_beyond_the_top_speed():
    e = _energy()
    # 5 m/s of a lagging climb spend all but 1 m/s of 6: the speed gets g x 1 / 50
    assert e.split(50.0, 0.0, 6.0, 3.0, 5.0) == (6.0, pytest.approx(t.G_MPS2 / 50.0))
    # where the climb is below zero at full throttle it is cut to level, and the aircraft slows
    e2 = t.ExcessPower((60.0, 80.0), (0.0,), ((1.0, -2.0),), ((1.0, -2.0),), margin=1.0)
    climb, accel = e2.split(80.0, 0.0, 3.0, 1.0)
    assert climb == 0.0 and accel == pytest.approx(-2.0 * t.G_MPS2 / 80.0)


def test_energy_tables_of_the_wrong_shape_are_refused():
    with pytest.raises(ArgumentError):
        t.ExcessPower((40.0, 50.0), (0.0,), ((1.0, 2.0, 3.0),), ((1.0, 2.0),))
    with pytest.raises(ArgumentError):
        t.ExcessPower((50.0, 40.0), (0.0,), ((1.0, 2.0),), ((1.0, 2.0),))


def test_the_turns_induced_drag_is_that_of_a_parabolic_polar():
    """A made-up aircraft with a parabolic drag polar: P_s = A(v) / m - c m n^2 / v (thrust power
    less parasitic drag over the weight, less the induced drag k n^2 W^2 / q times v over W). Its
    level-flight table at two masses gives back the turn's P_s at any mass and load factor."""
    speeds, masses, c = (40.0, 55.0, 70.0), (1500.0, 2500.0), 0.07
    a = {40.0: 9000.0, 55.0: 12000.0, 70.0: 10000.0}

    def ps(v: float, m: float, n: float = 1.0) -> float:
        return a[v] / m - c * m * n * n / v

    rows = tuple(tuple(ps(v, m) for v in speeds) for m in masses)
    e = t.ExcessPower(speeds, (0.0, 1000.0), rows, rows, mass_kg=masses, margin=1.0)
    for v in speeds:
        for w, m in ((0.0, 1500.0), (1000.0, 2500.0)):
            for n in (1.0, 1.0 / math.cos(math.radians(30.0)), math.sqrt(2.0)):
                assert e.power_at(v, w, n) == pytest.approx(ps(v, m, n))
                assert e.climb_max_at(v, w, n) == pytest.approx(ps(v, m, n))


def test_at_its_floor_the_aircraft_holds_its_speed_before_it_climbs():
    """Full of water in a hard turn at the slowest speed it flies, P_s < 0: the split holds the
    speed (no deceleration below the floor) and gives up height at P_s (energy conservation);
    above the floor the same command cuts the climb to level and slows the aircraft."""
    e = t.ExcessPower((40.0, 60.0), (0.0,), ((-1.0, -1.0),), ((-1.0, -1.0),), margin=1.0)
    assert e.split(45.0, 0.0, 2.0, 0.5, v_floor_mps=46.0) == (-1.0, 0.0)
    climb, accel = e.split(50.0, 0.0, 2.0, 0.5, v_floor_mps=46.0)
    assert climb == 0.0 and accel == pytest.approx(-t.G_MPS2 / 50.0)


def _polar(masses: tuple[float, ...], c: float = 0.07, margin: float = 1.0) -> t.ExcessPower:
    """A made-up aircraft with a parabolic drag polar (as above), tabulated at each mass in level
    flight, water 0, 500, 1000 kg for three masses (JSBSim weighs the water linearly)."""
    speeds = (40.0, 55.0, 70.0)
    a = {40.0: 9000.0, 55.0: 12000.0, 70.0: 10000.0}
    rows = tuple(tuple(a[v] / m - c * m / v for v in speeds) for m in masses)
    water = tuple(500.0 * k for k in range(len(masses)))
    return t.ExcessPower(speeds, water, rows, rows, mass_kg=masses, margin=margin)


def test_a_third_water_row_is_interpolated_between_its_neighbours():
    """Bilinear in water as well: at 750 kg halfway between the second and third rows (of three),
    the level-flight value is their mean; the turn's induced drag there is c m n^2 / v less c m / v
    with m halfway between their masses (1875 kg), c = 0.07 the polar's."""
    e = t.ExcessPower(
        (40.0, 50.0),
        (0.0, 500.0, 1000.0),
        ((1.0, 2.0), (3.0, 4.0), (7.0, 10.0)),
        ((1.0, 2.0), (3.0, 4.0), (7.0, 10.0)),
        margin=1.0,
    )
    assert e.power_at(45.0, 750.0) == pytest.approx(0.5 * (3.5 + 8.5))
    assert e.climb_max_at(50.0, 250.0) == pytest.approx(3.0)
    p = _polar((1500.0, 1750.0, 2000.0))
    n = math.sqrt(2.0)
    for v in (40.0, 55.0, 70.0):
        assert p.power_at(v, 750.0) - p.power_at(v, 750.0, n) == pytest.approx(0.07 * 1875.0 / v)


def test_the_defaults_are_level_flight_and_without_masses_there_is_no_turn_term():
    """The tables are measured in level flight (n = 1): a call without a load factor reads them as
    they are; a table without ``mass_kg`` has no induced-drag term (class doc), so a turn reads the
    same."""
    p = _polar((1500.0, 2500.0))
    for v, row in ((40.0, 0), (70.0, 1)):
        w = 1000.0 * row
        assert p.power_at(v, w) == pytest.approx(p.power_mps[row][p.speeds_mps.index(v)])
        assert p.climb_max_at(v, w) == pytest.approx(p.climb_mps[row][p.speeds_mps.index(v)])
        assert p.split(v, w, 50.0, 0.0) == (pytest.approx(p.climb_mps[row][p.speeds_mps.index(v)]), 0.0)
    e = _energy()
    assert e.power_at(50.0, 0.0, 2.0) == e.power_at(50.0, 0.0) == 6.0
    assert e.climb_max_at(50.0, 0.0, 2.0) == e.climb_max_at(50.0, 0.0) == 6.0


def test_in_a_turn_the_split_spends_the_turns_excess_power():
    """At n = sqrt(2) (a 45 deg coordinated turn, B&M Eq. 9.14) the polar's P_s is A / m - 2 c m / v:
    the climb is cut to it and the speed gets nothing more (Lambregts: climb + (v / g) dv/dt <= P_s);
    a small climb leaves the rest, g (P_s - climb) / v, to the speed."""
    p = _polar((1500.0, 2500.0))
    n, v, m = math.sqrt(2.0), 55.0, 1500.0
    ps = 12000.0 / m - 0.07 * m * n * n / v
    climb, accel = p.split(v, 0.0, 50.0, 1.0, load_factor=n)
    assert climb == pytest.approx(ps) and accel == pytest.approx(0.0, abs=1e-9)
    climb, accel = p.split(v, 0.0, 1.0, 5.0, load_factor=n)
    assert climb == 1.0 and accel == pytest.approx(t.G_MPS2 * (ps - 1.0) / v)


def test_at_exactly_its_floor_the_speed_comes_first_even_on_a_hold():
    """The split's doc: *at or below* ``v_floor_mps`` the speed is held first. At the floor itself,
    and on a command to hold the speed (dv/dt 0), the climb is cut to P_s < 0; a modelled climb that
    still spends 2 m/s does not slow the aircraft below its floor."""
    e = t.ExcessPower((40.0, 60.0), (0.0,), ((-1.0, -1.0),), ((-1.0, -1.0),), margin=1.0)
    assert e.split(46.0, 0.0, 2.0, 0.5, v_floor_mps=46.0) == (-1.0, 0.0)
    assert e.split(45.0, 0.0, 2.0, 0.0, v_floor_mps=46.0) == (-1.0, 0.0)
    assert e.split(46.0, 0.0, 2.0, 0.5, climb_now_mps=2.0, v_floor_mps=46.0) == (-1.0, 0.0)


def test_the_margin_keeps_a_reserve_on_either_side_of_zero():
    """``margin`` < 1 keeps a reserve: what the split may spend is below the measured P_s whether
    that is a surplus (a share of it, 0.9 x 0.5) or a deficit (counted larger)."""
    e = t.ExcessPower((40.0, 60.0), (0.0,), ((0.5, -1.0),), ((0.5, -1.0),), margin=0.9)
    assert e.power_at(40.0, 0.0) == pytest.approx(0.45)
    assert e.power_at(60.0, 0.0) < -1.0
    assert e.climb_max_at(60.0, 0.0) < -1.0


def test_every_malformed_table_is_refused_with_its_reason():
    one = ((1.0,),)
    with pytest.raises(ArgumentError, match=r"tables must be 1 x 1 \(water x speed\), with >= 2 speeds"):
        t.ExcessPower((40.0,), (0.0,), one, one)
    with pytest.raises(
        ArgumentError, match=r"mass_kg needs one mass per water row \(>= 2\), got \(1\.0, 2\.0, 3\.0\)"
    ):
        t.ExcessPower((40.0, 50.0), (0.0, 1.0), ((1.0, 2.0),) * 2, ((1.0, 2.0),) * 2, mass_kg=(1.0, 2.0, 3.0))
    with pytest.raises(ArgumentError, match="mass_kg needs one mass per water row"):
        t.ExcessPower((40.0, 50.0), (0.0,), ((1.0, 2.0),), ((1.0, 2.0),), mass_kg=(1.0,))
    with pytest.raises(ArgumentError, match=r"axis must be ascending, got \(40\.0, 40\.0\)"):
        t.ExcessPower((40.0, 40.0), (0.0,), ((1.0, 2.0),), ((1.0, 2.0),))
