"""The study report: ``index.html`` with figures (matplotlib PNGs), tables and verdicts, and the
results as ``results.csv`` and ``results.parquet`` (pandas / pyarrow) beside it.

Figures: burned area per arm (box plot with every seed's point), paired differences per pair of
tactics (every seed's B - A and the bootstrap CI of the mean), containment curves (Kaplan-Meier:
fraction of seeds contained by t), and the measures over fleet size (mean and its CI per tactic).
"""

from __future__ import annotations

import html
import itertools
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .spec import MEASURES, Arm, Study
from .stats import ArmStats, PairStats, arm_stats, containment, paired_stats, verdict

__all__ = ["auto_check", "pairs", "summary_table", "write_report", "write_tables"]

_COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]


def _groups(study: Study) -> list[tuple[str, str, int]]:
    return [(sc, af, n) for sc in study.scenarios for af, _ in study.airframes for n in study.uavs]


def pairs(study: Study, rows: Sequence[dict], measure: str) -> list[PairStats]:
    """Every pair of tactics (later against earlier in the study's order) in every group."""
    out = []
    for sc, af, n in _groups(study):
        for ta, tb in itertools.combinations(study.tactics, 2):
            out.append(paired_stats(rows, Arm(sc, af, n, ta), Arm(sc, af, n, tb), measure))
    return out


def auto_check(study: Study, rows: Sequence[dict], measure: str = "burned_area_m2") -> list[dict]:
    """Per group: auto against the better fixed tactic (lower mean); ``worse`` when the CI of the
    relative difference lies wholly above zero."""
    fixed = [t for t in study.tactics if t != "auto"]
    if "auto" not in study.tactics or not fixed:
        return []
    out = []
    for sc, af, n in _groups(study):
        means = {t: arm_stats(rows, Arm(sc, af, n, t), measure).mean for t in fixed}
        known = {t: m for t, m in means.items() if math.isfinite(m)}
        if not known:
            continue
        best = min(known, key=lambda t: known[t])
        p = paired_stats(rows, Arm(sc, af, n, best), Arm(sc, af, n, "auto"), measure)
        lo = p.rel_ci[0]
        out.append({"scenario": sc, "airframe": af, "uavs": n, "best": best, "pair": p,
                    "worse": bool(math.isfinite(lo) and lo > 0)})  # fmt: skip
    return out


def _fmt(v: float | None, nd: int = 3) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f"{v:.{nd}g}"


def _scale(measure: str) -> tuple[float, str]:
    """Display scale: areas in ha."""
    if measure == "burned_area_m2":
        return 1e-4, "ha"
    return 1.0, MEASURES[measure][1]


def summary_table(study: Study, rows: Sequence[dict]) -> str:
    """Plain-text table: one line per arm (seeds, burned area mean / median, contained)."""
    head = f"{'arm':44} {'seeds':>5} {'burned mean [ha]':>17} {'median':>8} {'contained':>10} {'KM median [s]':>13}"
    lines = [f"study {study.name}: {len(rows)} missions on file", head, "-" * len(head)]
    for arm in study.arms():
        s = arm_stats(rows, arm, "burned_area_m2")
        c = containment(rows, arm)
        if s.n == 0:
            lines.append(f"{arm.label():44} {0:>5} {'-':>17} {'-':>8} {'-':>10} {'-':>13}")
            continue
        lines.append(
            f"{arm.label():44} {s.n:>5} {s.mean * 1e-4:>17.2f} {s.median * 1e-4:>8.2f} "
            f"{f'{c.contained}/{c.n}':>10} {_fmt(c.median_s, 4):>13}"
        )
    for p in pairs(study, rows, "burned_area_m2"):
        if p.seeds:
            lines.append("- " + verdict(p))
    return "\n".join(lines)


def write_tables(rows: Sequence[dict], out_dir: Path) -> list[str]:
    """results.csv and results.parquet (one row per mission)."""
    import pandas as pd

    df = pd.DataFrame(list(rows)).sort_values(["scenario", "airframe", "uavs", "tactic", "seed"])
    df.to_csv(out_dir / "results.csv", index=False)
    df.to_parquet(out_dir / "results.parquet", index=False)
    return ["results.csv", "results.parquet"]


