"""index.html of the report: a debrief that opens with the outcome, then the timeline, fires,
UAVs, safety, faults and capability sections, with the estimator diagnostics last.

Every number shown comes from ``metrics`` (metrics.json) or :mod:`fire_report.debrief`; this
module only words and formats them (units in every label, no code names, no JSON).
"""

from __future__ import annotations

import html
import math
from typing import Any

from fire_report.debrief import Entry, Fault
from fire_report.sections import Figure, Section

e = html.escape
DASH = "\u2013"

STYLE = """
:root{--ink:#1d2430;--muted:#5b6472;--line:#dde1e7;--bg:#f6f7f9;--ok:#1f7a3d;--bad:#b3261e;--warn:#9a5b00;
--accent:#c2410c}
*{box-sizing:border-box}
body{margin:0;font:15px/1.5 system-ui,-apple-system,"Segoe UI",Roboto,Helvetica,Arial,sans-serif;color:var(--ink);
background:var(--bg)}
header{background:#fff;border-bottom:1px solid var(--line)}
.wrap{max-width:1080px;margin:0 auto;padding:0 20px}
header .wrap{padding-top:18px;padding-bottom:10px}
h1{font-size:1.6em;margin:0 0 2px}
.sub{color:var(--muted);margin:0 0 10px}
nav{display:flex;flex-wrap:wrap;gap:4px 14px;font-size:.93em}
nav a{color:var(--accent);text-decoration:none}nav a:hover{text-decoration:underline}
section{background:#fff;border:1px solid var(--line);border-radius:8px;margin:18px 0;padding:6px 20px 14px}
h2{font-size:1.25em;margin:12px 0 8px}
h3{font-size:1.02em;margin:14px 0 6px}
p.lead{color:var(--muted);margin:4px 0 10px}
.banner{border-radius:6px;padding:10px 14px;margin:12px 0;font-weight:600}
.banner.ok{background:#e8f5ec;color:var(--ok)}.banner.bad{background:#fdecea;color:var(--bad)}
.banner.warn{background:#fff4e0;color:var(--warn)}
.cards{display:grid;grid-template-columns:repeat(auto-fill,minmax(190px,1fr));gap:10px;margin:8px 0 6px}
.card{border:1px solid var(--line);border-radius:6px;padding:8px 12px}
.card .k{display:block;color:var(--muted);font-size:.85em}.card .v{display:block;font-size:1.15em;font-weight:600}
.card a{color:inherit;text-decoration:none}
.scroll{overflow-x:auto}
table{border-collapse:collapse;margin:6px 0 10px;font-size:.93em}
th,td{border-bottom:1px solid var(--line);padding:4px 10px;text-align:left;vertical-align:top}
thead th{background:var(--bg);font-weight:600}
td.num,th.num{text-align:right;font-variant-numeric:tabular-nums}
table.timeline td:first-child{white-space:nowrap;text-align:right;font-variant-numeric:tabular-nums;color:var(--muted)}
tr.loss td:last-child{color:var(--bad);font-weight:600}tr.fault td:last-child{color:var(--warn)}
tr.end td:last-child{font-weight:600}
ul.faults{padding-left:18px}ul.faults li{margin:0 0 8px}
figure{margin:14px 0}
figure img{display:block;max-width:100%;height:auto;border:1px solid var(--line);border-radius:4px}
figcaption{color:var(--muted);font-size:.9em;margin-top:4px;max-width:75ch}
.warn{color:var(--warn)}
footer{color:var(--muted);font-size:.85em;padding:10px 0 30px}
code{font-size:.9em}
"""


def fmt(v: Any, digits: int = 1, unit: str = "") -> str:
    """A number for people: rounded, thousands separated, with its unit; None -> a dash."""
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return DASH
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        text = f"{v:,}"
    elif isinstance(v, float):
        text = f"{v:,.{digits}f}"
    else:
        text = str(v)
    return f"{text} {unit}" if unit else text


def _figure(name: str, caption: str) -> str:
    return f'<figure><img src="{e(name)}" alt="{e(caption)}"><figcaption>{e(caption)}</figcaption></figure>'


