"""Suppression benchmark: burned area against the no-fleet baseline.

usage: python -m fire_bench.suppression [--quick] [--jobs N] [--out DIR] [--case SC:UAVS:SEED:TACTIC ...]
                                       [--duration S] [--drop-model disc|pattern]
       python -m fire_bench.suppression --from-runs JSONL [--from-runs JSONL ...] [--out DIR] [--update-docs]
       (or scripts/bench --only suppression)

Output goes to ``--out`` (default: a new ``runs/suppression-<time>/``); ``--update-docs`` also
puts the summary into ``docs/bench/results.json`` (its ``suppression`` section, plots beside it)
and renders ``docs/benchmarks.md`` again (``scripts/bench --render``).

Runs in-process (``fire_uav_agent.testing.harness``: the real World and the real Agents, no
DDS; deterministic for a scenario and seed), so every figure here comes from the harness, not
from real processes. Cases:

* tactics: head attack vs flank attack, 6 UAVs, on the pre-burnt raster scenarios
  ``grass_running`` and ``grass_brush_hill``, seeds 1-3, 900 s;
* fleet size: 0 (the fire alone: ``World(no_fleet=True)``), 3, 6 and 10 UAVs, head attack and
  flank attack, ``grass_running``, seed 1, 900 s;
* ``--quick``: ``grass_brush_hill``, seed 1, 300 s: no fleet, head and flank with 6 UAVs.

A mission ends before 900 s only when every fire is out and every UAV has landed, so its final
burned area is also its burned area at 900 s. Each finished case is appended at once to
``suppression_runs.jsonl`` in the output directory (a cut-short benchmark keeps what it has),
with every CRASH's context (all UAVs' objectives, positions and aim points at that step).

Measures are the world's own (:class:`fire_world_sim.measures.SuppressionMeasures`): burned
area [m^2] over time, hit rate, water on burning cells [kg], containment time [s] (no cell
ignited for 60 s). ``monitors_per_fire`` is set to 0 in these runs (every UAV suppresses;
the agents' front pictures keep their own PM Eq. 1 maps) -- the scenario's value would make
two UAVs per fire monitor instead, and costs about 4x the run time.
"""

from __future__ import annotations

import dataclasses
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from fire_mission.cli import OneLineParser

SCENARIOS = ("grass_running", "grass_brush_hill")
_LOG: Path | None = None  # suppression_runs.jsonl of the current benchmark
TACTICS = ("head", "flank")


def run_case(
    scenario: str,
    uavs: int,
    seed: int,
    tactic: str,
    duration_s: float,
    monitors: int = 0,
    drop_model: str = "disc",
) -> dict:
    """One mission in the harness (``uavs`` 0: the fire alone); the world's measures + area history.
    ``drop_model``: the scenario's ``fires.drop_model`` (disc, or a ground pattern: docs/suppression.md)."""
    from fire_uav_agent.testing.harness import Harness, scenario_path
    from fire_uav_common.constants import EventType
    from fire_uav_common.scenario import load_scenario
    from fire_world_sim.world import World

    sc = load_scenario(scenario_path(scenario))
    sc = dataclasses.replace(
        sc,
        mission=dataclasses.replace(sc.mission, tactic=tactic, monitors_per_fire=monitors),
        timing=dataclasses.replace(sc.timing, max_duration_s=duration_s),
        fires=dataclasses.replace(sc.fires, drop_model=drop_model),
    )
    wall0 = time.monotonic()
    crash_log: list[dict] = []
    if uavs == 0:
        world = World(sc, seed, no_fleet=True)
        while not world.complete:
            world.step({})
        crashes = 0
    else:
        h = Harness(sc, seed=seed, uav_count=uavs)
        seen = 0
        while not h.world.complete:
            h.step()
            for e in h.events[seen:]:
                if (
                    e.type == EventType.CRASH
                ):  # the phase it happened in: where over a raster fire vehicles collide
                    crash_log.append(_crash_context(h, e))
            seen = len(h.events)
        world = h.world
        crashes = sum(1 for e in h.events if e.type == EventType.CRASH)
    m = world.measures
    return {
        "scenario": scenario,
        "uavs": uavs,
        "seed": seed,
        "tactic": tactic if uavs else "none",
        "duration_s": duration_s,
        "drop_model": drop_model,
        **m.as_dict(),
        "crashes": crashes,
        "crash_log": crash_log,
        "mission_time_s": round(world.step_index * sc.timing.control_period_s, 1),
        "complete_reason": world.complete_reason,
        "area_t_s": m.area_t_s,
        "area_m2": m.area_m2,
        "wall_s": round(time.monotonic() - wall0, 1),
    }


