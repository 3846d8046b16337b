"""Render docs/benchmarks.md from bench results.json and the hand-written notes; draw its plots.

The page is generated, never edited: :func:`render` builds it from ``results.json`` (what the
benchmarks measured) and the notes directory (``docs/bench/notes``: the reading of the figures,
written by hand). ``notes/intro.md`` follows the page's header; ``notes/<section>.before.md``
goes between a section's command line and its tables, ``notes/<section>.md`` after them (the
section names are the benchmark names of ``scripts/bench --list``). ``scripts/bench --render``
rewrites the page from both without running anything, and a test checks that the committed page
is that render byte for byte.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the checkout: tools/<package>/<module>.py
DOCS = ROOT / "docs"  # the committed page (benchmarks.md), its results and notes (bench/)
RUNS = ROOT / "runs"  # where a benchmark writes unless told otherwise (not committed)

#: the page's sections in order: the sweep and scale benchmarks, then the library scripts'
SCRIPT_SECTIONS = [
    ("ekf", "EKF error (FF Fig. 4) and agent cost"),
    ("world", "World step cost"),
    ("perimeter", "Perimeter monitoring (PM Figs. 11, 16)"),
    ("search", "Coverage search (CP Fig. 8)"),
    ("record", "Recorder and report"),
]


def _fmt(v: object, nd: int = 2) -> str:
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.{nd}f}"
    return str(v)


def _table(rows: list[dict], cols: list[tuple[str, str]]) -> str:
    head = "| " + " | ".join(h for _, h in cols) + " |\n|" + "---|" * len(cols) + "\n"
    return head + "".join("| " + " | ".join(_fmt(r.get(k)) for k, _ in cols) + " |\n" for r in rows)


def _ran_on(r: dict) -> list[str]:
    """A section's own machine line (``scripts/bench --only`` runs on other days and hosts)."""
    m = r.get("machine")
    if not m:
        return []
    return [f"Ran on: {m.get('cpu')}, {m.get('cores')} cores; commit {m.get('commit')}, {m.get('date')}.", ""]


class _Notes:
    """The hand-written notes of a page (none for a run folder's page: they read the committed figures)."""

    def __init__(self, directory: Path | None) -> None:
        self.directory = directory

    def get(self, name: str) -> list[str]:
        if self.directory is None:
            return []
        path = self.directory / f"{name}.md"
        return [path.read_text().rstrip(), ""] if path.is_file() else []

    def before(self, section: str) -> list[str]:
        return self.get(f"{section}.before")

    def after(self, section: str) -> list[str]:
        return self.get(section)


