"""The in-fleet coverage search: coordinators exchanging messages in-process (no ROS)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_uav_agent.agent_core import PlannerView
from fire_uav_agent.coverage import make_grid
from fire_uav_agent.search import SearchConfigError, balance_weights
from fire_uav_agent.search.coordinator import (
    Phase,
    SearchConfig,
    SearchCoordinator,
    SearchPlanner,
    agreed,
    default_cell_size_m,
    plan_is_partition,
)
from fire_uav_agent.search.fleet import FleetSim

AREA = (0.0, 1000.0, 0.0, 1000.0)


def _fleet(n: int, loss: float, seed: int = 1, **cfg) -> FleetSim:
    return FleetSim(
        n, AREA, seed=seed, config=SearchConfig(**cfg), loss_probability=loss, max_extra_delay_steps=1
    )


def _live(f: FleetSim) -> list[SearchCoordinator]:
    return [c for c in f.coordinators if c.uav_id not in f.crashed_at]


@pytest.mark.parametrize(("n", "loss", "seed"), [(3, 0.0, 1), (4, 0.0, 2), (3, 0.3, 3), (4, 0.3, 4)])
def test_fleet_agrees_on_one_plan_that_partitions_the_grid(n: int, loss: float, seed: int) -> None:
    f = _fleet(n, loss, seed)
    steps = f.run_until_planned(600)
    assert steps < 200, "planning took too long"
    cs = f.coordinators
    assert agreed(cs)
    best = min(min(c.known.values(), key=lambda m: (m.cost, m.candidate_id)).cost for c in cs)
    assert cs[0].plan.candidate_id in {m.candidate_id for c in cs for m in c.known.values() if m.cost == best}
    for c in cs:
        assert plan_is_partition(c.plan, c.grid)  # every free cell owned by exactly one uav
        np.testing.assert_array_equal(c.plan.labels, cs[0].plan.labels)
        assert c.plan.e_max < c.config.epsilon
    if loss == 0.0:
        assert all(c.plan.via_messages for c in cs)
    assert sum(c.own_evaluations for c in cs) == cs[0].config.budget


def test_weights_balanced_over_messages_equal_the_lockstep_loop() -> None:
    f = _fleet(4, 0.3, seed=5)
    f.run_until_planned(600)
    c = f.coordinators[0]
    ref = balance_weights(c.grid, c.plan.seeds_m, c.problem.balance)
    np.testing.assert_allclose(c.plan.weights_m2, ref.weights_m2)


@pytest.mark.parametrize("n", [3, 4])
def test_message_mst_equals_centralised_radius_without_loss(n: int) -> None:
    f = _fleet(n, 0.0, seed=6)
    f.run_until_planned(600)
    f.run(30)
    for c in f.coordinators:
        res = c.mst_results[0]
        assert res["complete"], res
        assert res["radius_m"] == pytest.approx(res["local_radius_m"], rel=1e-12)
        assert res["instants_done"] == c.config.n_time_samples
        assert c.mst_radius_m == pytest.approx(res["local_radius_m"])


def test_message_mst_with_loss_finishes_or_times_out() -> None:
    f = _fleet(4, 0.3, seed=7)
    f.run_until_planned(600)
    f.run(f.coordinators[0].config.mst_timeout_steps + 5)
    for c in f.coordinators:
        assert c.mst_results, "MST session never ended"
        res = c.mst_results[0]
        if res["complete"]:
            assert res["radius_m"] == pytest.approx(res["local_radius_m"], rel=1e-12)


def test_heavy_loss_does_not_stall() -> None:
    f = _fleet(3, 0.8, seed=8, balance_timeout_steps=60, mst_timeout_steps=30)
    steps = f.run_until_planned(400)
    assert steps < 400
    for c in f.coordinators:
        assert c.phase == Phase.FLY
        assert plan_is_partition(c.plan, c.grid)
    f.run(100)
    assert all(c.mst_results for c in f.coordinators)
    assert agreed(f.coordinators)  # late rebroadcasts removed any disagreement


@pytest.mark.parametrize("loss", [0.0, 0.3])
def test_crashed_agents_region_is_repartitioned(loss: float) -> None:
    f = _fleet(4, loss, seed=9)
    f.run_until_planned(600)
    f.run(50)
    victim = 2
    f.crash(victim)
    f.run(f.detect_steps + 1)
    f.run_until_planned(600)
    live = _live(f)
    assert agreed(live)
    for c in live:
        assert c.plan.alive == (0, 1, 3)
        assert plan_is_partition(c.plan, c.grid)
        assert victim not in set(np.unique(c.plan.labels))
        assert len(c.plans) >= 2
        assert c.planner.plans_set >= 2


def test_crash_during_optimisation() -> None:
    f = _fleet(3, 0.3, seed=10)
    f.run(3)
    f.crash(1)
    f.run_until_planned(600)
    live = _live(f)
    assert agreed(live)
    assert live[0].plan.alive == (0, 2)
    assert all(plan_is_partition(c.plan, c.grid) for c in live)


def test_disagreement_resolves_to_the_cheapest_candidate() -> None:
    f = _fleet(3, 0.0, seed=11)
    f.run_until_planned(600)
    c0 = f.coordinators[0]
    worst = max(c0.known.values(), key=lambda m: m.cost)
    best_id = c0.plan.candidate_id
    c0._adopt(worst, "test: forced worse candidate")  # as if every better COST had been lost
    f.run(3)
    assert c0.adopted.candidate_id == worst.candidate_id or c0.adopted.candidate_id == best_id
    f.run(2 * c0.config.rebroadcast_every_steps)
    f.run_until_planned(600)
    assert agreed(f.coordinators)
    assert c0.plan.candidate_id == best_id


def test_random_mode_spends_the_same_budget() -> None:
    f = _fleet(3, 0.0, seed=12, mode="random", budget=12)
    f.run_until_planned(600)
    assert sum(c.own_evaluations for c in f.coordinators) == 12
    assert agreed(f.coordinators)


def test_planner_waypoints_follow_the_path() -> None:
    cfg = SearchConfig()
    c = SearchCoordinator(0, 1, AREA, seed=0, config=cfg)
    grid = make_grid(*AREA, 20.0)

    def view(t: float, pos: np.ndarray) -> PlannerView:
        return PlannerView(
            t, 0, np.array([pos[0], pos[1], 30.0, 0.0]), grid, np.ones(len(grid.points), bool), {}, ()
        )

    pos = np.array([50.0, 200.0])
    assert c.planner.plan(view(0.0, pos)) is None  # no plan yet
    c.on_step(0.1, 0, [0])
    for k in range(1, 60):
        c.on_step(0.1 * (k + 1), k, [0])
    assert c.plan is not None and c.phase == Phase.FLY
    path = c.plan.paths[0]
    dense = path.positions_at(np.linspace(0.0, path.length_m, 4000, endpoint=False))
    # a point mass flying at the search speed straight at each waypoint (10 Hz)
    dt, speed = 0.1, cfg.speed_mps
    dist_on_path = []
    for k in range(int(1.3 * path.length_m / speed / dt)):
        tgt = c.planner.plan(view(k * dt, pos))
        wp = np.array(tgt.waypoint_xy)
        assert tgt.speed_cap_mps == cfg.speed_mps
        step = wp - pos
        pos = pos + step / max(np.linalg.norm(step), 1e-9) * min(speed * dt, np.linalg.norm(step))
        if c.planner.joined:
            dist_on_path.append(np.min(np.linalg.norm(dense - pos, axis=1)))
    assert dist_on_path, "never joined the path"
    assert max(dist_on_path) < cfg.capture_m
    assert c.planner.laps > 0.9  # flew about one lap: progress follows the vehicle, never stops
    # every waypoint lies on the path
    wp = np.array(c.planner.plan(view(1e3, pos)).waypoint_xy)
    assert np.min(np.linalg.norm(dense - wp, axis=1)) < 1.0


def test_default_cell_size_fits_the_area_and_the_sensor() -> None:
    d = default_cell_size_m(AREA, 70.0)
    assert d / 2 <= 1.4 * 70.0
    assert math.isclose(1000.0 / d, round(1000.0 / d))


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"mode": "grid"}, "mode must be"),
        ({"budget": 0}, "budget"),
        ({"lambda_m_per_j": -1.0}, "lambda_m_per_j"),
        ({"cell_size_m": 0.0}, "cell_size_m"),
        ({"n_time_samples": 0}, "n_time_samples"),
        ({"lookahead_m": 0.0}, "lookahead_m"),
    ],
)
def test_config_errors(kw: dict, match: str) -> None:
    with pytest.raises(SearchConfigError, match=match):
        SearchConfig(**kw)


def test_coordinator_rejects_bad_ids() -> None:
    with pytest.raises(SearchConfigError, match="uav_id"):
        SearchCoordinator(3, 3, AREA, seed=0)


def test_planner_without_path_returns_none() -> None:
    p = SearchPlanner(SearchConfig())
    grid = make_grid(*AREA, 50.0)
    v = PlannerView(0.0, 0, np.zeros(4), grid, np.ones(len(grid.points), bool), {}, ())
    assert p.plan(v) is None


@pytest.mark.slow
def test_closed_loop_agents_fly_the_plan_and_find_the_fire() -> None:
    """The harness (real World and Agents, scenario search_area) whose agents' SEARCH planner is the coordinator's."""
    from fire_uav_agent.mission import Objective
    from fire_uav_agent.testing.harness import Harness, scenario_path
    from fire_uav_common.constants import EventType

    h = Harness.from_file(scenario_path("search_area"))
    ar = h.scenario.area
    assert (ar.x_min_m, ar.x_max_m, ar.y_min_m, ar.y_max_m) == AREA and h.scenario.mission.search_first
    fleet = FleetSim(3, AREA, seed=0, loss_probability=0.05)
    for a, c in zip(h.agents, fleet.coordinators, strict=True):
        a.planners[int(Objective.SEARCH)] = c.planner
    detected = None
    for _ in range(1500):
        h.step()
        fleet.step()
        for o in h.outputs:
            if o is not None and any(ev.type == EventType.FIRE_DETECTED for ev in o.events):
                detected = (o.step, o.state.uav_id)
        if detected:
            break
    assert detected is not None, "the fire was not found within 150 s"
    assert agreed(fleet.coordinators)
    assert all(c.planner.joined or c.planner.laps > 0 for c in fleet.coordinators)
    owner = fleet.coordinators[0].plan.labels
    g = fleet.coordinators[0].grid
    iy, ix = int((720.0 - g.y_min_m) // g.cell_size_m), int((760.0 - g.x_min_m) // g.cell_size_m)
    assert owner[iy, ix] >= 0