def _fig_box(study: Study, rows: Sequence[dict], measure: str, path: Path) -> None:
    import matplotlib.pyplot as plt

    k, unit = _scale(measure)
    fig, axes = plt.subplots(1, len(study.scenarios), figsize=(6 * len(study.scenarios), 4.2), squeeze=False)
    rng = np.random.default_rng(0)
    for ax, sc in zip(axes[0], study.scenarios, strict=True):
        pos, ticks, labels = 0.0, [], []
        for af, _ in study.airframes:
            for n in study.uavs:
                for i, t in enumerate(study.tactics):
                    s = arm_stats(rows, Arm(sc, af, n, t), measure)
                    if s.n:
                        v = np.asarray(s.values) * k
                        ax.boxplot([v], positions=[pos], widths=0.6, showfliers=False,
                                   medianprops={"color": _COLORS[i % len(_COLORS)]})  # fmt: skip
                        ax.plot(pos + rng.uniform(-0.15, 0.15, len(v)), v, "o", ms=4, alpha=0.8,
                                color=_COLORS[i % len(_COLORS)], label=t if (n, af) == (study.uavs[0], study.airframes[0][0]) else None)  # fmt: skip
                    ticks.append(pos)
                    labels.append(f"{n}\n{t}" if len(study.airframes) == 1 else f"{n} {af}\n{t}")
                    pos += 1
                pos += 0.6
        ax.set_xticks(ticks, labels, fontsize=7)
        ax.set_ylim(bottom=0)  # the differences against the whole, not magnified
        ax.set_title(sc)
        ax.set_ylabel(f"{MEASURES[measure][0]} [{unit}]")
        ax.set_xlabel("UAVs / tactic")
        ax.grid(axis="y", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _fig_pairs(study: Study, ps: list[PairStats], measure: str, path: Path) -> None:
    import matplotlib.pyplot as plt

    k, unit = _scale(measure)
    fig, axes = plt.subplots(1, len(study.scenarios), figsize=(6 * len(study.scenarios), 4.2), squeeze=False)
    combos = list(itertools.combinations(study.tactics, 2))
    for ax, sc in zip(axes[0], study.scenarios, strict=True):
        ticks, labels = [], []
        pos = 0.0
        for p in (q for q in ps if q.a.scenario == sc):
            j = combos.index((p.a.tactic, p.b.tactic))
            c = _COLORS[j % len(_COLORS)]
            if p.diffs:
                ax.plot([pos] * len(p.diffs), np.asarray(p.diffs) * k, "o", ms=4, alpha=0.6, color=c)
                lo, hi = p.mean_diff_ci
                if math.isfinite(lo):
                    ax.errorbar([pos + 0.2], [p.mean_diff * k], yerr=[[(p.mean_diff - lo) * k], [(hi - p.mean_diff) * k]],
                                fmt="s", color=c, capsize=3)  # fmt: skip
                else:
                    ax.plot([pos + 0.2], [p.mean_diff * k], "s", color=c)
            ticks.append(pos)
            labels.append(f"{p.a.uavs}\n{p.b.tactic}-{p.a.tactic}")
            pos += 1
        ax.axhline(0, color="k", lw=0.8)
        ax.set_xticks(ticks, labels, fontsize=7)
        ax.set_title(f"{sc}: paired differences (B - A per seed, mean and 95 % CI)", fontsize=9)
        ax.set_ylabel(f"{MEASURES[measure][0]} B - A [{unit}]")
        ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _fig_containment(study: Study, rows: Sequence[dict], path: Path) -> None:
    import matplotlib.pyplot as plt

    groups = _groups(study)
    ncol = len(study.uavs) * len(study.airframes)
    fig, axes = plt.subplots(len(study.scenarios), ncol, figsize=(3.6 * ncol, 3.0 * len(study.scenarios)),
                             squeeze=False, sharey=True)  # fmt: skip
    for idx, (sc, af, n) in enumerate(groups):
        ax = axes[idx // ncol][idx % ncol]
        for i, t in enumerate(study.tactics):
            c = containment(rows, Arm(sc, af, n, t))
            if c.n:
                ax.step(c.times_s, c.fraction, where="post", color=_COLORS[i % len(_COLORS)],
                        label=f"{t} ({c.contained}/{c.n})")  # fmt: skip
        ax.set_title(f"{sc}, {n} UAVs" + ("" if af == "default" else f", {af}"), fontsize=9)
        ax.set_ylim(-0.02, 1.02)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("contained (KM)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _fig_fleet(study: Study, rows: Sequence[dict], measure: str, path: Path) -> None:
    import matplotlib.pyplot as plt

    k, unit = _scale(measure)
    fig, axes = plt.subplots(1, len(study.scenarios), figsize=(5.5 * len(study.scenarios), 4), squeeze=False)
    for ax, sc in zip(axes[0], study.scenarios, strict=True):
        for af, _ in study.airframes:
            for i, t in enumerate(study.tactics):
                xs, ys, lo, hi = [], [], [], []
                for n in study.uavs:
                    s = arm_stats(rows, Arm(sc, af, n, t), measure)
                    if s.n:
                        xs.append(n)
                        ys.append(s.mean * k)
                        a, b = s.mean_ci
                        lo.append((s.mean - a) * k if math.isfinite(a) else 0.0)
                        hi.append((b - s.mean) * k if math.isfinite(b) else 0.0)
                if xs:
                    ax.errorbar(np.asarray(xs) + 0.08 * i, ys, yerr=[lo, hi], marker="o", capsize=3,
                                color=_COLORS[i % len(_COLORS)], label=t if af == "default" else f"{t} {af}")  # fmt: skip
        ax.set_xticks(list(study.uavs))
        ax.set_title(sc)
        ax.set_xlabel("UAVs")
        ax.set_ylabel(f"mean {MEASURES[measure][0]} [{unit}]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _table(head: list[str], body: list[list[str]]) -> str:
    h = "".join(f"<th>{html.escape(c)}</th>" for c in head)
    b = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>" for r in body)
    return f"<table><thead><tr>{h}</tr></thead><tbody>{b}</tbody></table>"


def _ci(ci: tuple[float, float], k: float = 1.0, nd: int = 3) -> str:
    lo, hi = ci
    return "-" if not (math.isfinite(lo) and math.isfinite(hi)) else f"{lo * k:.{nd}g} - {hi * k:.{nd}g}"


def write_report(study: Study, rows: Sequence[dict], out_dir: Path) -> dict:
    """Write the report into ``out_dir``; returns {"index": path, "figures": [...], "tables": [...]}."""
    import matplotlib

    matplotlib.use("Agg")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = list(rows)
    tables = write_tables(rows, out_dir)
    figures: list[str] = []
    main = study.measures[0]
    parts: list[str] = []
    seeds_done = sorted({r["seed"] for r in rows})
    parts.append(f"<h1>Study {html.escape(study.name)}</h1>")
    if study.description:
        parts.append(f"<p>{html.escape(study.description)}</p>")
    parts.append(
        f"<p>{len(rows)} of {len(study.arms()) * len(study.seeds)} missions on file; "
        f"{len(study.arms())} arms; seeds run: {', '.join(map(str, seeds_done)) or 'none'} "
        f"(study file: {len(study.seeds)} seeds). Results: "
        + ", ".join(f'<a href="{t}">{t}</a>' for t in tables)
        + ".</p>"
    )
    # verdicts first
    ps_main = pairs(study, rows, main)
    parts.append(f"<h2>Verdicts ({html.escape(MEASURES[main][0])})</h2><ul>")
    parts += [f"<li>{html.escape(verdict(p))}</li>" for p in ps_main if p.seeds]
    parts.append("</ul>")
    ac = auto_check(study, rows, main)
    if ac:
        parts.append("<h2>auto against the better fixed tactic</h2>")
        body = [
            [r["scenario"], str(r["uavs"]), r["best"], str(len(r["pair"].seeds)), _fmt(100 * r["pair"].rel, 3) + " %",
             _ci(r["pair"].rel_ci, 100, 3) + " %", "worse" if r["worse"] else "not significantly worse"]
            for r in ac
        ]  # fmt: skip
        parts.append(
            _table(
                ["scenario", "UAVs", "better fixed", "paired seeds", "auto vs it", "95 % CI", "verdict"], body
            )
        )
    for name, fn in (
        ("burned_per_arm.png", lambda p: _fig_box(study, rows, main, p)),
        ("paired_differences.png", lambda p: _fig_pairs(study, ps_main, main, p)),
        ("containment.png", lambda p: _fig_containment(study, rows, p)),
        ("fleet_size.png", lambda p: _fig_fleet(study, rows, main, p)),
    ):
        fn(out_dir / name)
        figures.append(name)
    captions = {
        "burned_per_arm.png": f"{MEASURES[main][0]} per arm: box and every seed",
        "paired_differences.png": "paired differences B - A per seed (dots), mean and 95 % bootstrap CI (squares)",
        "containment.png": "time to containment, Kaplan-Meier (censored at the time limit): fraction contained by t",
        "fleet_size.png": f"mean {MEASURES[main][0]} over fleet size, 95 % bootstrap CI",
    }
    for f in figures:
        parts.append(
            f'<figure><img src="{f}" alt="{html.escape(captions[f])}"><figcaption>{html.escape(captions[f])}</figcaption></figure>'
        )
    # per-arm tables
    for m in study.measures:
        k, unit = _scale(m)
        body = []
        for arm in study.arms():
            s: ArmStats = arm_stats(rows, arm, m)
            body.append(
                [
                    arm.label(),
                    str(s.n),
                    _fmt(s.mean * k),
                    _ci(s.mean_ci, k),
                    _fmt(s.median * k),
                    _ci(s.median_ci, k),
                ]
            )
        parts.append(f"<h2>{html.escape(MEASURES[m][0])} [{unit}] per arm</h2>")
        parts.append(_table(["arm", "seeds", "mean", "95 % CI", "median", "95 % CI"], body))
    # containment table
    body = []
    for arm in study.arms():
        c = containment(rows, arm)
        body.append([arm.label(), f"{c.contained}/{c.n}", _fmt(c.median_s, 4), _fmt(c.limit_s, 4)])
    parts.append("<h2>Containment (Kaplan-Meier)</h2>")
    parts.append(_table(["arm", "contained", "median time [s]", "time limit [s]"], body))
    # pairs, every measure
    for m in study.measures:
        k, unit = _scale(m)
        body = [
            [f"{p.a.scenario} {p.a.uavs}", f"{p.b.tactic} - {p.a.tactic}", str(len(p.seeds)), _fmt(p.mean_diff * k),
             _ci(p.mean_diff_ci, k), _fmt(100 * p.rel) + " %", _ci(p.rel_ci, 100) + " %", _fmt(p.wilcoxon_p, 2)]
            for p in pairs(study, rows, m) if p.seeds
        ]  # fmt: skip
        parts.append(f"<h2>Paired differences: {html.escape(MEASURES[m][0])} [{unit}]</h2>")
        parts.append(
            _table(
                ["group", "B - A", "seeds", "mean diff", "95 % CI", "relative", "95 % CI", "Wilcoxon p"], body
            )
        )
    parts.append(
        "<p>Method: per arm bootstrap CIs (scipy.stats.bootstrap, 9999 resamples; percentile below 8 seeds, "
        "BCa from 8); paired differences over the seeds both arms ran, paired bootstrap CI and Wilcoxon "
        "signed-rank (scipy.stats.wilcoxon); containment Kaplan-Meier (statsmodels SurvfuncRight), a mission "
        "never contained censored at its time limit (in the paired time comparison it counts at the limit). "
        'A verdict says "no detectable difference" when the CI of the relative difference spans zero.</p>'
    )
    style = (
        "body{font-family:sans-serif;max-width:1200px;margin:auto;padding:1em}"
        "table{border-collapse:collapse;margin:0.5em 0 1.5em}td,th{border:1px solid #ccc;padding:2px 6px;"
        "font-size:13px;text-align:right}td:first-child{text-align:left}img{max-width:100%}"
    )
    page = (
        f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>Study {html.escape(study.name)}</title>"
        f"<style>{style}</style></head><body>\n" + "\n".join(parts) + "\n</body></html>\n"
    )
    (out_dir / "index.html").write_text(page, encoding="utf-8")
    return {"index": str(out_dir / "index.html"), "figures": figures, "tables": tables}
