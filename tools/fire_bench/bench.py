"""scripts/bench: benchmarks that reproduce the papers' results and measure scale.

usage: scripts/bench [--quick] [--only NAME ...] [--out DIR | --update-docs] [--list]
                     [--scheduler tcp://HOST:PORT | --jobs N]
       scripts/bench --render

Each sub-benchmark prints its figures and returns a JSON-able dict; everything lands in
``<out>/results.json`` (default: a new run folder, ``runs/bench-<time>/``), plots and a page
(``benchmarks.md``) beside it. The committed results change only with ``--update-docs``: then
``docs/bench/results.json`` takes the new sections and ``docs/benchmarks.md`` is rendered again.
``--render`` runs nothing: it rewrites ``docs/benchmarks.md`` from ``docs/bench/results.json``
and the hand-written notes in ``docs/bench/notes/`` (``fire_bench.markdown``). Figures are
measured, never asserted: machines are shared and noisy.

The sweep-shaped sub-benchmarks (independent missions + a reducer, :class:`fire_bench.sweep.Sweep`)
run their missions on the executor of the command line: here one after the other (default),
``--jobs N`` at a time here, or on the workers of a Dask scheduler (``--scheduler
tcp://HOST:PORT``; docs/deployment.md). The results are the same whichever ran them.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shlex
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import yaml
from fire_mission.cli import OneLineParser

from fire_bench import markdown as page
from fire_bench.sweep import (
    DaskExecutor,
    Executor,
    MissionSpec,
    Sweep,
    SweepError,
    SweepResults,
    make_executor,
    run_spec,
    run_sweep,
)

ROOT = Path(__file__).resolve().parents[2]  # the checkout: tools/<package>/<module>.py
SCEN_DIR = ROOT / "ros2_ws/src/fire_world_sim/scenarios"

# FF Table I: fleet size -> (mean drop interval [steps of the paper's sim], drops)
FF_TABLE_I = {
    3: (235, 9),
    4: (163, 12),
    5: (143, 15),
    6: (129, 18),
    7: (139, 17),
    8: (135, 17),
    9: (138, 17),
    10: (132, 17),
    11: (122, 19),
    12: (110, 21),
    13: (96, 24),
    14: (95, 24),
}


def log(msg: str) -> None:
    print(f"[bench] {msg}", file=sys.stderr, flush=True)


def machine() -> dict:
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem_gib = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    commit = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False
    ).stdout.strip()
    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "mem_gib": round(mem_gib, 1),
        "python": platform.python_version(),
        "os": platform.platform(),
        "commit": commit,
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
    }


def machine_probe(repeats: int = 5) -> dict:
    """This (shared) machine's single-thread Python speed just before a scale row.

    ``probe_ms``: the median wall time of a fixed pure-Python loop (integer arithmetic, like the
    agents' bookkeeping). Over one afternoon it stayed at 21.4-23.2 ms while the 20-UAV
    fleet's rate moved between 8.7 and 11.5 steps/s: the variation is not the speed of
    one core but the 22-process setting (context switches, caches, the other vCPU), which only
    the messaging skeleton run beside each row measures. So read the ratio to the skeleton, not a
    rate alone, across days; the probe rules out the simplest explanation. A figure, not a
    correction: no row is rescaled."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        acc = 0
        for i in range(300_000):
            acc = (acc * 31 + i) & 0xFFFFFFFF
        times.append(time.perf_counter() - t0)
    times.sort()
    return {"probe_ms": round(1000 * times[len(times) // 2], 2)}


# --- running missions -----------------------------------------------------------------------
def mission(scenario: str | Path, *args: str, timeout_s: float = 1800) -> dict:
    """One run_mission here (no recording, no report, a private ROS domain); its summary.json."""
    spec = MissionSpec("local", str(scenario), mode="processes", args=tuple(args), timeout_s=timeout_s)
    return run_spec(spec)[0]


def derived_scenario(base: str, edit: Callable[[dict], None], name: str) -> str:
    """The YAML text of ``base`` edited by ``edit`` and renamed ``name`` (it travels in a spec)."""
    data = yaml.safe_load((SCEN_DIR / f"{base}.yaml").read_text())
    edit(data)
    data["name"] = name
    return yaml.safe_dump(data, sort_keys=False)


def _mean(xs: list[float]) -> float | None:
    xs = [x for x in xs if x is not None]
    return sum(xs) / len(xs) if xs else None


# --- sub-benchmarks ---------------------------------------------------------------------------
# A sweep-shaped sub-benchmark returns fire_bench.sweep.Sweep(specs, reduce): independent
# missions, run by the executor chosen on the command line (local, or --scheduler: Dask), and a
# reducer that gets [(spec, result)] in sorted-spec order. Other sub-benchmarks return their
# figures directly and always run here (they measure this machine).
def bench_table1(quick: bool) -> Sweep:
    """FF Table I: mean interval between consecutive drops and number of drops vs fleet size."""
    sizes = [3, 5, 8] if quick else list(range(3, 15))
    seeds = [1] if quick else [1, 2, 3]
    specs = [
        MissionSpec("table1", "ff_two_fires", uavs=n, seed=s, mode="processes") for n in sizes for s in seeds
    ]

    def reduce(pairs: list[tuple[MissionSpec, dict]]) -> dict:
        g = SweepResults(pairs)
        rows = []
        for n in sizes:
            runs = g.where(uavs=n)
            intervals = [r.get("mean_inter_drop_interval_s") for r in runs]
            rows.append(
                {
                    "uavs": n,
                    "seeds": seeds,
                    "mean_interval_s": _mean(intervals),
                    "drops": _mean([r.get("drops_total") for r in runs]),
                    "mission_time_s": _mean([r.get("mission_time_s") for r in runs]),
                    "completed": sum(r.get("outcome") == "complete" for r in runs),
                    "paper_interval": FF_TABLE_I.get(n, (None, None))[0],
                    "paper_drops": FF_TABLE_I.get(n, (None,) * 2)[1],
                }
            )
        base = next((r for r in rows if r["mean_interval_s"]), None)
        for r in rows:
            if base and r["mean_interval_s"]:
                r["scaling_efficiency"] = (
                    base["mean_interval_s"] * base["uavs"] / (r["mean_interval_s"] * r["uavs"])
                )
        return {"rows": rows}

    return Sweep(specs, reduce)


def _fig15_scenario(sigma: float, known: bool) -> str:
    """ff_two_fires with fire 1 at sigma 50 m and fire 2 at ``sigma`` m (FF Fig. 15)."""

    def edit(data: dict) -> None:
        data["fires"]["analytic"][0]["sigma_m"] = 50.0
        data["fires"]["analytic"][1]["sigma_m"] = float(sigma)
        if known:
            data.setdefault("mission", {})["prior_fires"] = "known"

    return derived_scenario("ff_two_fires", edit, f"ff_{'k' if known else 'f2'}_{sigma}")


def bench_fire_share(quick: bool) -> Sweep:
    """FF Figs. 14-15: share of drops per fire vs its share of area; drops vs second fire size."""
    sizes = [25, 50] if quick else [15, 20, 25, 30, 40, 50]
    specs = [
        MissionSpec(
            "fire_share",
            f"ff_f2_{sigma}",
            uavs=5,
            seed=1,
            mode="processes",
            label=f"sigma2={sigma}",
            scenario_yaml=_fig15_scenario(sigma, known=False),
        )
        for sigma in sizes
    ]

    def reduce(pairs: list[tuple[MissionSpec, dict]]) -> dict:
        g = SweepResults(pairs)
        out: dict = {}
        rows = []
        for sigma in sizes:
            r = g.where(label=f"sigma2={sigma}")[0]
            per = r.get("drops_per_fire", {})
            rows.append(
                {
                    "sigma2_m": sigma,
                    "drops_fire0": per.get("0", 0),
                    "drops_fire1": per.get("1", 0),
                    "missed": per.get("missed", 0),
                    "outcome": r.get("outcome"),
                }
            )
        out["rows"] = rows
        r25 = next((r for r in rows if r["sigma2_m"] == 25), None)
        if r25 and r25["drops_fire0"] + r25["drops_fire1"]:
            tot = r25["drops_fire0"] + r25["drops_fire1"]
            out["share_fire0_at_25m"] = r25["drops_fire0"] / tot
            out["paper_share_fire0"] = 0.726
        return out

    return Sweep(specs, reduce)


def bench_ff_known(quick: bool) -> Sweep:
    """FF Table I, Fig. 14 and Fig. 15 in the known-fires mode (mission.prior_fires: known), in process.

    The real World and Agents on the lockstep harness (``fire_mission.inprocess``; the process
    fleet gives the same numbers per seed, slower), 3-14 UAVs x 3 seeds (full) or 3, 5, 8 x 1
    seed (quick); Fig. 15 with 5 UAVs, fire 1 sigma 50 m, fire 2 sigma 15-50 m. Also the safety
    figures of every run: collisions, closest approach, landing error, hit rate.
    """
    known = (("mission.prior_fires", "known"),)
    sizes = [3, 5, 8] if quick else list(range(3, 15))
    seeds = [1] if quick else [1, 2, 3]
    sigmas = [25, 50] if quick else [15, 20, 25, 30, 40, 50]
    specs = [
        MissionSpec("ff_known", "ff_two_fires", uavs=n, seed=s, overrides=known, label="table1")
        for n in sizes
        for s in seeds
    ]
    specs += [
        MissionSpec(
            "ff_known",
            f"ff_k_{sigma}",
            uavs=5,
            seed=s,
            label=f"fig15 sigma2={sigma}",
            scenario_yaml=_fig15_scenario(sigma, known=True),
        )
        for sigma in sigmas
        for s in seeds
    ]

    def reduce(pairs: list[tuple[MissionSpec, dict]]) -> dict:
        g = SweepResults(pairs)
        rows = []
        for n in sizes:
            runs = g.where(label="table1", uavs=n)
            per = [r.get("drops_per_fire", {}) for r in runs]
            land = [max(r["landing_error_m"].values()) for r in runs if r.get("landing_error_m")]
            rows.append(
                {
                    "uavs": n,
                    "seeds": seeds,
                    "mean_interval_s": _mean([r.get("mean_inter_drop_interval_s") for r in runs]),
                    "drops": _mean([r.get("drops_total") for r in runs]),
                    "drops_fire0": _mean([p.get("0", 0) for p in per]),
                    "drops_fire1": _mean([p.get("1", 0) for p in per]),
                    "mission_time_s": _mean([r.get("mission_time_s") for r in runs]),
                    "completed": sum(r.get("outcome") == "complete" for r in runs),
                    "collisions": sum(r.get("collisions", 0) for r in runs),
                    "min_separation_m": min(
                        (r["min_separation_m"] for r in runs if r.get("min_separation_m")), default=None
                    ),
                    "max_landing_error_m": max(land) if land else None,
                    "min_hit_rate": min(
                        (r["hit_rate"] for r in runs if r.get("hit_rate") is not None), default=None
                    ),
                    "paper_interval": FF_TABLE_I.get(n, (None, None))[0],
                    "paper_drops": FF_TABLE_I.get(n, (None,) * 2)[1],
                }
            )
        fig15 = []
        for sigma in sigmas:
            runs = g.where(label=f"fig15 sigma2={sigma}")
            per = [r.get("drops_per_fire", {}) for r in runs]
            fig15.append(
                {
                    "sigma2_m": sigma,
                    "drops_fire0": _mean([p.get("0", 0) for p in per]),
                    "drops_fire1": _mean([p.get("1", 0) for p in per]),
                    "missed": _mean([p.get("missed", 0) for p in per]),
                    "completed": sum(r.get("outcome") == "complete" for r in runs),
                }
            )
        tot0 = sum(r["drops_fire0"] for r in rows)
        tot1 = sum(r["drops_fire1"] for r in rows)
        return {
            "rows": rows,
            "fig15": fig15,
            "share_fire0": tot0 / (tot0 + tot1) if tot0 + tot1 else None,
            "paper_share_fire0": 0.726,
        }

    return Sweep(specs, reduce)


def bench_faults(quick: bool) -> Sweep:
    """Mission time and drops with 0, 1, 2 agents killed, and with 0%, 5%, 20%, 50% loss."""
    seeds = [1] if quick else [1, 2, 3]
    cases = [("none", []), ("kill 1", ["--kill", "1@30"]), ("kill 2", ["--kill", "1@30", "--kill", "3@30"])]
    cases += [(f"loss {p:.0%}", ["--loss", str(p)]) for p in ([0.2, 0.5] if quick else [0.0, 0.05, 0.2, 0.5])]
    specs = [
        MissionSpec("faults", "ff_two_fires", uavs=5, seed=s, mode="processes", args=tuple(extra), label=name)
        for name, extra in cases
        for s in seeds
    ]

    def reduce(pairs: list[tuple[MissionSpec, dict]]) -> dict:
        g = SweepResults(pairs)
        rows = []
        for name, _ in cases:
            runs = g.where(label=name)
            rows.append(
                {
                    "case": name,
                    "mission_time_s": _mean([r.get("mission_time_s") for r in runs]),
                    "drops": _mean([r.get("drops_total") for r in runs]),
                    "completed": f"{sum(r.get('outcome') == 'complete' for r in runs)}/{len(runs)}",
                }
            )
        return {"rows": rows}

    return Sweep(specs, reduce)


def _skeleton(
    n: int, steps: int, peer_messages: int = 1, wire: str = "bytes", fidelity: str = "full"
) -> dict:
    """One run of the messaging skeleton (``fire_bench.skeleton``): its world's step rate, the agents'
    CPU per step and RSS; ``fidelity`` full also starts the runner's stand-in (``supervisor``)."""
    from fire_mission.procs import ProcessGroup, claim_domain
    from fire_mission.procstat import sample

    with (
        claim_domain() as domain,
        tempfile.TemporaryDirectory() as d,
        ProcessGroup(Path(d), dict(os.environ, ROS_DOMAIN_ID=str(domain))) as g,
    ):
        for k in range(n):
            g.start(
                f"agent_{k}",
                [sys.executable, "-m", "fire_bench.skeleton", "agent", "--uav-id", str(k), "--uavs", str(n)]
                + ["--peer-messages", str(peer_messages), "--wire", wire, "--fidelity", fidelity],
            )
        if fidelity == "full":
            g.start(
                "supervisor", [sys.executable, "-m", "fire_bench.skeleton", "supervisor", "--uavs", str(n)]
            )
        w = g.start(
            "world",
            [sys.executable, "-m", "fire_bench.skeleton", "world", "--uavs", str(n), "--steps", str(steps)]
            + ["--peer-messages", str(peer_messages), "--wire", wire, "--fidelity", fidelity],
        )
        stats: dict = {}
        t_end = time.monotonic() + 600
        while w.alive() and time.monotonic() < t_end:
            for name, c in g.children.items():
                st = sample(c.pid)
                if st:
                    stats[name] = st
            time.sleep(0.5)
        line = (Path(d) / "world.log").read_text().strip().splitlines()
        result = json.loads(line[-1]) if line and line[-1].startswith("{") else {"steps_per_s": None}
        g.stop_all()  # agents print their CPU per step as they exit
        per_step = []
        for k in range(n):
            tail = (Path(d) / f"agent_{k}.log").read_text().strip().splitlines()
            rec = [json.loads(x) for x in tail if x.startswith("{")]
            if rec:
                per_step.append(rec[-1]["cpu_ms_per_step"])
    agents = [v for k, v in stats.items() if k.startswith("agent")]
    result["agent_cpu_ms_per_step"] = _mean(per_step)
    result["agent_rss_mb_mean"] = _mean([a.rss_mb for a in agents])
    result["world_rss_mb"] = stats["world"].rss_mb if "world" in stats else None
    return result


#: the scale targets (benchmark figures, not tests): fleet/skeleton step-rate ratio, agent RSS, 20-UAV rate
SCALE_TARGETS = {"ratio_to_skeleton": 0.8, "agent_rss_mb": 100.0, "steps_per_s_at_20": 10.0}
SCALE_SIZES: list[int] | None = None  # --scale-sizes
SCALE_DURATION_S: float | None = None  # --scale-duration
OUT: Path | None = None  # the results directory of the current run (benchmarks that write files)


def bench_scale(quick: bool) -> dict:
    """Lockstep step rate, CPU and memory per process for N UAVs, against the messaging skeleton
    (the same sizes in the same run): 3-30 UAVs (full), 3/5/10 (quick) or ``--scale-sizes``. The
    skeleton runs twice per size: with the fleet's processes, topics and protocol (``--fidelity
    full``, the ratio's reference, as it carries the fleet's whole traffic;
    ``tests/system/test_skeleton_fidelity.py`` holds it to the fleet's) and as the minimal
    skeleton (bundles, one unsigned state, the command), kept to compare with the older rows
    that were measured against it."""
    sizes = SCALE_SIZES or ([3, 5, 10] if quick else [3, 5, 10, 14, 20, 30])
    duration = SCALE_DURATION_S or (15.0 if quick else 30.0)
    rows = []
    for n in sizes:
        log(f"scale: skeleton with {n} UAVs (the fleet's processes, topics and protocol)")
        sk = _skeleton(n, int(duration * 10))
        log(f"scale: minimal skeleton with {n} UAVs")
        skm = _skeleton(n, int(duration * 10), fidelity="minimal")
        log(f"scale: fleet with {n} UAVs for {duration:g} s of mission time")
        probe = machine_probe()
        r = mission("ff_two_fires", "--uavs", str(n), "--seed", "1", "--max-duration", str(duration))
        procs = r.get("processes", {})
        agents = [v for k, v in procs.items() if k.startswith("agent")]
        rate = r.get("steps_per_wall_s")
        world_ms = procs.get("world", {}).get("cpu_ms_per_step")
        sk_rate = sk.get("steps_per_s")
        rows.append(
            {
                "uavs": n,
                "steps_per_s": rate,
                "skeleton_steps_per_s": sk_rate,
                "ratio_to_skeleton": (rate / sk_rate) if rate and sk_rate else None,
                "agent_cpu_ms_per_step": _mean([a.get("cpu_ms_per_step") for a in agents]),
                "skeleton_agent_cpu_ms_per_step": sk.get("agent_cpu_ms_per_step"),
                "skeleton_minimal_steps_per_s": skm.get("steps_per_s"),
                "ratio_to_minimal_skeleton": (rate / skm["steps_per_s"])
                if rate and skm.get("steps_per_s")
                else None,
                "skeleton_minimal_agent_cpu_ms_per_step": skm.get("agent_cpu_ms_per_step"),
                # bundles sent again (lost): full, minimal
                "skeleton_resends": [sk.get("resends"), skm.get("resends")],
                "world_cpu_ms_per_step": world_ms,
                "agent_rss_mb": _mean([a["rss_mb"] for a in agents]),
                "skeleton_agent_rss_mb": sk.get("agent_rss_mb_mean"),
                "world_cpu_s": procs.get("world", {}).get("cpu_s"),
                "world_rss_mb": procs.get("world", {}).get("rss_mb"),
                **probe,  # the machine's speed just before the fleet's run (machine_probe)
            }
        )
    return {"mission_time_s": duration, "rows": rows, "targets": SCALE_TARGETS}


# per library benchmark: (quick args, full args)
SCRIPT_ARGS = {
    "agent": (["--duration", "60"], []),
    "world": (["--steps", "100", "--warmup-s", "60"], []),
    "perimeter": (["--quick"], []),
    "search": (["--quick"], []),
    "record": (["--seconds", "10"], []),
}


def _script(name: str, quick: bool) -> dict:
    """Run a library benchmark script (scripts/bench_<name>.py); keep its printed figures."""
    from fire_mission.procs import claim_domain

    path = ROOT / "scripts" / f"bench_{name}.py"
    if not path.is_file():
        return {"status": f"missing: {path.name}"}
    extra = SCRIPT_ARGS.get(name, ([], []))[0 if quick else 1]
    t0 = time.monotonic()
    # the packages come from the sourced workspace (scripts/env.sh), the tools from their install
    with claim_domain() as domain:
        p = subprocess.run(
            [sys.executable, str(path), *extra],
            capture_output=True,
            text=True,
            check=False,
            timeout=3600,
            env=dict(os.environ, ROS_DOMAIN_ID=str(domain)),
        )
    out = {
        "command": " ".join(["scripts/" + path.name, *extra]),
        "exit_code": p.returncode,
        "wall_s": round(time.monotonic() - t0, 1),
        # a script's whole report (the full perimeter run prints ~6 KB; a 6,000-character tail cut
        # its header and first table); bounded only against a runaway script
        "stdout": p.stdout[-60000:],
    }
    if p.returncode != 0:
        out["stderr"] = p.stderr[-2000:]
    return out


BENCHES: dict[str, tuple[Callable[[bool], dict | Sweep], float, float, str]] = {
    # name: (function, quick minutes, full minutes, what); the function returns its figures
    # (runs here) or a Sweep of missions (runs on the executor: local, or --scheduler)
    "ekf": (lambda q: _script("agent", q), 0.5, 2, "FF Fig. 4: EKF error bounds; agent CPU per step"),
    "world": (
        lambda q: _script("world", q),
        0.5,
        2,
        "world step cost (analytic, 200x200 raster, 5 and 14 UAVs), raster share, raster direction errors",
    ),
    "perimeter": (
        lambda q: _script("perimeter", q),
        1,
        3,
        "PM Figs. 11, 16: direction changes vs alpha; importance vs circling",
    ),
    "search": (lambda q: _script("search", q), 1, 5, "CP Fig. 8: Bayesian optimisation vs random sampling"),
    "record": (
        lambda q: _script("record", q),
        1,
        3,
        "recorder CPU and bytes per mission second; report time",
    ),
    "scale": (
        bench_scale,
        2.5,
        20,
        "lockstep step rate, CPU, memory vs fleet size, against the messaging skeleton",
    ),
    "speed": (
        lambda q: _speed(q),
        8,
        25,
        "this commit against --base (a built checkout of an older commit), back to back: CPU per "
        "mission second in one process, world step at 20 UAVs, DDS steps/s and agent RSS",
    ),
    "table1": (bench_table1, 3, 90, "FF Table I: drop interval and drops vs fleet size"),
    "fire_share": (bench_fire_share, 2, 15, "FF Figs. 14-15: drops per fire vs fire size"),
    "ff_known": (
        bench_ff_known,
        4,
        60,
        "FF Table I, Figs. 14-15 with known fires (in process); collisions, separation, landing, hit rate",
    ),
    "faults": (bench_faults, 3, 40, "crash and loss: mission time and drops"),
    "suppression": (
        lambda q: _suppression(q),
        8,
        60,
        "raster suppression: burned area vs no fleet, head vs flank, fleet of 0/3/6/10 (in process)",
    ),
}


SPEED_BASE: Path | None = None  # --base


def _speed(quick: bool) -> dict:
    from fire_bench.speed import bench_speed

    return bench_speed(SPEED_BASE, quick, SCALE_SIZES)


def _suppression(quick: bool) -> dict:
    from fire_bench.suppression import bench_suppression

    return bench_suppression(quick, jobs=2, out=OUT)


def estimate_minutes(names: list[str], quick: bool, measured: dict) -> tuple[float, list[str]]:
    """Expected minutes of ``names``: each benchmark's last measured wall time of the same kind
    (quick or full) in ``measured`` (a results.json), else the guess of :data:`BENCHES`; and the
    names that had only the guess."""
    total, guessed = 0.0, []
    for n in names:
        r = measured.get(n)
        if isinstance(r, dict) and r.get("quick") == quick and isinstance(r.get("wall_s"), int | float):
            total += r["wall_s"] / 60
        else:
            total += BENCHES[n][1 if quick else 2]
            guessed.append(n)
    return total, guessed


def run_command(a: argparse.Namespace, name: str, sweep: bool = False) -> str:
    """The command line that reproduces section ``name``'s figures (output options left out;
    a sweep's executor kept, as it changes the wall time)."""
    parts = ["scripts/bench"] + (["--quick"] if a.quick else []) + ["--only", name]
    if name == "scale":
        parts += ["--scale-sizes", a.scale_sizes] if getattr(a, "scale_sizes", None) else []
        parts += ["--scale-duration", f"{a.scale_duration:g}"] if getattr(a, "scale_duration", None) else []
    if name == "speed":
        parts += ["--base", "BASE"] if getattr(a, "base", None) else []
        parts += ["--scale-sizes", a.scale_sizes] if getattr(a, "scale_sizes", None) else []
    if sweep and getattr(a, "scheduler", None):
        parts += ["--scheduler", a.scheduler]
    elif sweep and getattr(a, "jobs", 1) != 1:
        parts += ["--jobs", str(a.jobs)]
    return " ".join(shlex.quote(x) for x in parts)


def main(argv: list[str] | None = None) -> int:
    p = OneLineParser(prog="bench", description=__doc__.split("\n\n")[0])
    p.add_argument(
        "--quick", action="store_true", help="small version of each benchmark (< 10 minutes in all)"
    )
    p.add_argument("--only", nargs="+", choices=list(BENCHES), help="run only these")
    p.add_argument(
        "--out",
        type=Path,
        default=None,
        help="results directory (default: a new runs/bench-<time>/; the committed docs change only "
        "with --update-docs)",
    )
    p.add_argument(
        "--update-docs",
        action="store_true",
        help="write the results into docs/bench/results.json (the sections run replace theirs) and "
        "render docs/benchmarks.md again",
    )
    p.add_argument(
        "--render",
        action="store_true",
        help="run nothing: rewrite docs/benchmarks.md from docs/bench/results.json and docs/bench/notes",
    )
    p.add_argument("--list", action="store_true", help="list the benchmarks and their expected durations")
    p.add_argument("--scale-sizes", default=None, metavar="N,N,...", help="scale: these fleet sizes")
    p.add_argument(
        "--scale-duration", type=float, default=None, metavar="S", help="scale: mission seconds per run"
    )
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="tcp://HOST:PORT",
        help="run the missions of sweep benchmarks on this Dask distributed scheduler's workers",
    )
    p.add_argument(
        "--jobs", type=int, default=1, metavar="N", help="without --scheduler: N missions at a time here"
    )
    p.add_argument("--no-page", action="store_true", help="write results.json only, no page")
    p.add_argument(
        "--base",
        type=Path,
        default=None,
        metavar="DIR",
        help="speed: a built checkout of the commit to compare with (e.g. a git worktree of it); the "
        "page names its commit",
    )
    a = p.parse_args(argv)
    if a.render:
        if a.quick or a.only or a.out or a.update_docs or a.list:
            p.error("--render runs nothing: it takes no other option")
        log(f"page: {page.render_docs()}")
        return 0
    if a.update_docs and a.out is not None:
        p.error("--update-docs writes into docs/bench; leave out --out")
    if a.jobs < 1:
        p.error(f"--jobs must be >= 1, got {a.jobs}")
    if a.scheduler and a.jobs != 1:
        p.error("--jobs applies to local runs only; the cluster's workers set the parallelism")
    global SCALE_SIZES, SCALE_DURATION_S, OUT, SPEED_BASE
    if a.base is not None:
        if not (a.base / "scripts" / "env.sh").is_file():
            p.error(f"--base {a.base}: not a checkout of this project (no scripts/env.sh)")
        SPEED_BASE = a.base.resolve()
    if a.scale_sizes:
        try:
            SCALE_SIZES = [int(x) for x in a.scale_sizes.split(",")]
        except ValueError:
            p.error(f"--scale-sizes expects comma-separated whole numbers, got '{a.scale_sizes}'")
        if any(n < 1 for n in SCALE_SIZES):
            p.error(f"--scale-sizes must all be >= 1, got '{a.scale_sizes}'")
    if a.scale_duration is not None:
        if not a.scale_duration > 0:
            p.error(f"--scale-duration must be > 0, got {a.scale_duration}")
        SCALE_DURATION_S = a.scale_duration
    names = a.only or list(BENCHES)
    try:
        measured = json.loads((page.DOCS / "bench/results.json").read_text())
    except (OSError, json.JSONDecodeError):
        measured = {}
    if a.list:
        print("minutes from the committed results' wall times (~: a guess, not measured yet)")
        for n in BENCHES:
            q, q_guess = estimate_minutes([n], True, measured)
            full, full_guess = estimate_minutes([n], False, measured)
            print(
                f"{n:12s} quick {'~' if q_guess else ''}{q:.1f} min, full {'~' if full_guess else ''}"
                f"{full:.1f} min  {BENCHES[n][3]}"
            )
        return 0
    est, guessed = estimate_minutes(names, a.quick, measured)
    log(
        f"running {', '.join(names)} ({'quick' if a.quick else 'full'}): expect about {est:.0f} minutes"
        + (f" (last measured runs; guessed for {', '.join(guessed)})" if guessed else " (last measured runs)")
    )
    if a.update_docs:
        a.out = page.DOCS / "bench"
    elif a.out is None:
        a.out = page.RUNS / f"bench-{time.strftime('%Y%m%d-%H%M%S')}"
    OUT = a.out
    try:
        executor = make_executor(a.scheduler, a.jobs)
    except SweepError as e:
        print(f"bench: error: {e}", file=sys.stderr)
        return 2
    if isinstance(executor, DaskExecutor):
        n_workers = len(executor.workers())
        log(
            f"sweep missions go to {a.scheduler}: {n_workers} workers"
            + ("" if n_workers else " now; missions wait until one joins")
        )
    try:
        return _run(a, names, executor)
    finally:
        executor.close()


def _run(a: argparse.Namespace, names: list[str], executor: Executor) -> int:
    a.out.mkdir(parents=True, exist_ok=True)
    results_path = a.out / "results.json"
    results = json.loads(results_path.read_text()) if results_path.is_file() else {}
    here = machine()
    if not a.only or "machine" not in results:
        results["machine"] = here  # the page's header: the machine of the last full run
    for i, n in enumerate(names, 1):
        log(f"({i}/{len(names)}) {n}: {BENCHES[n][3]}")
        t0 = time.monotonic()
        made = BENCHES[n][0](a.quick)
        if isinstance(made, Sweep):
            log(f"{n}: {len(made.specs)} missions on {executor.name}")
            r = run_sweep(made, executor)
            r["executor"] = executor.name
        else:
            r = made
        r["wall_s"] = round(time.monotonic() - t0, 1)
        r["quick"] = a.quick
        r["command"] = r.get("command") or run_command(a, n, sweep=isinstance(made, Sweep))
        # each section names the machine, commit and date it ran on: an --only run on another
        # day (runs land on AMD EPYC or Intel Xeon hosts here) must not relabel the others
        r["machine"] = here
        results[n] = r
        results_path.write_text(json.dumps(results, indent=2, default=str) + "\n")
        log(f"{n} done in {r['wall_s']:.0f} s")
    if a.no_page:
        log(f"results: {results_path}")
        return 0
    page.draw_plots({n: results[n] for n in names if n in results}, a.out)  # only the sections that ran
    if getattr(a, "update_docs", False):
        md = page.render_docs()
    else:  # a run folder's page: its own plots beside it, no notes (they read the committed figures)
        md = a.out / "benchmarks.md"
        md.write_text(page.render(results, None, plot_dir=a.out, plot_prefix=""))
    log(f"results: {results_path}; page: {md}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