def _table(head: list[str], rows: list[list[str]], cls: str = "", numeric: set[int] | None = None) -> str:
    numeric = numeric or set()
    th = "".join(f"<th{' class=num' if i in numeric else ''}>{e(h)}</th>" for i, h in enumerate(head))
    body = "".join(
        "<tr>"
        + "".join(f"<td{' class=num' if i in numeric else ''}>{e(c)}</td>" for i, c in enumerate(r))
        + "</tr>"
        for r in rows
    )
    return f'<div class="scroll"><table class="{cls}"><thead><tr>{th}</tr></thead><tbody>{body}</tbody></table></div>'


def _section(key: str, title: str, body: str) -> str:
    return f'<section id="{e(key)}"><h2>{e(title)}</h2>{body}</section>'


# --- the summary ---------------------------------------------------------------------------------
def outcome_banner(m: dict[str, Any]) -> str:
    result, detail = m.get("outcome"), m.get("outcome_detail") or ""
    if result == "complete":
        return f'<div class="banner ok">Mission complete at {fmt(m.get("mission_duration_s"), 1, "s")}: {e(detail)}.</div>'
    if result == "time_limit":  # the world's detail names its parameter: say it in words
        total, active = m.get("fires_total"), m.get("fires_active_at_end")
        left = f", {active} of {total} fires still burning" if total else ""
        return (
            f'<div class="banner warn">The mission reached its time limit at '
            f"{fmt(m.get('mission_duration_s'), 1, 's')}{left}.</div>"
        )
    return (
        '<div class="banner bad">The recording ended before the mission did '
        f"(last message at {fmt(m.get('mission_duration_s'), 1, 's')}).</div>"
    )


def summary_cards(
    m: dict[str, Any], uavs: list[dict[str, Any]], faults: list[Fault], raster: bool
) -> list[tuple[str, str, str]]:
    """(label, value, link to the section that explains it) for the summary grid."""
    cards: list[tuple[str, str, str]] = []
    total, active = m.get("fires_total"), m.get("fires_active_at_end")
    if total:
        out = total - (active or 0)
        cards.append(("fires put out", f"{out} of {total}", "#fires"))
    cards.append(("mission time", fmt(m.get("mission_duration_s"), 1, "s"), "#timeline"))
    n = len(uavs)
    if n:
        drops, hit = m.get("drop_count", 0), m.get("hit_rate")
        cards.append(
            (
                "water drops",
                f"{drops}" + (f" ({hit * 100:.0f} % on a fire)" if hit is not None else ""),
                "#fires",
            )
        )
        landed = len(m.get("landed") or [])
        lost = [u for u in uavs if u["end"].startswith("lost")]
        inj = sum("(injected)" in u["end"] for u in lost)
        text = f"{landed} of {n} landed"
        if lost:
            text += f", {len(lost)} lost ({inj} injected)" if inj else f", {len(lost)} lost"
        cards.append(("UAVs", text, "#uavs"))
        sep = m.get("min_separation_m")
        col = m.get("collisions", 0)
        if sep is not None:
            cards.append(
                (
                    "closest approach",
                    f"{sep:.1f} m, " + ("no collision" if not col else f"{col} collision(s)"),
                    "#safety",
                )
            )
        recv = sum(p["received"] for p in m.get("packets", {}).values())
        lost_p = m.get("packets_lost_total", 0)
        if recv + lost_p:
            cards.append(
                (
                    "peer messages lost",
                    f"{lost_p:,} of {recv + lost_p:,} ({100 * lost_p / (recv + lost_p):.1f} %)",
                    "#faults",
                )
            )
    if faults:
        cards.append(("faults injected", str(len(faults)), "#faults"))
    if raster:
        cards.append(("burned area", fmt((m.get("burned_area_m2") or 0.0) / 1e4, 2, "ha"), "#fires"))
        c = m.get("contained_at_s")
        cards.append(("contained", "not contained" if c is None else f"at {c:.1f} s", "#fires"))
        if m.get("baseline_burned_area_m2") is not None:
            cards.append(
                ("burned area with no fleet", fmt(m["baseline_burned_area_m2"] / 1e4, 2, "ha"), "#fires")
            )
    return cards


# --- the body ------------------------------------------------------------------------------------
def timeline_html(entries: list[Entry]) -> str:
    if not entries:
        return "<p>No event in the recording.</p>"
    rows = "".join(
        f'<tr class="{e(x.kind)}"><td>{x.t_s:.1f} s</td><td>{e(x.text)}</td></tr>' for x in entries
    )
    return (
        '<div class="scroll"><table class="timeline"><thead><tr><th>time</th><th>what happened</th></tr></thead>'
        f"<tbody>{rows}</tbody></table></div>"
    )


