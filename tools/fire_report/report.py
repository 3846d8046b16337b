"""metrics.json + figures + index.html for one bag."""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import Any

from fire_report.data import load_mission
from fire_report.errors import ReportError
from fire_report.figures import make_figures
from fire_report.metrics import compute_metrics
from fire_report.sections import Section, make_sections, render_section

META_ROWS = (
    ("scenario file", "fire_uav.scenario_file"),
    ("seed", "fire_uav.seed"),
    ("fleet size", "fire_uav.uav_count"),
    ("software", "fire_uav.software_version"),
    ("recorder started (UTC)", "fire_uav.recorder_started_utc"),
    ("closed cleanly", "fire_uav.closed_cleanly"),
)
SUMMARY_KEYS = (
    "outcome",
    "outcome_detail",
    "mission_duration_s",
    "drop_count",
    "drops_per_fire",
    "mean_inter_drop_interval_s",
    "extinction_times_s",
    "crash_events",
    "peers_declared_crashed",
    "packets_lost_total",
    "packets_rejected_total",
    "perimeter_distance_error_m",
    "hit_rate",
    "burned_area_m2",
    "contained_at_s",
    "water_on_burning_kg",
)


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.3f}"
    if isinstance(v, (dict, list)):
        return json.dumps(v, default=str)
    return str(v)


def render_html(
    metrics: dict[str, Any],
    custom: dict[str, str],
    figures: list[tuple[str, str]],
    sections: list[Section] | None = None,
) -> str:
    """One self-contained page: metadata, summary metrics, EKF table, every figure, then one
    section per capability the mission used (``fire_report.sections``)."""
    e = html.escape
    rows = "".join(f"<tr><th>{e(k)}</th><td>{e(custom.get(key, '-'))}</td></tr>" for k, key in META_ROWS)
    summ = "".join(f"<tr><th>{e(k)}</th><td>{e(_fmt(metrics.get(k)))}</td></tr>" for k in SUMMARY_KEYS)
    ekf = metrics.get("ekf_error", {})
    ekf_rows = "".join(
        f"<tr><th>{e(ax)} [{e(ekf['units'][ax])}]</th>"
        + "".join(f"<td>{_fmt((ekf.get(ax) or {}).get(p, '-'))}</td>" for p in ("p50", "p90", "p95", "max"))
        + "</tr>"
        for ax in ("x", "y", "z", "yaw", "horizontal")
    )
    warns = "".join(f"<li>{e(w)}</li>" for w in metrics.get("warnings", []))
    figs = "".join(
        f'<figure><img src="{e(name)}" alt="{e(cap)}"><figcaption>{e(cap)}</figcaption></figure>'
        for name, cap in figures
    )
    title = f"Mission report: {metrics.get('scenario') or metrics.get('bag')}"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{e(title)}</title>
<style>body{{font-family:sans-serif;max-width:1200px;margin:auto;padding:1em}}
table{{border-collapse:collapse;margin-bottom:1em}}th,td{{border:1px solid #ccc;padding:3px 8px;text-align:left}}
figure{{margin:1.5em 0}}img{{max-width:100%}}figcaption{{color:#444}}.warn{{color:#a40}}</style></head>
<body><h1>{e(title)}</h1>
<p>Bag: <code>{e(str(metrics.get("bag")))}</code> &middot; <a href="metrics.json">metrics.json</a></p>
{f'<ul class="warn">{warns}</ul>' if warns else ""}
<h2>Recording</h2><table>{rows}</table>
<h2>Summary</h2><table>{summ}</table>
<h2>EKF error (|estimate - truth|, {ekf.get("samples", 0)} samples)</h2>
<table><tr><th></th><th>p50</th><th>p90</th><th>p95</th><th>max</th></tr>{ekf_rows}</table>
<h2>Figures</h2>{figs or "<p>No figure: the bag holds none of the topics they need.</p>"}
{"".join(render_section(s) for s in sections or [])}
</body></html>
"""


def write_report(
    bag: str | Path, out_dir: str | Path, *, salvage: bool = True, baseline: str | Path | None = None
) -> dict[str, Any]:
    """Read ``bag`` and write metrics.json, the PNG figures and index.html into ``out_dir``.

    ``baseline``: a bag of the same scenario and seed with no fleet (``--uavs 0``) for the
    burned-area comparison (``baseline_burned_area_m2`` and the figure)."""
    mission = load_mission(bag, salvage=salvage)
    base = load_mission(baseline, salvage=salvage) if baseline is not None else None
    out = Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise ReportError(f"{out}: cannot create the output directory: {err.strerror}") from None
    metrics = compute_metrics(mission)
    if base is not None:
        from fire_report.metrics import suppression_metrics

        metrics["baseline_burned_area_m2"] = suppression_metrics(base)["burned_area_m2"]
    figures = make_figures(mission, out, base)
    sections = make_sections(mission, out, salvage=salvage)
    metrics["figures"] = [name for name, _ in figures] + [name for s in sections for name, _ in s.figures]
    metrics["sections"] = {s.key: s.metrics for s in sections}
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2, default=str) + "\n", encoding="utf8")
    page = render_html(metrics, mission.custom_data, figures, sections)
    (out / "index.html").write_text(page, encoding="utf8")
    return metrics