def draw_plots(results: dict, out: Path) -> dict[str, str]:
    """Draw the page's plots of ``results`` into ``out``; {section: file name}."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    made = {}
    t1 = results.get("table1", {}).get("rows")
    if t1:
        fig, ax = plt.subplots(figsize=(6, 3.5))
        xs = [r["uavs"] for r in t1]
        ax.plot(xs, [r["mean_interval_s"] for r in t1], "o-", label="ours [s]")
        ax2 = ax.twinx()
        ax2.plot(xs, [r["paper_interval"] for r in t1], "s--", color="gray", label="FF Table I [paper steps]")
        ax.set_xlabel("UAVs")
        ax.set_ylabel("mean inter-drop interval [s]")
        ax2.set_ylabel("paper [its time unit]")
        fig.legend(loc="upper right")
        fig.tight_layout()
        fig.savefig(out / "table1.png", dpi=100)
        plt.close(fig)
        made["table1"] = "table1.png"
    sc = results.get("scale", {}).get("rows")
    if sc:
        fig, ax = plt.subplots(figsize=(6, 3.5))
        xs = [r["uavs"] for r in sc]
        ax.plot(xs, [r["steps_per_s"] for r in sc], "o-", label="fleet")
        ax.plot(
            xs,
            [r["skeleton_steps_per_s"] for r in sc],
            "s--",
            label="messaging skeleton (the fleet's topics)",
        )
        if any(r.get("skeleton_minimal_steps_per_s") for r in sc):
            ax.plot(
                xs,
                [r.get("skeleton_minimal_steps_per_s") or float("nan") for r in sc],
                "d-.",
                label="minimal skeleton",
            )
        ax.axhline(10.0, color="grey", lw=0.8, label="real time (10 steps/s)")
        ax.set_xlabel("UAVs")
        ax.set_ylabel("lockstep control steps per wall second")
        ax.set_yscale("log")
        ax.legend()
        fig.tight_layout()
        fig.savefig(out / "scale.png", dpi=100)
        plt.close(fig)
        made["scale"] = "scale.png"
    return made


def render_docs() -> Path:
    """Rewrite docs/benchmarks.md from docs/bench/results.json and docs/bench/notes; runs nothing."""
    results_path = DOCS / "bench/results.json"
    try:
        results = json.loads(results_path.read_text())
    except (OSError, json.JSONDecodeError) as e:
        raise SystemExit(f"bench: error: cannot read {results_path}: {e}") from None
    page = DOCS / "benchmarks.md"
    page.write_text(render(results, DOCS / "bench/notes", plot_dir=DOCS / "bench"))
    return page


def write_markdown(
    results: dict, out: Path, md_path: Path, notes: Path | None = None, plot_prefix: str = "bench/"
) -> None:
    """Draw the plots into ``out`` and write the page ``md_path`` (plots linked as ``plot_prefix``+name)."""
    draw_plots(results, out)
    md_path.write_text(render(results, notes, plot_dir=out, plot_prefix=plot_prefix))


def render(
    results: dict, notes_dir: Path | None, plot_dir: Path | None = None, plot_prefix: str = "bench/"
) -> str:
    """The page's text: ``results`` (results.json) and the notes in ``notes_dir``; runs nothing.

    A plot is linked when its file is in ``plot_dir`` (drawn by :func:`draw_plots` when the
    benchmark ran)."""
    notes = _Notes(notes_dir)
    plots = {
        name: f"{plot_prefix}{name}.png"
        for name in ("table1", "scale")
        if plot_dir is not None and (plot_dir / f"{name}.png").is_file() and results.get(name, {}).get("rows")
    }
    m = results.get("machine", {})
    lines = [
        "# Benchmarks",
        "",
        *(
            [
                "Generated by `scripts/bench` from `docs/bench/results.json` and the hand-written notes in",
                "`docs/bench/notes/` (edit those, then `scripts/bench --render`; never this page); every figure",
                "below names the command that produced it. Measured, not asserted: the machine is shared and noisy.",
            ]
            if notes_dir is not None
            else [
                "Generated by `scripts/bench` from `results.json` beside this page; every figure below names the",
                "command that produced it. Measured, not asserted: the machine is shared and noisy.",
            ]
        ),
        "",
        f"Machine: {m.get('cpu')}, {m.get('cores')} cores, {m.get('mem_gib')} GiB, Python {m.get('python')}, "
        f"{m.get('os')}; commit {m.get('commit')}, {m.get('date')}.",
        "",
    ]
    lines += notes.get("intro")
    if "table1" in results:
        r = results["table1"]
        lines += [
            "## FF Table I: drop interval vs fleet size",
            "",
            *_ran_on(r),
            f"Command: `{r['command']}` ({r['wall_s']:.0f} s)",
            "",
            *notes.before("table1"),
            "The paper's interval is in its simulation's own time unit (not stated); ours is in seconds of",
            "mission time, so compare the trend and the scaling efficiency, interval(N)·N / (interval(3)·3)",
            "inverted (1 = the drop rate grows linearly with the fleet).",
            "",
            _table(
                r["rows"],
                [
                    ("uavs", "UAVs"),
                    ("mean_interval_s", "interval [s]"),
                    ("drops", "drops"),
                    ("scaling_efficiency", "scaling eff."),
                    ("completed", "completed"),
                    ("paper_interval", "paper interval"),
                    ("paper_drops", "paper drops"),
                ],
            ),
        ]
        if "table1" in plots:
            lines += [f"![Table I]({plots['table1']})", ""]
        lines += notes.after("table1")
    if "fire_share" in results:
        r = results["fire_share"]
        lines += [
            "## FF Figs. 14-15: drops per fire vs fire size",
            "",
            *_ran_on(r),
            f"Command: `{r['command']}`",
            "",
            *notes.before("fire_share"),
            _table(
                r.get("rows", []),
                [
                    ("sigma2_m", "fire 2 sigma [m]"),
                    ("drops_fire0", "drops fire 1"),
                    ("drops_fire1", "drops fire 2"),
                    ("missed", "missed"),
                    ("outcome", "outcome"),
                ],
            ),
            f"Share of drops on fire 1 at sigma 50 / 25 m: {_fmt(r.get('share_fire0_at_25m'))} "
            f"(paper: {_fmt(r.get('paper_share_fire0'))}; area share 0.67).",
            "",
            *notes.after("fire_share"),
        ]
    if "ff_known" in results:
        r = results["ff_known"]
        lines += [
            "## FF Table I and Figs. 14-15 with known fires (`mission.prior_fires: known`)",
            "",
            *_ran_on(r),
            f"Command: `{r['command']}` ({r['wall_s']:.0f} s wall, {_missions(r)} missions on {r.get('executor')}).",
            "",
            *notes.before("ff_known"),
            _table(
                r["rows"],
                [
                    ("uavs", "UAVs"),
                    ("mean_interval_s", "interval [s]"),
                    ("paper_interval", "paper interval"),
                    ("drops", "drops"),
                    ("paper_drops", "paper drops"),
                    ("drops_fire0", "drops fire 1"),
                    ("drops_fire1", "drops fire 2"),
                    ("mission_time_s", "mission [s]"),
                    ("completed", "completed"),
                    ("collisions", "collisions"),
                    ("min_separation_m", "min sep. [m]"),
                    ("max_landing_error_m", "max landing err. [m]"),
                    ("min_hit_rate", "min hit rate"),
                ],
            ),
            f"Share of drops on fire 1 over all fleet sizes (Fig. 14): {_fmt(r.get('share_fire0'))} "
            f"(FF: {r.get('paper_share_fire0')} with sigma 50 / 25 m).",
            "",
            f"Fig. 15 (5 UAVs, fire 1 sigma 50 m, fire 2 sigma {_span([x['sigma2_m'] for x in r.get('fig15', [])])} m, "
            f"seeds {_span(_seeds(r))}, means):",
            "",
            _table(
                r.get("fig15", []),
                [
                    ("sigma2_m", "fire 2 sigma [m]"),
                    ("drops_fire0", "drops fire 1"),
                    ("drops_fire1", "drops fire 2"),
                    ("missed", "missed"),
                    ("completed", "completed"),
                ],
            ),
            *notes.after("ff_known"),
        ]
    if "faults" in results:
        r = results["faults"]
        lines += [
            "## Crashes and packet loss",
            "",
            *_ran_on(r),
            f"Command: `{r['command']}`",
            "",
            *notes.before("faults"),
            _table(
                r["rows"],
                [
                    ("case", "case"),
                    ("mission_time_s", "mission time [s]"),
                    ("drops", "drops"),
                    ("completed", "completed"),
                ],
            ),
            *notes.after("faults"),
        ]
    if "suppression" in results:
        lines += _suppression_section(results["suppression"], notes, plot_prefix)
    if "scale" in results:
        r = results["scale"]
        lines += [
            "## Scale: lockstep step rate, CPU and memory",
            "",
            *_ran_on(r),
            f"Command: `{r['command']}`; {r['mission_time_s']:g} s of mission time per run. The skeleton "
            "(`fire_bench.skeleton --fidelity full`, the ratio's reference) has the fleet's processes "
            "(world, agents, the runner's subscriptions), topics and protocol (signed states and payload "
            "requests, the lockstep peer wait, /tf, markers, truth) with messages of the fleet's sizes and "
            "rates and no algorithms (`tests/system/test_skeleton_fidelity.py` holds it to the fleet's "
            'traffic); "minimal": `--fidelity minimal`, the bundles, one unsigned state and the command only.',
            "",
            *notes.before("scale"),
            _table(
                r["rows"],
                [
                    ("uavs", "UAVs"),
                    ("steps_per_s", "steps/s"),
                    ("skeleton_steps_per_s", "skeleton steps/s"),
                    ("ratio_to_skeleton", "ratio"),
                    ("agent_cpu_ms_per_step", "agent CPU ms/step"),
                    ("skeleton_agent_cpu_ms_per_step", "skeleton agent CPU ms/step"),
                    ("skeleton_minimal_steps_per_s", "minimal skeleton steps/s"),
                    ("ratio_to_minimal_skeleton", "ratio to it"),
                    ("skeleton_minimal_agent_cpu_ms_per_step", "minimal skeleton agent CPU ms/step"),
                    ("agent_rss_mb", "agent RSS MiB"),
                    ("skeleton_agent_rss_mb", "skeleton RSS MiB"),
                    ("world_cpu_ms_per_step", "world CPU ms/step"),
                    ("world_rss_mb", "world RSS MiB"),
                    ("probe_ms", "probe ms"),
                ],
            ),
            "",
            "probe ms: one core's Python speed just before the fleet's run (a fixed pure-Python loop, "
            "median of 5; larger is slower; `fire_bench.bench.machine_probe`). It does not follow the "
            "fleet's day-to-day variation; the skeleton beside each row does.",
        ]
        t = r.get("targets")
        if t:
            lines += [
                "",
                f"Targets: ratio to the skeleton >= {t['ratio_to_skeleton']:g}, agent RSS <= "
                f"{t['agent_rss_mb']:g} MiB, >= {t['steps_per_s_at_20']:g} steps/s (real time) at 20 UAVs.",
                "",
            ]
        lines += notes.after("scale")
        if "scale" in plots:
            lines += [f"![scale]({plots['scale']})", ""]
    if "speed" in results:
        lines += _speed_section(results["speed"], notes)
    for name, title in SCRIPT_SECTIONS:
        if name in results:
            r = results[name]
            lines += [
                f"## {title}",
                "",
                *_ran_on(r),
                f"Command: `{r.get('command')}` (exit {r.get('exit_code')}, {r.get('wall_s')} s)",
                "",
                *notes.before(name),
                "```",
                (r.get("stdout") or r.get("status") or "").rstrip(),
                "```",
                "",
                *notes.after(name),
            ]
    return "\n".join(lines) + "\n"


def _missions(r: dict) -> int:
    """Missions of the known-fires benchmark: seeds x (fleet sizes + Fig. 15 sizes)."""
    return len(_seeds(r)) * (len(r.get("rows", [])) + len(r.get("fig15", [])))


def _seeds(r: dict) -> list[int]:
    rows = r.get("rows") or [{}]
    return list(rows[0].get("seeds", []))


def _span(xs: list) -> str:
    """``15-50`` for a range of values, the value alone for one, ``-`` for none."""
    if not xs:
        return "-"
    return f"{min(xs)}-{max(xs)}" if min(xs) != max(xs) else f"{xs[0]}"


def _suppression_section(r: dict, notes: _Notes | None = None, plot_prefix: str = "bench/") -> list[str]:
    """Raster suppression (``fire_bench.suppression``): head vs flank per seed, fleet size."""
    rows = []
    for sc, entry in r.get("scenarios", {}).items():
        base = entry.get("baseline_burned_area_m2")
        for tactic, runs in entry.get("tactics", {}).items():
            for x in runs:
                rows.append(
                    {
                        "scenario": sc,
                        "tactic": tactic,
                        "seed": x["seed"],
                        "base_ha": None if base is None else round(base / 1e4, 2),
                        "burned_ha": round(x["burned_area_m2"] / 1e4, 2),
                        "ratio": None if x["ratio_to_baseline"] is None else round(x["ratio_to_baseline"], 3),
                        "hit_rate": x["hit_rate"],
                        "contained_at_s": x["contained_at_s"],
                        "crashes": x["crashes"],
                    }
                )
    fleet: dict[int, dict] = {}  # UAVs -> burned [ha] per tactic (the no-fleet run under both)
    for x in r.get("fleet_size", []):
        row = fleet.setdefault(x["uavs"], {"uavs": x["uavs"]})
        ha = round(x["burned_area_m2"] / 1e4, 2)
        for t in ("head", "flank") if x.get("tactic", "head") == "none" else (x.get("tactic", "head"),):
            row[f"{t}_ha"] = ha
            if x["uavs"]:
                row[f"{t}_contained"] = x.get("contained_at_s")
    out = [
        "## Raster suppression: burned area, head vs flank, fleet size",
        "",
        *_ran_on(r),
        f"Command: `{r.get('command')}` ({r.get('wall_s')} s); in process, 6 UAVs unless stated; see",
        "docs/suppression.md for the targets and the reading.",
        "",
        *(notes.before("suppression") if notes else []),
        _table(
            rows,
            [
                ("scenario", "scenario"),
                ("tactic", "tactic"),
                ("seed", "seed"),
                ("base_ha", "no fleet [ha]"),
                ("burned_ha", "burned [ha]"),
                ("ratio", "ratio"),
                ("hit_rate", "hit rate"),
                ("contained_at_s", "contained at [s]"),
                ("crashes", "crashed UAVs"),
            ],
        ),
    ]
    if fleet:
        done = "" if len(fleet) >= 4 else "; only these fleet sizes finished"
        out += [
            f'Burned area at 900 s vs fleet size (grass_running, seed 1{done}; "-" = never contained or not run):',
            "",
            _table(
                [fleet[k] for k in sorted(fleet)],
                [
                    ("uavs", "UAVs"),
                    ("head_ha", "head: burned [ha]"),
                    ("head_contained", "head: contained at [s]"),
                    ("flank_ha", "flank: burned [ha]"),
                    ("flank_contained", "flank: contained at [s]"),
                ],
            ),
        ]
    out += [f"![{p}]({plot_prefix}{p})" for p in r.get("plots", [])] + [""]
    return out + (notes.after("suppression") if notes else [])


def _row_notes(rows: list[dict], label: Callable[[dict], str]) -> list[str]:
    """The speed rows' notes under their table: base and head measured on unlike hosts
    (``not_comparable``: speed.PROBE_TOLERANCE), a figure left empty (``not_measured``: a failed
    run, a window without two samples: speed._not_a_measure); each note after its row's label."""
    out: list[str] = []
    for key, heading in (
        ("not_comparable", "Not comparable side by side:"),
        ("not_measured", "Not measured (empty cells above):"),
    ):
        notes_of = [f"- {label(row)}: {note}" for row in rows for note in row.get(key, [])]
        if notes_of:
            out += [heading, "", *notes_of, ""]
    return out