def fires_html(rows: list[dict[str, Any]], raster: bool) -> str:
    if not rows:
        return "<p>No fire in the recording.</p>"
    head = [
        "fire",
        "position x, y [m]",
        "started [s]",
        "first seen [s]",
        "drops",
        "first drop [s]",
        "out at [s]",
    ]
    if any(r.get("lat_deg") is not None for r in rows):
        head[1] = "position x, y [m] (latitude, longitude [\u00b0])"
    if raster:
        head.append("burned [ha]")
    head.append("at the end")
    body = []
    for r in rows:
        seen = DASH if r["detected_s"] is None else f"{r['detected_s']:.1f} (UAV {r['detected_by']})"
        pos = DASH if r["x_m"] is None else f"{r['x_m']:.0f}, {r['y_m']:.0f}"
        if r.get("lat_deg") is not None:  # a mission on a landscape: where it is on the Earth too
            pos += f" ({latlon_text(r['lat_deg'], r['lon_deg'])})"
        row = [
            str(r["fire"]),
            pos,
            fmt(r["started_s"]),
            seen,
            str(r["drops"]),
            fmt(r["first_drop_s"]),
            fmt(r["out_s"]),
        ]
        if raster:
            row.append(fmt(r.get("burned_ha"), 2))
        row.append("burning" if r["burning_at_end"] else "out")
        body.append(row)
    return _table(head, body, numeric={2, 4, 5, 6})


def latlon_text(lat: float, lon: float) -> str:
    """WGS84 degrees for people: "44.372100, -72.558300" (latitude first, as map tools take it)."""
    return f"{lat:.6f}, {lon:.6f}"


MAX_PLACE_DROPS = 40  # more drops than this: their positions only in metrics.json


def places_html(rows: list[dict[str, Any]], landscape: str) -> str:
    """The places of a mission on a landscape (``fire_report.ground.places``) with latitude and
    longitude: ignitions, fires, lakes, UAV homes, drops, UAVs lost."""
    drops = [r for r in rows if r.get("kind") == "drop"]
    shown = [r for r in rows if r.get("kind") != "drop" or len(drops) <= MAX_PLACE_DROPS]
    body = [
        [
            r["what"],
            fmt(r["t_s"]),
            f"{r['x_m']:.0f}, {r['y_m']:.0f}",
            f"{r['lat_deg']:.6f}",
            f"{r['lon_deg']:.6f}",
        ]
        for r in shown
    ]
    lead = (
        f"<p class=lead>The mission flew on the landscape {e(landscape)}: each position in metres on the "
        "scenario's map and in WGS84 latitude and longitude (degrees; north and east positive), for "
        "map tools and people on the ground.</p>"
    )
    note = (
        f"<p>{len(drops)} drops: their positions are in metrics.json (geo.places).</p>"
        if len(drops) > MAX_PLACE_DROPS
        else ""
    )
    head = ["what", "time [s]", "x, y [m]", "latitude [\u00b0]", "longitude [\u00b0]"]
    return lead + _table(head, body, numeric={1, 3, 4}) + note


def fire_types_html(m: dict[str, Any]) -> str:
    """Burnt cells per fire type (a fire on a landscape with crown fire; '' for any other), and
    what the scenario's loader noted about the ground (water left out as too small to refill)."""
    notes = "".join(f"<p>Ground: {e(n)}</p>" for n in m.get("scenario_notes") or [])
    cells = m.get("fire_type_cells")
    if not cells:
        return notes
    total = sum(cells.values())
    ha = (m.get("fire_type_cell_m") or 0.0) ** 2 / 1e4
    names = {"surface": "surface", "passive_crown": "passive crown", "active_crown": "active crown"}
    body = [
        [names[k], str(n), fmt(n * ha, 2), fmt(100.0 * n / total if total else None, 1)]
        for k, n in cells.items()
    ]
    return notes + (
        "<p>How the burnt cells burned (the world's fire type per cell: Van Wagner initiation, "
        "Finney's method):</p>"
        + _table(["fire type", "cells", "area [ha]", "share [%]"], body, numeric={1, 2, 3})
    )


