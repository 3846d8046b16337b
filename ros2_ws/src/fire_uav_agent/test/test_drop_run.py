"""A pattern drop's run: low and slow near the aim point (fire_uav_agent.guidance.Guide._drop_run).

Truth: the world's own ground-pattern model (fire_world_sim.drop_pattern, (P1)-(P3)) and the
fire services' coverage level for grass (FBFM 1: CL 1, 0.41 L/m^2): a tanker's drop from its run
reaches it, the same drop from the layer and speed it cruises at does not (grass_running_tanker:
no cell put out from the 22 and 36 m layers, docs/airframes.md).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.agent_config import config_from_scenario
from fire_uav_agent.agent_core import Agent
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common.scenario import load_scenario
from fire_world_sim.drop_pattern import L_PER_M2_PER_CL, Release, coverage_level, pattern_of

GRASS_LPM2 = coverage_level(1) * L_PER_M2_PER_CL  # FBFM 1 (short grass): CL 1


def _tanker(uid: int, leg: bool = False, **over):
    sc = load_scenario(scenario_path("grass_running_tanker"), overrides=over)
    return sc, Agent(config_from_scenario(sc, uid, uav_count=5, seed=1, loss_probability=0.0, drop_leg=leg))


def _peak(sc, height_m: float, speed_mps: float) -> float:
    af = sc.uavs.airframe
    r = Release(0.0, 0.0, 0.0, speed_mps, height_m, af.water_capacity_kg, af.drop_flow_lps)
    return pattern_of(r).peak_lpm2


@pytest.mark.parametrize("uid", [1, 2])  # the 22 and 36 m layers
def test_the_run_puts_grass_out_where_the_cruise_does_not(uid):
    sc, a = _tanker(uid)
    g = a.guide
    aim = (3000.0, 3000.0)
    run = g._drop_run((aim[0] + 0.5 * g.drop_run_m, aim[1]), aim)
    assert run is not None
    height, speed = run
    assert _peak(sc, height, speed) >= GRASS_LPM2
    layer = g.raster.tactic.layer_height_m(uid)
    assert height < layer
    assert _peak(sc, layer, sc.uavs.airframe.v_max_mps) < GRASS_LPM2


def test_the_run_begins_where_the_tanker_can_still_slow_and_descend():
    """From its top speed to the run's speed at its deceleration limit, (v0^2 - v1^2) / (2 a)
    (B&M Eq. 9.18), plus the release radius; the tanker's descent from 36 to 8 m is shorter."""
    sc, a = _tanker(2)
    g = a.guide
    af = sc.uavs.airframe
    v_run = g._drop_run((0.0, 0.0), (1.0, 0.0))[1]
    slow = (af.v_max_mps**2 - v_run**2) / (2.0 * af.accel_max_mps2)
    assert g.drop_run_m == pytest.approx(g.raster.tactic.release_radius_m + slow)
    assert g._drop_run((0.0, 0.0), (g.drop_run_m * 1.0001, 0.0)) is None
    assert g._drop_run((0.0, 0.0), (g.drop_run_m * 0.9999, 0.0)) is not None


def test_no_run_where_the_drop_is_a_disc():
    for name in ("grass_running", "ff_two_fires"):
        sc = load_scenario(scenario_path(name))
        a = Agent(config_from_scenario(sc, 0, uav_count=2, seed=1, loss_probability=0.0))
        assert a.guide.drop_run_m == 0.0 and a.guide._drop_run((0.0, 0.0), (1.0, 0.0)) is None
    _, a = _tanker(0, **{"fires.drop_model": "disc"})
    assert a.guide.drop_run_m == 0.0
    assert math.isfinite(_tanker(0)[1].guide.drop_run_m)