def _probe_paragraph(r: dict) -> list[str]:
    """What the tables' "probe ms" columns are, when any row has one (session 27 on: DDS rows;
    session 28 on: the in-process and world rows too)."""
    rows = [row for key in ("inprocess", "world", "dds") for row in r.get(key, [])]
    if not any(row.get(f"{tag}_probe_ms") for row in rows for tag in ("base", "head")):
        return []
    return [
        "probe ms: the host's one-core speed while the runs ran (`fire_bench.speed.CpuProbe`: CPU ms "
        "of a fixed pure-Python loop, one sample a second, median; larger is slower; in one process, "
        "over each side's least-CPU run). On this shared machine it moves by up to 1.7x within a "
        "minute, and every figure below with it; rows whose base and head probes differ by more than "
        f"{100 * r.get('probe_tolerance', 0.15):.0f} % are listed under their table as not comparable.",
        "",
    ]


def _speed_section(r: dict, notes: _Notes) -> list[str]:
    """This commit against a base commit, measured back to back in one run (``fire_bench.speed``)."""
    base, head = r.get("base_commit") or "-", r.get("head_commit") or "-"
    lines = [
        "## Speed: this commit against the commit before the work, side by side",
        "",
        *_ran_on(r),
        f"Command: `{r.get('command')}` (BASE: a checkout of commit {base}, built; HEAD: commit {head}). "
        "Base and head alternate row by row in one run on the same machine; CPU is user + system "
        "time of the child process.",
        "",
        *notes.before("speed"),
        *_probe_paragraph(r),
        "In one process (`python -m fire_mission.inprocess SCENARIO --uavs N --seed 1`, world and "
        "agents, no DDS; start-up and imports included; the least CPU of the runs, base and head "
        "alternating; same summary: every field but the wall-clock ones). Start-up: the CPU of the "
        "same command at `timing.max_duration_s=1`; x real time after start-up: (mission - 1 s) / "
        "(CPU - start-up CPU), what a long mission approaches:",
        "",
        _table(
            [
                {
                    **row,
                    **{
                        f"{tag}_ms": 1000 * row[f"{tag}_cpu_s"] / row["mission_time_s"]
                        for tag in ("base", "head")
                        if row.get(f"{tag}_cpu_s") is not None and row.get("mission_time_s")
                    },
                }
                for row in r.get("inprocess", [])
            ],
            [
                ("scenario", "scenario"),
                ("uavs", "UAVs"),
                ("repeats", "runs each"),
                ("mission_time_s", "mission [s]"),
                ("base_cpu_s", f"CPU s {base}"),
                ("head_cpu_s", f"CPU s {head}"),
                ("base_ms", f"CPU ms per mission s {base}"),
                ("head_ms", f"CPU ms per mission s {head}"),
                ("base_x_real_time", f"x real time {base}"),
                ("head_x_real_time", f"x real time {head}"),
                ("base_startup_cpu_s", f"start-up CPU s {base}"),
                ("head_startup_cpu_s", f"start-up CPU s {head}"),
                ("base_x_real_time_after_startup", f"x real time after start-up {base}"),
                ("head_x_real_time_after_startup", f"x real time after start-up {head}"),
                ("base_probe_ms", f"probe ms {base}"),
                ("head_probe_ms", f"probe ms {head}"),
                ("summary_same", "same summary"),
            ],
        ),
        "",
        *_row_notes(r.get("inprocess", []), lambda row: row["scenario"]),
        "World step (`fire_bench/speed_probe.py world`, `World.step` alone, ff_two_fires, every vehicle "
        "airborne; CPU ms per step; truth digest compared):",
        "",
        _table(
            r.get("world", []),
            [
                ("uavs", "UAVs"),
                ("steps", "steps"),
                ("base_world_ms_per_step", f"ms/step {base}"),
                ("head_world_ms_per_step", f"ms/step {head}"),
                ("base_probe_ms", f"probe ms {base}"),
                ("head_probe_ms", f"probe ms {head}"),
                ("truth_same", "same truth"),
            ],
        ),
        "",
        *_row_notes(r.get("world", []), lambda row: f"{row['uavs']} UAVs"),
        "Over DDS (`python -m fire_mission.runner ff_two_fires --uavs N --seed 1 --no-record "
        "--no-report`, one process per UAV, lockstep; vehicle model `jsbsim`: the same with "
        "`--set uavs.vehicle_model=jsbsim`, one JSBSim aircraft and autopilot per UAV at 100 Hz; "
        "the window opens once every UAV is airborne, older rows without it are the first seconds, "
        "in the takeoff column; since session 27 it is measured within one run, from the runner's "
        "`stepping.json`, not as the difference of two runs, which multiplied the runs' spread):",
        "",
        _table(
            [{"vehicle_model": "ff_paper", **row} for row in r.get("dds", [])],
            [
                ("uavs", "UAVs"),
                ("vehicle_model", "vehicle model"),
                ("airborne_from_s", "window from [s]"),
                ("mission_time_s", "window [s]"),
                ("base_steps_per_s", f"steps/s {base}"),
                ("head_steps_per_s", f"steps/s {head}"),
                ("base_world_cpu_ms_per_step", f"world CPU ms/step {base}"),
                ("head_world_cpu_ms_per_step", f"world CPU ms/step {head}"),
                ("base_agent_cpu_ms_per_step", f"agent CPU ms/step {base}"),
                ("head_agent_cpu_ms_per_step", f"agent CPU ms/step {head}"),
                ("base_agent_rss_mb", f"agent RSS MiB {base}"),
                ("head_agent_rss_mb", f"agent RSS MiB {head}"),
                ("base_probe_ms", f"probe ms {base}"),
                ("head_probe_ms", f"probe ms {head}"),
            ],
        ),
        "",
    ]
    lines += _row_notes(
        r.get("dds", []), lambda row: f"{row['uavs']} UAVs, {row.get('vehicle_model', 'ff_paper')}"
    )
    t = r.get("targets")
    if t:
        lines += [
            f"Targets: >= {t['grass_running_x_real_time']:g}x real time for grass_running (6 UAVs) and >= "
            f"{t['ff_two_fires_x_real_time']:g}x for ff_two_fires (5) in one process on one core; world "
            f"step <= {t['world_ms_at_20']:g} ms at 20 UAVs; >= {t['dds_steps_per_s_at_30']:g} steps/s "
            f"(real time) at 30 UAVs over DDS, and at 20 on `jsbsim` (issue [airframe]); agent RSS <= "
            f"{t['agent_rss_mb']:g} MiB.",
            "",
        ]
    return lines + notes.after("speed")
