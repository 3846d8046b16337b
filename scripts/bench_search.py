#!/usr/bin/env python3
"""Benchmark of the coverage search (CP): distributed Thompson-sampling BO vs random sampling.

For each seed: one shared candidate pool; asynchronous BO (lossless, and with 30 % message loss)
and a variant that also samples around each agent's incumbent (not in the paper), and the
random-sampling baseline with the same evaluation budget (the CP Fig. 8 comparison);
then, for the best BO candidate, the coverage fraction and the time to first detection of fires
at uniformly random places. Prints only; no assertions.

    .venv/bin/python scripts/bench_search.py            # 10 seeds, budget 40 (~2-5 min)
    .venv/bin/python scripts/bench_search.py --quick    # 3 seeds, budget 20 (< 1 min)
    .venv/bin/python scripts/bench_search.py --fleet    # the in-agent pipeline only (SearchCoordinator)

``--fleet``: N :class:`SearchCoordinator` s exchanging messages in-process (0 % and 30 % loss, BO and
random mode, 1000 x 1000 m): control steps until every agent flies the agreed plan, cost of that plan,
and the time to first detection of random fires = planning time + first pass of a path within
sensor range (agents assumed at their path start when the plan is ready).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from fire_uav_agent.search import (
    BoConfig,
    CoverageGrid,
    SearchProblem,
    coverage_fraction,
    evaluate_candidate,
    first_detection_time_s,
    make_pool,
    run_async_bo,
    run_random_search,
)
from threadpoolctl import threadpool_limits


def _stats(x: np.ndarray) -> str:
    return f"mean {np.mean(x):8.1f}  std {np.std(x):6.1f}  min {np.min(x):8.1f}  max {np.max(x):8.1f}"


def fleet_bench(args: argparse.Namespace) -> int:
    """Time to plan and to first detection of the in-agent pipeline (SearchCoordinator over FleetSim)."""
    from fire_uav_agent.search.coordinator import SearchConfig, agreed
    from fire_uav_agent.search.fleet import FleetSim

    area = (0.0, 1000.0, 0.0, 1000.0)
    n_seeds = args.seeds or 5
    budget = args.budget or 18
    n = min(args.agents, 4)
    print(f"in-agent pipeline: 1000 x 1000 m, {n} agents, budget {budget}, {n_seeds} seeds, T = 0.1 s")
    print(
        f"{'mode':>6} {'loss':>5} {'steps':>6} {'agreed':>6} {'cost':>8} {'r_max':>7} {'det mean':>9} {'det p90':>8} {'det max':>8} {'missed':>6}"
    )
    with threadpool_limits(1):
        for mode in ("bo", "random"):
            for loss in (0.0, 0.3):
                rows = []
                for seed in range(n_seeds):
                    f = FleetSim(n, area, seed=seed, config=SearchConfig(mode=mode, budget=budget),
                                 loss_probability=loss, max_extra_delay_steps=1)  # fmt: skip
                    steps = f.run_until_planned(2000)
                    c = f.coordinators[0]
                    plan = c.plan
                    cost = c.adopted.cost
                    paths = tuple(plan.paths[u] for u in plan.alive)
                    offs = np.array([plan.start_offsets[u] for u in plan.alive])
                    fires = np.random.default_rng([seed, 4]).uniform(0.0, 1000.0, size=(args.fires, 2))
                    det = first_detection_time_s(c.problem, paths, offs, fires) + steps * 0.1
                    seen = det[np.isfinite(det)]  # a fire in an outer corner can stay > range from the arcs
                    rows.append((steps, agreed(f.coordinators), cost, c.adopted.radio_radius_m,
                                 np.mean(seen), np.percentile(seen, 90), np.max(seen), len(det) - len(seen)))  # fmt: skip
                r = np.array(rows, dtype=float)
                print(f"{mode:>6} {loss:5.1f} {r[:, 0].mean():6.1f} {int(r[:, 1].sum()):>3}/{n_seeds:<2} "
                      f"{r[:, 2].mean():8.1f} {r[:, 3].mean():7.1f} {r[:, 4].mean():9.1f} {r[:, 5].mean():8.1f} "
                      f"{r[:, 6].max():8.1f} {int(r[:, 7].sum()):6d}", flush=True)  # fmt: skip
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="3 seeds, budget 20, no lossy run")
    ap.add_argument("--seeds", type=int, default=None, help="number of seeds (default 10, quick 3)")
    ap.add_argument("--budget", type=int, default=None, help="evaluations per run (default 40, quick 20)")
    ap.add_argument("--agents", type=int, default=4)
    ap.add_argument("--fires", type=int, default=200, help="random fire positions per seed")
    ap.add_argument("--fleet", action="store_true", help="only the in-agent coordinator pipeline")
    args = ap.parse_args()
    if args.fleet:
        return fleet_bench(args)
    n_seeds = args.seeds or (3 if args.quick else 10)
    budget = args.budget or (20 if args.quick else 40)

    grid = CoverageGrid.from_area(0.0, 1200.0, 0.0, 1200.0, cell_size_m=120.0)
    problem = SearchProblem(grid=grid, n_agents=args.agents)
    cfg = BoConfig(budget=budget, pool_size=1024)
    cfg_lossy = BoConfig(budget=budget, pool_size=1024, loss_probability=0.3)
    # not in the paper: Thompson points also drawn around the agent's incumbent (local_points)
    cfg_local = BoConfig(budget=budget, pool_size=1024, local_points=256, local_sigma=0.03)
    print(
        f"area 1200 x 1200 m, cell {grid.cell_size_m:.0f} m (swath {grid.cell_size_m / 2:.0f} m), "
        f"{args.agents} agents, v {problem.energy.speed_mps:.0f} m/s, turn radius {problem.arc_radius_m:.0f} m, "
        f"sensor {problem.sensor_range_m:.0f} m, lambda {problem.lambda_m_per_j:g} m/J"
    )
    print(f"{n_seeds} seeds, budget {budget} evaluations per run, pool {cfg.pool_size}")
    print(
        f"{'seed':>4} {'BO best':>9} {'BO lossy':>9} {'BO+local':>9} {'random':>9} {'BO 1st':>9} "
        f"{'r_max':>7} {'E[kJ]':>7} {'cover':>6} {'det mean':>9} {'det p90':>8} {'det max':>8} {'s':>5}"
    )
    rows = []
    t_all = time.perf_counter()
    with threadpool_limits(1):
        for seed in range(n_seeds):
            t0 = time.perf_counter()
            pool = make_pool(problem, cfg.pool_size, np.random.default_rng([seed, 0]))
            bo = run_async_bo(problem, np.random.default_rng([seed, 1]), cfg, pool=pool)
            loc = run_async_bo(problem, np.random.default_rng([seed, 1]), cfg_local, pool=pool)
            rs = run_random_search(problem, np.random.default_rng([seed, 2]), cfg, pool=pool)
            lossy = (
                None
                if args.quick
                else run_async_bo(problem, np.random.default_rng([seed, 3]), cfg_lossy, pool=pool)
            )
            best = evaluate_candidate(problem, bo.best_candidate)
            cover = coverage_fraction(problem, best.paths)
            fires = np.random.default_rng([seed, 4]).uniform(0.0, 1200.0, size=(args.fires, 2))
            det = first_detection_time_s(problem, best.paths, best.candidate.start_offsets, fires)
            row = dict(
                bo=bo.best_so_far[-1],
                bo_half=bo.best_so_far[budget // 2 - 1],
                loc=loc.best_so_far[-1],
                rs=rs.best_so_far[-1],
                rs_half=rs.best_so_far[budget // 2 - 1],
                lossy=lossy.best_so_far[-1] if lossy is not None else np.nan,
                lossy_obs=lossy.observations_per_agent.mean() if lossy is not None else np.nan,
                first=bo.costs[0],
                r=best.radius_m,
                e=best.energy_j,
                cover=cover,
                det_mean=float(np.mean(det)),
                det_p90=float(np.percentile(det, 90)),
                det_max=float(np.max(det)),
            )
            rows.append(row)
            print(
                f"{seed:4d} {row['bo']:9.1f} {row['lossy']:9.1f} {row['loc']:9.1f} {row['rs']:9.1f} {row['first']:9.1f} "
                f"{row['r']:7.1f} {row['e'] / 1e3:7.1f} {cover:6.3f} {row['det_mean']:9.1f} "
                f"{row['det_p90']:8.1f} {row['det_max']:8.1f} {time.perf_counter() - t0:5.1f}",
                flush=True,
            )
    col = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    print("\nbest cost after the full budget [m]")
    print(f"  BO (async TS)      {_stats(col['bo'])}")
    if not args.quick:
        print(
            f"  BO, 30 % loss      {_stats(col['lossy'])}   (mean data per agent {np.mean(col['lossy_obs']):.1f})"
        )
    print(f"  BO + local points  {_stats(col['loc'])}   (not in the paper)")
    print(f"  random sampling    {_stats(col['rs'])}")
    print(f"  BO better than random on {int(np.sum(col['bo'] < col['rs']))} of {n_seeds} seeds")
    print(f"  BO + local better than random on {int(np.sum(col['loc'] < col['rs']))} of {n_seeds} seeds")
    print(
        f"best cost after half the budget: BO {np.mean(col['bo_half']):.1f}, random {np.mean(col['rs_half']):.1f}"
    )
    print(f"coverage fraction of the best BO plan: {_stats(col['cover'])}")
    print(
        f"first detection of a random fire [s]: mean {np.mean(col['det_mean']):.1f}, "
        f"p90 {np.mean(col['det_p90']):.1f}, max {np.max(col['det_max']):.1f}"
    )
    print(f"total {time.perf_counter() - t_all:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