def _fly_run(a, front_deg: float, start_xy: tuple[float, float], yaw: float, wind=(0.0, 0.0)):
    """Fly uav ``a`` (tanker) on its guide's commands toward an aim point on a straight front of
    burning cells through (3000, 3000) at ``front_deg``; a unicycle at the commanded speed and turn
    rate, the turn rate held to the airframe's bank limit (g tan(phi_max) / v), drifted by ``wind``
    [m/s] (the guide sees the drifted pose, as from its EKF). Returns the
    track [(x, y, yaw)] until the UAV is within the release radius of the aim point, or 6,000 steps."""
    from fire_uav_agent.fire_front import FrontConfig, FrontPicture
    from fire_uav_agent.guidance import Situation
    from fire_uav_agent.mission import Decision
    from fire_uav_agent.planning import PlannerView
    from fire_uav_common.codecs.uav_state import FireEntry
    from fire_uav_common.constants import CellState, Objective, VehicleStatus

    g = a.guide
    cfg = a.cfg
    aim = (3000.0, 3000.0)
    th = math.radians(front_deg)
    d = np.arange(-600.0, 601.0, 5.0)  # a line of burning cells 1.2 km long (10 m cells)
    pic = FrontPicture(FrontConfig(cfg.area_m, 10.0))
    x, y = aim[0] + d * math.cos(th), aim[1] + d * math.sin(th)
    pic.observe(x, y, np.full(x.shape, int(CellState.BURNING)), 1.0)
    a.raster.front = pic
    t_s = 1.0
    fire = FireEntry(0, True, aim[0], aim[1], 0.0)
    cell = np.ones(a.grid.points.shape[0], dtype=bool)
    s = np.array([start_xy[0], start_xy[1], 8.0, yaw])
    af = cfg.airframe
    dt = cfg.control_period_s
    track = [(float(s[0]), float(s[1]), float(s[3]))]
    for k in range(6000):
        view = PlannerView(t_s, cfg.uav_id, s, a.grid, cell, {}, (fire,))
        sit = Situation(Decision(Objective.SUPPRESS, 0, None, False, False), (fire,), None, view, cell, aim)
        v, _, om = g.run(sit, VehicleStatus.AIRBORNE, s, k).command
        w_max = af.turn_rate_max_radps(v)
        om = max(-w_max, min(w_max, om))
        s = s.copy()
        s[3] = math.remainder(s[3] + om * dt, math.tau)
        s[0] += (v * math.cos(s[3]) + wind[0]) * dt
        s[1] += (v * math.sin(s[3]) + wind[1]) * dt
        track.append((float(s[0]), float(s[1]), float(s[3])))
        if math.hypot(s[0] - aim[0], s[1] - aim[1]) < g.raster.tactic.release_radius_m:
            break  # over the aim point
    return track


@pytest.mark.parametrize("front_deg, wind_across", [(30.0, 0.0), (-60.0, 0.0), (30.0, 3.0), (30.0, -3.0)])
def test_the_run_is_lined_up_with_the_front(front_deg, wind_across):
    """A tanker arriving square to a straight front (1.5 km out, heading at the aim) reaches the aim
    point flying along the front, within 10 deg of it, and has flown its last 200 m (a pattern's
    length: its line from the release on) within 15 deg of it and 25 m of the front's line. Today's
    run (straight at the aim) crosses the front at 90 deg. With grass_running_tanker's 3 m/s across
    the front the leg is held on the line by the crab angle (without it: about 22 m off)."""
    _, a = _tanker(0, leg=True)
    g = a.guide
    th = math.radians(front_deg)
    normal = (-math.sin(th), math.cos(th))
    start = (3000.0 + 1500.0 * normal[0], 3000.0 + 1500.0 * normal[1])
    yaw = math.atan2(-normal[1], -normal[0])  # heading at the aim, square to the front
    track = _fly_run(a, front_deg, start, yaw, (wind_across * normal[0], wind_across * normal[1]))
    x, y, psi = track[-1]
    assert math.hypot(x - 3000.0, y - 3000.0) < g.raster.tactic.release_radius_m

    def off_deg(p):  # angle between the heading and the front's line [deg], 0-90
        e = abs(math.remainder(p - th, math.pi))
        return math.degrees(e)

    assert off_deg(psi) < 10.0 + 4.0 * abs(wind_across)  # the heading, crabbed into the wind
    tail, flown = [], 0.0
    for (x0, y0, _), (x1, y1, p1) in zip(reversed(track[:-1]), reversed(track[1:]), strict=False):
        tail.append((x1, y1, p1))
        flown += math.hypot(x1 - x0, y1 - y0)
        if flown >= 200.0:
            break
    assert flown >= 200.0
    for xi, yi, pi in tail:
        assert off_deg(pi) < 15.0 + 4.0 * abs(wind_across)
        assert abs((xi - 3000.0) * normal[0] + (yi - 3000.0) * normal[1]) < 25.0
    assert g.leg_counts["leg"] >= 1


def test_no_leg_without_a_line_of_front_cells():
    """Fewer than five front cells near the aim: today's straight run at the aim point."""
    from fire_uav_agent.fire_front import FrontConfig, FrontPicture
    from fire_uav_common.constants import CellState

    _, a = _tanker(0, leg=True)
    g = a.guide
    pic = FrontPicture(FrontConfig(a.cfg.area_m, 10.0))
    pic.observe(
        np.array([3000.0, 3010.0]), np.array([3000.0, 3000.0]), np.full(2, int(CellState.BURNING)), 1.0
    )
    a.raster.front = pic
    s = np.array([3000.0, 2000.0, 8.0, math.pi / 2])
    assert g._drop_leg(s, (3000.0, 3000.0), 1.0) == (3000.0, 3000.0)
    assert g.leg_counts["few_cells"] == 1 and g.leg is None


def test_the_leg_is_off_by_default():
    """Without AgentConfig.drop_leg the run flies straight at the aim, square to the front as it came."""
    _, a = _tanker(0)
    track = _fly_run(
        a, 30.0, (3000.0 - 750.0, 3000.0 + 1500.0 * math.cos(math.radians(30.0))), math.radians(-60.0)
    )
    assert abs(math.degrees(abs(math.remainder(track[-1][2] - math.radians(30.0), math.pi))) - 90.0) < 1.0
    assert a.guide.leg_counts["leg"] == 0 and a.guide.leg is None