def _crash_context(h, e) -> dict:
    """A CRASH event with every UAV's objective, true position and height [m] at that step."""
    from fire_uav_common.constants import Objective

    return {
        "t_s": round(e.stamp_ns * 1e-9, 1),
        "uav": e.uav_id,
        "detail": e.detail,
        "fleet": [
            {
                "uav": v.uav_id,
                "objective": Objective(int(h.agents[v.uav_id].mission.objective)).name,
                "xyz_m": [round(v.x_m, 1), round(v.y_m, 1), round(v.z_m, 1)],
                "aim_m": None
                if h.agents[v.uav_id]._front_aim is None
                else [round(c, 1) for c in h.agents[v.uav_id]._front_aim],
            }
            for v in h.world.vehicles
        ],
    }


def cases(quick: bool) -> list[tuple]:
    """Full: the module doc's cases. Quick: grass_brush_hill, seed 1, 300 s: no fleet, head, flank."""
    if quick:
        sc = "grass_brush_hill"
        return [(sc, 6, 1, "head", 300.0), (sc, 6, 1, "flank", 300.0), (sc, 0, 1, "head", 300.0)]
    dur = 900.0
    seeds = [1, 2, 3]
    out: list[tuple] = []
    for seed in seeds:  # seed by seed, so that a cut-short run still has whole comparisons
        out += [(sc, 6, seed, t, dur) for sc in reversed(SCENARIOS) for t in TACTICS]  # the quicker first
        if seed == seeds[0]:
            out += [(sc, 0, 1, "head", dur) for sc in SCENARIOS]  # the fire alone has no randomness
            out += [("grass_running", 3, seed, t, dur) for t in TACTICS]
    return out + [("grass_running", 10, seeds[0], t, dur) for t in TACTICS]


def _star(args: tuple) -> dict:
    r = run_case(*args)
    if _LOG is not None:  # every finished case at once: a cut-short benchmark keeps what it has
        with _LOG.open("a") as f:
            f.write(json.dumps(r) + "\n")
    print(
        f"[suppression] {r['scenario']} uavs={r['uavs']} seed={r['seed']} {r['tactic']} "
        f"{r.get('drop_model', 'disc')}: "
        f"burned {r['burned_area_m2'] / 1e4:.2f} ha, hit rate {_num(r['hit_rate'], 2)}, "
        f"contained at {_num(r['contained_at_s'], 1)} s, "
        f"crashes {r['crashes']} ({r['wall_s']} s wall)",
        file=sys.stderr,
        flush=True,
    )
    return r


def _num(v: float | None, digits: int) -> str:
    """A figure for a printed line: rounded (``137.10000000000002`` -> ``137.1``), ``-`` for None."""
    return "-" if v is None else f"{v:.{digits}f}"


def summarise(results: list[dict]) -> dict:
    """Per scenario: baseline, per tactic the seeds' burned area / ratio / hit rate / containment."""
    out: dict = {"scenarios": {}, "fleet_size": []}
    for sc in SCENARIOS:
        base = next((r for r in results if r["scenario"] == sc and r["uavs"] == 0), None)
        entry: dict = {"baseline_burned_area_m2": base["burned_area_m2"] if base else None, "tactics": {}}
        for t in TACTICS:
            rows = [r for r in results if r["scenario"] == sc and r["uavs"] == 6 and r["tactic"] == t]
            entry["tactics"][t] = [
                {
                    "seed": r["seed"],
                    "burned_area_m2": r["burned_area_m2"],
                    "ratio_to_baseline": r["burned_area_m2"] / base["burned_area_m2"] if base else None,
                    "hit_rate": r["hit_rate"],
                    "drops": r["drops"],
                    "water_on_burning_kg": r["water_on_burning_kg"],
                    "contained_at_s": r["contained_at_s"],
                    "crashes": r["crashes"],
                }
                for r in sorted(rows, key=lambda r: r["seed"])
            ]
        out["scenarios"][sc] = entry
    for r in _fleet_size_runs(results):
        out["fleet_size"].append(
            {
                "uavs": r["uavs"],
                "tactic": r["tactic"],
                "burned_area_m2": r["burned_area_m2"],
                "contained_at_s": r["contained_at_s"],
            }
        )
    return out


