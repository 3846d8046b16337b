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
