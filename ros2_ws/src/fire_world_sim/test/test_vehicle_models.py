"""Vehicle-model backends (``uavs.vehicle_model``): for every backend the sensors read the flown
truth, not the command, and collisions happen at exactly the configured radius; for
``coordinated_turn`` the envelope of Beard & McLain ch. 9 (bank and roll-rate limits, the
coordinated-turn rate g tan(phi) / v, first-order airspeed, climb limits, stall with load, wind
drift) checked against its analytic values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_common.scenario import AIRFRAMES, ScenarioError
from fire_uav_common.scenario.airframes import G_MPS2
from fire_world_sim.vehicle import Status
from fire_world_sim.vehicles import Command, CoordinatedTurnModel, FlightState
from fire_world_sim.world import EventType, World

from .conftest import make_scenario

BACKENDS = ("ff_paper", "coordinated_turn", "jsbsim")
SMALL = AIRFRAMES["small_uav"]
EXACT_SENSORS = {
    "gyro": {"rate_hz": 100.0, "sigma_radps": 0.0, "p_valid": 1.0},
    "gps": {"rate_hz": 10.0, "sigma_m": 0.0, "p_valid": 1.0},
    "altimeter": {"rate_hz": 10.0, "sigma_m": 0.0, "p_valid": 1.0, "max_range_m": 1000.0},
}


def _world(
    model: str, count: int = 1, dy_m: float = 30.0, noise: float = 0.0, radius_m: float = 3.0, **extra
):
    sc = make_scenario(
        lakes=[],
        uavs={
            "count": count,
            "first": {"x_m": 200.0, "y_m": 500.0, "yaw_rad": 0.0},
            "spacing": {"dx_m": 0.0, "dy_m": dy_m},
            "vehicle_model": model,
        },
        vehicle={"process_noise_sigma": noise, "collision_radius_m": radius_m},
        sensors=EXACT_SENSORS,
        fires={"analytic": [{"x_m": 10.0, "y_m": 10.0, "sigma_m": 5.0}]},
        **extra,
    )
    return World(sc, seed=3)


def _takeoff_speed(w: World) -> float:
    return w.scenario.vehicle.v_stall_mps + 2.0


@pytest.mark.parametrize("model", BACKENDS)
def test_gyro_gps_and_altimeter_read_the_flown_truth(model: str) -> None:
    # ff_paper: process noise makes the flown yaw rate differ from the command;
    # coordinated_turn: the bank lags the commanded turn, so the flown rate does
    w = _world(model, noise=0.5 if model == "ff_paper" else 0.0)
    v = _takeoff_speed(w)
    prev = w.step({0: Command(v, 2.0, 0.0)}).vehicles[0]
    checked = 0
    for k in range(40):
        r = w.step({0: Command(v, 1.0, 0.6)})
        now = r.vehicles[0]
        b = r.bundles[0]
        # the gyro samples every substep: their mean is the heading change over the step
        dyaw = math.remainder(now.yaw_rad - prev.yaw_rad, 2 * math.pi)
        assert len(b.gyro) == w.substeps
        assert np.mean([g.omega_z_radps for g in b.gyro]) == pytest.approx(
            dyaw / w.control_period_s, abs=1e-9
        ), k
        # GPS and altimeter at t_{k+1} read the truth at t_{k+1}
        gps = [g for g in b.gps if g.stamp_ns == r.stamp_ns]
        alt = [a for a in b.altimeter if a.stamp_ns == r.stamp_ns]
        assert gps and alt
        assert (gps[0].x_m, gps[0].y_m) == pytest.approx((now.x_m, now.y_m), abs=1e-9)
        assert alt[0].range_m == pytest.approx(now.z_m, abs=1e-9)  # flat ground at 0
        checked += abs(dyaw / w.control_period_s - 0.6) > 0.05  # the flown rate is not the command
        prev = now
    assert checked >= 5


@pytest.mark.parametrize("model", BACKENDS)
@pytest.mark.parametrize("offset_m", [-0.05, 0.05])
def test_collisions_happen_at_exactly_the_configured_radius(model: str, offset_m: float) -> None:
    radius = 7.0
    w = _world(model, count=2, dy_m=radius + offset_m, radius_m=radius)
    v = _takeoff_speed(w)
    res = [w.step({0: Command(v, 2.0, 0.0), 1: Command(v, 2.0, 0.0)})]
    for _ in range(20):  # the same commands, the same dynamics: the pair stays dy apart
        res.append(w.step({0: Command(v, 1.0, 0.0), 1: Command(v, 1.0, 0.0)}))
    crashed = [e for r in res for e in r.events if e.type == EventType.CRASH]
    if offset_m < 0:
        assert sorted(e.uav_id for e in crashed) == [0, 1] and res[-1].collisions == 1
    else:
        assert not crashed and res[-1].collisions == 0
        assert res[-1].min_separation_m == pytest.approx(radius + offset_m, abs=1e-6)


# --- coordinated_turn: Beard & McLain ch. 9 ------------------------------------------------------
def _airborne(water_kg: float = 0.0, v_mps: float | None = None) -> tuple[CoordinatedTurnModel, FlightState]:
    m = CoordinatedTurnModel(SMALL, 0.0)
    v = SMALL.v_min_mps + 5.0 if v_mps is None else v_mps
    return m, FlightState(0.0, 0.0, 100.0, 0.0, airspeed_mps=v, water_kg=water_kg)


def _run(m, s, cmd, seconds, dt=0.01, wind=(0.0, 0.0)) -> list[FlightState]:
    rng = np.random.default_rng(0)
    out = []
    for _ in range(round(seconds / dt)):
        (s,) = m.step([s], [cmd], dt, [rng], wind)
        out.append(s)
    return out


def test_a_hard_turn_command_flies_the_bank_limit_and_its_radius() -> None:
    m, s = _airborne()
    v = s.airspeed_mps
    traj = _run(m, s, Command(v, 0.0, 10.0), 20.0)  # FF's 10 rad/s: far beyond the envelope
    phi_max = math.radians(SMALL.bank_max_deg)
    assert max(abs(f.bank_rad) for f in traj) == pytest.approx(phi_max, rel=1e-9)
    assert all(abs(f.turn_rate_radps) <= G_MPS2 * math.tan(phi_max) / f.airspeed_mps + 1e-12 for f in traj)
    # steady state: the circle of radius v^2 / (g tan phi_max)
    last = traj[len(traj) // 2 :]
    xs, ys = np.array([f.x_m for f in last]), np.array([f.y_m for f in last])
    r = (xs.max() - xs.min()) / 2
    assert r == pytest.approx(v**2 / (G_MPS2 * math.tan(phi_max)), rel=0.01)
    assert (ys.max() - ys.min()) / 2 == pytest.approx(r, rel=0.01)


def test_bank_rises_no_faster_than_the_roll_rate_limit_with_first_order_lag() -> None:
    m, s = _airborne()
    traj = _run(m, s, Command(s.airspeed_mps, 0.0, 10.0), 2.0)
    rates = np.diff([0.0] + [f.bank_rad for f in traj]) / 0.01
    assert rates.max() <= math.radians(SMALL.roll_rate_max_degps) + 1e-9
    assert rates.max() == pytest.approx(math.radians(SMALL.roll_rate_max_degps), rel=1e-6)  # the limit binds


def test_airspeed_follows_a_first_order_response_within_the_acceleration_limit() -> None:
    m, s = _airborne(v_mps=20.0)
    traj = _run(m, s, Command(21.0, 0.0, 0.0), 3 * SMALL.tau_airspeed_s, dt=0.001)
    # a 1 m/s step is below the acceleration limit: v(t) = 21 - exp(-t / tau)
    k = round(SMALL.tau_airspeed_s / 0.001) - 1
    assert traj[k].airspeed_mps == pytest.approx(21.0 - math.exp(-1.0), abs=2e-3)
    big = _run(m, s, Command(SMALL.v_max_mps, 0.0, 0.0), 1.0)
    assert big[-1].airspeed_mps == pytest.approx(20.0 + SMALL.accel_max_mps2 * 1.0, rel=1e-6)


def test_climb_and_descent_stay_within_their_limits() -> None:
    m, s = _airborne()
    up = _run(m, s, Command(s.airspeed_mps, 100.0, 0.0), 10.0)
    down = _run(m, s, Command(s.airspeed_mps, -100.0, 0.0), 10.0)
    # the flight-path angle approaches its limit as a first-order lag, never beyond it
    assert SMALL.climb_max_mps * (1 - 1e-4) <= max(f.climb_mps for f in up) <= SMALL.climb_max_mps
    assert -SMALL.descent_max_mps <= min(f.climb_mps for f in down) <= -SMALL.descent_max_mps * (1 - 1e-4)


def test_stall_speed_rises_with_load_factor_and_water() -> None:
    m, _ = _airborne()
    v = 1.1 * SMALL.v_stall_mps  # the stall limit (34 deg full) binds below the 45 deg bank limit
    full, empty = m.bank_limit_rad(v, SMALL.water_capacity_kg), m.bank_limit_rad(v, 0.0)
    # n = 1 / cos(phi) may rise to (v / v_s(m))^2 (lift = n W at C_L,max)
    assert 1 / math.cos(full) == pytest.approx((v / SMALL.v_stall_mps) ** 2, rel=1e-9)
    assert empty > full
    assert SMALL.stall_speed_mps(SMALL.water_capacity_kg, 2.0) == pytest.approx(
        SMALL.v_stall_mps * math.sqrt(2)
    )


def test_the_aircraft_drifts_with_the_wind() -> None:
    m, s = _airborne()
    calm = _run(m, s, Command(s.airspeed_mps, 0.0, 0.0), 10.0)[-1]
    windy = _run(m, s, Command(s.airspeed_mps, 0.0, 0.0), 10.0, wind=(0.0, 4.0))[-1]
    assert (windy.x_m - calm.x_m, windy.y_m - calm.y_m) == pytest.approx((0.0, 40.0), abs=1e-9)


def test_coordinated_turn_takes_off_at_its_lowest_speed_and_lands_below_it() -> None:
    w = _world("coordinated_turn")
    veh = w.vehicles[0]
    assert w.scenario.vehicle.v_stall_mps == pytest.approx(SMALL.v_min_mps)
    w.step({0: Command(SMALL.v_min_mps, 2.0, 0.0)})
    assert veh.status == Status.AIRBORNE and veh.airspeed_mps == pytest.approx(SMALL.v_min_mps)
    assert isinstance(w.vehicle_model, CoordinatedTurnModel) and veh.model is w.vehicle_model
    for _ in range(50):
        w.step({0: Command(SMALL.v_min_mps, 1.0, 0.0)})
    assert veh.height_above_terrain_m() > 0.5
    while veh.height_above_terrain_m() >= w.scenario.vehicle.landing_height_m:
        w.step({0: Command(SMALL.v_min_mps, -SMALL.descent_max_mps, 0.0)})
    w.step({0: Command(SMALL.v_min_mps - 1.0, 0.0, 0.0)})
    assert veh.status == Status.LANDED and veh.airspeed_mps == 0.0


# --- scenario: the model, the preset, and bad input ---------------------------------------------
def test_a_fixed_wing_model_alone_flies_the_small_uav_preset() -> None:
    sc = make_scenario(uavs={"vehicle_model": "coordinated_turn"})
    assert sc.uavs.airframe == SMALL
    assert sc.vehicle.omega_max_radps == pytest.approx(G_MPS2 * math.tan(math.radians(45)) / SMALL.v_min_mps)
    assert sc.vehicle.water_capacity_kg == SMALL.water_capacity_kg
    ff = make_scenario()
    assert ff.uavs.vehicle_model == "ff_paper" and ff.uavs.airframe is None
    assert ff.vehicle.omega_max_radps == 10.0  # FF's envelope stays


@pytest.mark.parametrize(
    ("uavs", "field"),
    [
        ({"vehicle_model": "helicopter"}, "uavs.vehicle_model"),
        ({"vehicle_model": "coordinated_turn", "airframe": "zeppelin"}, "uavs.airframe"),
        (
            {"vehicle_model": "coordinated_turn", "airframe": {"preset": "tanker", "v_stall_mps": 80}},
            "uavs.airframe.v_stall_mps",
        ),
        (
            {"vehicle_model": "coordinated_turn", "airframe": {"bank_max_deg": 85}},
            "uavs.airframe.bank_max_deg",
        ),
        (
            {"vehicle_model": "coordinated_turn", "airframe": {"bank_max_deg": 0}},
            "uavs.airframe.bank_max_deg",
        ),
        ({"airframe": "tanker"}, "uavs.airframe"),
    ],
)
def test_bad_model_or_preset_is_one_line_naming_the_field(uavs: dict, field: str) -> None:
    with pytest.raises(ScenarioError, match=rf"^<dict>: {field}: ") as e:
        make_scenario(uavs=uavs)
    assert "\n" not in str(e.value)