@pytest.mark.parametrize("deg", [0.0, 30.0, 90.0, 135.0])
def test_front_tangent_is_the_line_of_the_cells(deg):
    """Cells on a line (10 m cells, jittered by up to 4 m across it) give the line's direction
    (either sense); a square block of cells (no line) and too few cells give None."""
    from fire_uav_agent.fire_front import FrontCells
    from fire_uav_agent.tactics import front_tangent

    def cells(x, y):
        z = np.zeros(len(x))
        return FrontCells(np.asarray(x, float), np.asarray(y, float), z.astype(np.int64), z, z)

    th = math.radians(deg)
    d = np.arange(-150.0, 151.0, 10.0)
    jit = 4.0 * np.sin(d)  # a deterministic ragged edge
    x = 500.0 + d * math.cos(th) - jit * math.sin(th)
    y = 500.0 + d * math.sin(th) + jit * math.cos(th)
    t = front_tangent(cells(x, y), (500.0, 500.0), 200.0)
    assert t is not None
    assert math.degrees(abs(math.remainder(math.atan2(t[1], t[0]) - th, math.pi))) < 2.0
    gx, gy = np.meshgrid(np.arange(0.0, 100.0, 10.0), np.arange(0.0, 100.0, 10.0))
    assert front_tangent(cells(gx.ravel(), gy.ravel()), (50.0, 50.0), 200.0) is None
    assert front_tangent(cells(x[:4], y[:4]), (x[1], y[1]), 200.0) is None


def _small_uav(uid: int):
    over = {"uavs.vehicle_model": "coordinated_turn", "fires.drop_model": "pattern"}
    sc = load_scenario(scenario_path("grass_running"), overrides=over)
    return sc, Agent(config_from_scenario(sc, uid, uav_count=6, seed=1, loss_probability=0.0))


@pytest.mark.parametrize("uid", [0, 1, 2])
def test_a_small_uav_whose_pattern_cannot_put_grass_out_keeps_its_layer(uid):
    """Issue 36: the small UAV's 10 L at 5 L/s from the run (8 m up, sigma = 2 + 0.5 x 8 = 6 m by
    (P3), at 18.6 m/s: a 37 m line) peaks by (P2) at (5 / 18.6) / (sqrt(2 pi) 6) = 0.018 L/m^2,
    under grass's CL 1 (0.41 L/m^2): no run. Its fleet flew the run down to one layer and passed
    under 10 m in 4 of 6 missions for nothing (docs/suppression.md)."""
    sc, a = _small_uav(uid)
    g = a.guide
    af = sc.uavs.airframe
    assert (af.water_capacity_kg, af.drop_flow_lps, g.v_slow_mps) == (10.0, 5.0, pytest.approx(18.6))
    by_hand = (5.0 / 18.6) / (math.sqrt(2.0 * math.pi) * 6.0)  # L >> sigma: the line's middle
    assert by_hand < 0.05 * GRASS_LPM2
    assert _peak(sc, 8.0, g.v_slow_mps) == pytest.approx(by_hand, rel=0.02)  # the world's pattern
    aim = (500.0, 500.0)
    assert g._drop_run((aim[0] + 0.5 * g.drop_run_m, aim[1]), aim) is None
    assert g.run_skips == 1 and "drop run skipped" in (g.skip_note or "")
    assert g._drop_run((aim[0] + 2.0 * g.drop_run_m, aim[1]), aim) is None  # far: no run, no skip
    assert g.run_skips == 1


@pytest.mark.parametrize("fuel_model, flies", [(1, True), (5, False)])
def test_the_tanker_flies_its_run_only_where_its_pattern_reaches_the_fuels_level(fuel_model, flies):
    """The tanker's 3,000 L at 757 L/s from the run (8 m, 49.8 m/s: a 197 m line, sigma 6 m) peaks
    at (757 / 49.8) / (sqrt(2 pi) 6) = 1.01 L/m^2 = CL 2.5 by (P2)-(P3): it reaches grass's CL 1
    (FBFM 1) and flies the run; not brush's CL 3 (FBFM 5, a fuel patch under the aim): no run."""
    patch = {
        "x_min_m": 0.0,
        "x_max_m": 6000.0,
        "y_min_m": 2500.0,
        "y_max_m": 3500.0,
        "fuel_model": fuel_model,
    }
    sc, a = _tanker(1, **{"fires.raster.fuel_patches": [patch]})
    g = a.guide
    by_hand = (757.0 / 49.8) / (math.sqrt(2.0 * math.pi) * 6.0)
    assert GRASS_LPM2 < by_hand < 3.0 * L_PER_M2_PER_CL
    assert _peak(sc, 8.0, g.v_slow_mps) == pytest.approx(by_hand, rel=0.01)
    aim = (3000.0, 3000.0)
    run = g._drop_run((aim[0] + 0.5 * g.drop_run_m, aim[1]), aim)
    assert (run is not None) is flies
    assert (g.run_skips == 0) is flies
    outside = (3000.0, 1000.0)  # grass outside the patch: the run is flown either way
    assert g._drop_run((outside[0] + 0.5 * g.drop_run_m, outside[1]), outside) is not None