def uavs_html(rows: list[dict[str, Any]]) -> str:
    if not rows:
        return "<p>No UAV flew in this mission.</p>"
    head = ["UAV", "took off [s]", "drops", "water dropped [kg]", "how it ended", "landing error [m]",
            "peer messages received / lost", "position error, 95 % [m]"]  # fmt: skip
    body = [
        [
            str(r["uav"]),
            fmt(r["takeoff_s"]),
            str(r["drops"]),
            fmt(r["water_kg"], 0),
            r["end"],
            fmt(r["landing_error_m"], 2),
            DASH if r["received"] is None else f"{r['received']:,} / {r['lost']:,}",
            fmt(r["position_error_p95_m"], 2),
        ]  # fmt: skip
        for r in rows
    ]
    return _table(head, body, numeric={1, 2, 3, 5, 7})


def safety_html(m: dict[str, Any], collision_radius_m: float | None) -> str:
    sep, col = m.get("min_separation_m"), m.get("collisions", 0)
    rows = [
        ["closest approach of two flying UAVs", DASH if sep is None else f"{sep:.2f} m"],
        ["collisions (pairs closer than " + (f"{collision_radius_m:g} m" if collision_radius_m else "the collision radius") + ")", str(col)],
        ["UAVs landed", ", ".join(str(u) for u in m.get("landed") or []) or "none"],
        ["closest two touchdown points", fmt(m.get("touchdown_spacing_m"), 2, "m")],
    ]  # fmt: skip
    body = _table(["", ""], rows)
    err = m.get("landing_error_m") or {}
    if err:
        body += "<h3>Landing error: distance from touchdown to takeoff point</h3>"
        body += _table(["UAV", "landing error [m]"], [[k, f"{v:.2f}"] for k, v in err.items()], numeric={1})
    return body


def faults_html(faults: list[Fault], m: dict[str, Any], figures: list[Figure]) -> str:
    loss = m.get("loss_probability")
    parts = []
    if faults:
        items = "".join(
            f"<li><strong>{e(f.title)}</strong> ({e(f.source)}): {e(f.response)}</li>" for f in faults
        )
        parts.append(f'<ul class="faults">{items}</ul>')
    elif m.get("injected_faults_known", True):
        parts.append("<p>No fault was injected (no kill, freeze, stall or link outage).</p>")
    if not m.get("injected_faults_known", True):
        parts.append(
            "<p>The run's summary (summary.json, beside the bag when the mission runner recorded it) "
            "is not there: faults injected from the command line are not known, only the scenario's.</p>"
        )
    if loss is not None:
        parts.append(
            f"<p>Every peer message was also dropped at random with probability {loss:g} on receipt.</p>"
        )
    parts += [_figure(n, c) for n, c in figures]
    return "".join(parts)


def ekf_html(m: dict[str, Any]) -> str:
    ekf = m.get("ekf_error", {})
    if not ekf.get("samples"):
        return ""
    names = {
        "x": "east (x)",
        "y": "north (y)",
        "z": "height (z)",
        "yaw": "heading",
        "horizontal": "horizontal",
    }
    rows = []
    for ax in ("horizontal", "x", "y", "z", "yaw"):
        p = ekf.get(ax) or {}
        unit = ekf["units"][ax]
        rows.append([f"{names[ax]} [{unit}]", *(fmt(p.get(k), 3) for k in ("p50", "p90", "p95", "max"))])
    return (
        "<h3>Own position estimate</h3>"
        "<p class=lead>How far each UAV's estimate of where it was (its Kalman filter, fed by GPS, altimeter "
        f"and gyro) was from the truth while it flew, over {ekf['samples']:,} samples of all UAVs: half of the "
        "samples were within the median, 95 in 100 within the 95th percentile.</p>"
        + _table(["error", "median", "90 %", "95 %", "largest"], rows, numeric={1, 2, 3, 4})
    )


def capability_html(s: Section) -> str:
    rows = _table(["", ""], [[k, v] for k, v in s.rows]) if s.rows else ""
    notes = "".join(f"<li>{e(n)}</li>" for n in s.notes)
    return (
        f'<section id="{e(s.key)}"><h2>{e(s.heading)}</h2>'
        + rows
        + (f"<ul>{notes}</ul>" if notes else "")
        + "".join(_figure(n, c) for n, c in s.figures)
        + "</section>"
    )