def _fleet_size_runs(results: list[dict]) -> list[dict]:
    """grass_running, seed 1: the no-fleet run and every fleet size, by (UAVs, tactic)."""
    runs = [r for r in results if r["scenario"] == "grass_running" and r["seed"] == 1]
    return sorted(runs, key=lambda r: (r["uavs"], r["tactic"]))


def plot(results: list[dict], out: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = []
    fig, axes = plt.subplots(1, len(SCENARIOS), figsize=(12, 4.2))
    for ax, sc in zip(axes, SCENARIOS, strict=True):
        for r in results:
            if r["scenario"] != sc or r["uavs"] not in (0, 6):
                continue
            style = {"none": ("k", "-"), "head": ("tab:red", "--"), "flank": ("tab:blue", ":")}[r["tactic"]]
            label = "no fleet" if r["uavs"] == 0 else f"{r['tactic']} s{r['seed']}"
            ax.plot(r["area_t_s"], [a / 1e4 for a in r["area_m2"]], color=style[0], ls=style[1], label=label)
        ax.set_title(f"{sc}: burned area, 6 UAVs vs no fleet")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("burned area [ha]")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "suppression_area.png", dpi=110)
    plt.close(fig)
    names.append("suppression_area.png")
    fs = _fleet_size_runs(results)
    if fs:
        fig, ax = plt.subplots(figsize=(5, 4))
        base = [r for r in fs if r["uavs"] == 0]
        for tactic, style in (("head", "o-"), ("flank", "s--")):
            line = base + [r for r in fs if r["tactic"] == tactic]
            if len(line) > len(base):
                ax.plot(
                    [r["uavs"] for r in line], [r["burned_area_m2"] / 1e4 for r in line], style, label=tactic
                )
        ax.set_xlabel("UAVs")
        ax.set_ylabel(f"burned area at {fs[0]['duration_s']:g} s [ha]")
        ax.set_title("grass_running, seed 1")
        ax.set_ylim(bottom=0)
        ax.legend()
        fig.tight_layout()
        fig.savefig(out / "suppression_fleet_size.png", dpi=110)
        plt.close(fig)
        names.append("suppression_fleet_size.png")
    return names


def _init_log(path: Path | None) -> None:
    global _LOG
    _LOG = path


def parse_case(text: str, duration_s: float = 900.0, drop_model: str = "disc") -> tuple:
    """``SCENARIO:UAVS:SEED:TACTIC`` (``--case``) -> a case of :func:`cases`."""
    parts = text.split(":")
    if len(parts) != 4:
        raise SystemExit(f"--case {text!r}: expected SCENARIO:UAVS:SEED:TACTIC, e.g. grass_running:6:1:head")
    sc, uavs, seed, tactic = parts
    if sc not in SCENARIOS:
        raise SystemExit(f"--case {text!r}: scenario must be one of {list(SCENARIOS)}")
    if tactic not in TACTICS:
        raise SystemExit(f"--case {text!r}: tactic must be one of {list(TACTICS)}")
    try:
        n, k = int(uavs), int(seed)
    except ValueError:
        raise SystemExit(f"--case {text!r}: UAVS and SEED must be integers") from None
    if n < 0:
        raise SystemExit(f"--case {text!r}: UAVS must be >= 0")
    return (
        (sc, n, k, tactic, duration_s)
        if drop_model == "disc"
        else (sc, n, k, tactic, duration_s, 0, drop_model)
    )


def bench_suppression(
    quick: bool, jobs: int = 2, out: Path | None = None, todo: list[tuple] | None = None
) -> dict:
    todo = cases(quick) if todo is None else todo
    log = None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        log = out / "suppression_runs.jsonl"
        log.write_text("")
    with ProcessPoolExecutor(max_workers=max(1, jobs), initializer=_init_log, initargs=(log,)) as ex:
        results = list(ex.map(_star, todo))
    summary = summarise(results)
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        (out / "suppression_runs.json").write_text(json.dumps(results) + "\n")
        summary["plots"] = plot(results, out)
    return summary