def render_page(
    m: dict[str, Any],
    custom: dict[str, str],
    *,
    entries: list[Entry],
    fires: list[dict[str, Any]],
    uavs: list[dict[str, Any]],
    faults: list[Fault],
    figures: dict[str, list[Figure]],
    sections: list[Section],
    raster: bool,
    collision_radius_m: float | None,
    places: list[dict[str, Any]] | None = None,
    landscape: str | None = None,
) -> str:
    """The whole page. ``figures``: PNGs per part of the page ("maps", "fires", "faults", "diagnostics");
    ``places`` and ``landscape``: a mission on a landscape (positions in latitude and longitude too)."""
    title = f"Mission debrief: {m.get('scenario') or 'unnamed scenario'}"
    n = m.get("uav_count") or 0
    sub = [f"{n} UAV{'s' * (n != 1)}" if n else "no fleet (fire alone)"]
    if m.get("seed") is not None:
        sub.append(f"seed {m['seed']}")
    if custom.get("fire_uav.recorder_started_utc"):
        sub.append(f"recorded {custom['fire_uav.recorder_started_utc']}")
    subline = " \u00b7 ".join(sub)
    parts: list[tuple[str, str, str]] = []  # (anchor, nav label, html)
    cards = "".join(
        f'<div class="card"><a href="{e(link)}"><span class="k">{e(k)}</span><span class="v">{e(v)}</span></a></div>'
        for k, v, link in summary_cards(m, uavs, faults, raster)
    )
    warns = "".join(f"<li>{e(w)}</li>" for w in m.get("warnings", []))
    summary = outcome_banner(m) + f'<div class="cards">{cards}</div>'
    if warns:
        summary += f'<ul class="warn">{warns}</ul>'
    parts.append(("summary", "Summary", summary))
    parts.append(("timeline", "Timeline", timeline_html(entries)))
    if figures.get("maps"):
        parts.append(("maps", "The fleet on the map", "".join(_figure(*f) for f in figures["maps"])))
    parts.append(
        (
            "fires",
            "Fires",
            fires_html(fires, raster)
            + fire_types_html(m)
            + "".join(_figure(*f) for f in figures.get("fires", [])),
        )
    )
    if places and landscape:
        parts.append(("places", "Where on the ground", places_html(places, landscape)))
    if uavs:
        parts.append(("uavs", "UAVs", uavs_html(uavs)))
        parts.append(("safety", "Safety", safety_html(m, collision_radius_m)))
    if uavs or faults:
        parts.append(
            ("faults", "Faults and how the fleet answered", faults_html(faults, m, figures.get("faults", [])))
        )
    diag = ekf_html(m) + "".join(_figure(*f) for f in figures.get("diagnostics", []))
    meta = _table(
        ["", ""],
        [[k, custom.get(key, DASH)] for k, key in (
            ("scenario file", "fire_uav.scenario_file"), ("seed", "fire_uav.seed"),
            ("fleet size", "fire_uav.uav_count"), ("software", "fire_uav.software_version"),
            ("recorder started (UTC)", "fire_uav.recorder_started_utc"), ("closed cleanly", "fire_uav.closed_cleanly"),
        )],
    )  # fmt: skip
    nav_items = [(a, label) for a, label, _ in parts] + [(s.key, s.heading) for s in sections]
    if diag:
        nav_items.append(("diagnostics", "Diagnostics"))
    nav_items.append(("recording", "Recording"))
    nav = "".join(f'<a href="#{e(a)}">{e(label)}</a>' for a, label in nav_items)
    body = "".join(_section(a, label, h) for a, label, h in parts)
    body += "".join(capability_html(s) for s in sections)
    if diag:
        body += _section(
            "diagnostics",
            "Diagnostics",
            "<p class=lead>How well the estimators worked: each UAV's own position filter and the fleet's "
            "shared picture of the fires. For checking the algorithms, not the mission.</p>" + diag,
        )
    body += _section(
        "recording",
        "Recording",
        f"<p>Bag: <code>{e(str(m.get('bag')))}</code> &middot; every number of this page: "
        f'<a href="metrics.json">metrics.json</a></p>' + meta,
    )
    geo_note = (
        f", and latitude, longitude in WGS84 degrees from the landscape {e(landscape)}" if landscape else ""
    )
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width, initial-scale=1">
<title>{e(title)}</title><style>{STYLE}</style></head>
<body><header><div class="wrap"><h1>{e(title)}</h1><p class="sub">{e(subline)}</p>
<nav>{nav}</nav></div></header>
<main class="wrap">{body}</main>
<footer class="wrap">Times are simulated mission seconds from the start; positions are metres east (x) and
north (y) on the scenario's map{geo_note}.</footer>
</body></html>
"""