def read_runs(path: Path) -> list[dict]:
    """The cases of a ``suppression_runs.jsonl`` (one JSON object a line), in the order finished."""
    runs = []
    for n, line in enumerate(path.read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            runs.append(json.loads(line))
        except json.JSONDecodeError as e:
            raise SystemExit(f"{path}:{n}: not a JSON object: {e}") from None
    return runs


def update_docs(summary: dict, out: Path) -> Path:
    """Put ``summary`` into the committed results (``docs/bench/results.json``, section
    ``suppression``), copy its plots from ``out`` beside them and render the page again."""
    import shutil

    from fire_bench import markdown

    docs_bench = markdown.DOCS / "bench"
    results_path = docs_bench / "results.json"
    results = json.loads(results_path.read_text()) if results_path.is_file() else {}
    results["suppression"] = dict(summary, quick=summary.get("quick", False))
    for name in summary.get("plots", []):
        if (out / name).resolve() != (docs_bench / name).resolve():
            shutil.copyfile(out / name, docs_bench / name)
    results_path.write_text(json.dumps(results, indent=2, default=str) + "\n")
    return markdown.render_docs()


def main(argv: list[str] | None = None) -> int:
    p = OneLineParser(prog="python -m fire_bench.suppression", description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="grass_brush_hill, seed 1, 300 s (3 missions)")
    p.add_argument("--jobs", type=int, default=2, help="parallel missions (default 2)")
    p.add_argument(
        "--out", type=Path, default=None, help="results directory (default: a new runs/suppression-<time>/)"
    )
    p.add_argument(
        "--from-runs",
        type=Path,
        default=None,
        metavar="JSONL",
        action="append",
        help="run nothing: summarise and plot the finished cases of these suppression_runs.jsonl "
        "(repeatable: a benchmark run in parts) into --out",
    )
    p.add_argument(
        "--update-docs",
        action="store_true",
        help="also put the summary into docs/bench/results.json and render docs/benchmarks.md again",
    )
    p.add_argument(
        "--case",
        action="append",
        default=[],
        metavar="SCENARIO:UAVS:SEED:TACTIC",
        help="run only these cases, in this order (repeatable; 900 s each), e.g. grass_running:6:1:head",
    )
    p.add_argument(
        "--duration",
        type=float,
        default=900.0,
        metavar="S",
        help="mission time limit of the --case cases [s] (default 900)",
    )
    p.add_argument(
        "--drop-model",
        choices=("disc", "pattern"),
        default="disc",
        help="fires.drop_model of the --case cases (default disc, the scenarios' own)",
    )
    a = p.parse_args(argv)
    if a.out is None:
        from fire_bench.markdown import RUNS

        a.out = RUNS / f"suppression-{time.strftime('%Y%m%d-%H%M%S')}"
    try:
        if not a.duration > 0:
            raise SystemExit(f"--duration must be > 0, got {a.duration:g}")
        todo = [parse_case(c, a.duration, a.drop_model) for c in a.case] or None
    except SystemExit as e:
        p.error(str(e.code))
    if a.from_runs is not None:
        results = []
        for path in a.from_runs:
            if not path.is_file():
                p.error(f"--from-runs: no file {path}")
            results += read_runs(path)
        a.out.mkdir(parents=True, exist_ok=True)
        (a.out / "suppression_runs.json").write_text(json.dumps(results) + "\n")
        s = summarise(results)
        s["plots"] = plot(results, a.out)
        s["command"] = (
            "python -m fire_bench.suppression --jobs 2 --out DIR (= scripts/bench --only suppression)"
        )
        s["wall_s"] = round(sum(r["wall_s"] for r in results), 1)
    else:
        s = bench_suppression(a.quick, a.jobs, a.out, todo)
        s["quick"] = a.quick
    (a.out / "suppression.json").write_text(json.dumps(s, indent=2) + "\n")
    if a.update_docs:
        print(f"[suppression] page: {update_docs(s, a.out)}", file=sys.stderr)
    print(json.dumps(s, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
