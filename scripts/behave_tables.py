#!/usr/bin/env python3
"""Reference Rothermel tables from Behave (its C++ core through the ``pyrothermel`` bindings).

Offline only, not part of the tests or CI (the tests read the committed CSVs). Regenerate with:

    pip install pyrothermel==0.1.4
    python scripts/behave_tables.py > ros2_ws/src/fire_world_sim/test/data/behave_tables.csv
    python scripts/behave_tables.py landscape > ros2_ws/src/fire_world_sim/test/data/behave_53.csv
    python scripts/behave_tables.py crown > ros2_ws/src/fire_world_sim/test/data/behave_crown.csv

and the agreement table in the docs (needs no Behave: it reads the CSVs and runs our model, so it
runs in the project's environment):

    source scripts/env.sh && python scripts/behave_tables.py agreement > docs/behave_agreement.md

``landscape`` (all 53 standard models, per cell as the landscape command computes them): five
moisture scenarios (1-h, 10-h, 100-h, live herbaceous, live woody; herbaceous 30-150 % so that the
dynamic models' transfer is crossed), 20-ft wind 0, 5, 10, 20 mi/h from the south-west, slope 0 and
40 % facing south, and two canopies for the wind adjustment factor (none; cover 50 %, height 15 m,
crown ratio 0.6). Columns: the inputs, Behave's head rate [ft/min], its direction [deg from north],
Byram's fireline intensity [Btu/ft/s], flame length [ft] and midflame wind [mi/h].

``crown`` (Scott & Reinhardt 2001 run of Behave; pyrothermel's default metric units, the only ones
its crown module reads consistently, with the fuel model taken in US units, the only ones its
``FuelModel.from_existing`` converts right): fuel models 10, 145, 165, 183, 188 under 20-ft winds 10-60
km/h, canopy base heights 1-6 m, bulk densities 0.05-0.3 kg/m^3, foliar moisture 90 / 120 %.
Columns: the inputs, Behave's surface rate [km/h] and intensity [kW/m], its transition ratio
(I_B / I_0), active ratio (R_cactive / R'_active), fire type and final rate [km/h], intensity
[kW/m] and flame length [m].

Grid: standard fuel models 1-13; dead fuel moisture m = 3, 6, 9, 12 % (1-h m, 10-h m + 1 %,
100-h m + 2 %, as the raster fire derives them from ``moisture``); live herbaceous and woody
moisture 100 %; midflame wind 0, 2, 4, 6, 8, 10 mi/h (``direct_midflame``, no wind adjustment
factor); slope 0, 15, 30 %; wind blowing upslope (``cross`` = 0) or across the slope, toward
90 deg clockwise of upslope (``cross`` = 1, slope > 0 and wind > 0 only).

Columns: fuel model, dead moisture [fraction], midflame wind [mi/h], slope [%], cross, head
rate of spread [ft/min], backing rate of spread [ft/min] (Behave's rate in the direction
opposite the head, from the ignition point), head direction [deg clockwise from upslope],
and the length-to-width ratio of Behave's spread ellipse derived from the two rates:
``e = (R_head - R_back) / (R_head + R_back)``, ``L/W = 1 / sqrt(1 - e^2)`` (Behave's ellipse has
the ignition at its rear focus, so this is exactly the ratio Behave uses internally).
Behave applies Rothermel's (1972) wind limit (effective wind <= 0.9 I_R).
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

try:
    import pyrothermel as pr
    from pyrothermel import units
except ImportError:  # the agreement table needs only the committed CSVs
    pr = None

MOISTURES = (0.03, 0.06, 0.09, 0.12)
WINDS_MPH = (0.0, 2.0, 4.0, 6.0, 8.0, 10.0)
SLOPES_PCT = (0.0, 15.0, 30.0)
ASPECT_DEG = 180.0  # slope faces south: upslope is north (0 deg)


def run(fm: int, m: float, wind_mph: float, slope_pct: float, cross: int) -> tuple[float, float, float]:
    u = pr.UnitsPreset.us_standard()
    u.slope_units = units.SlopeUnits.Percent
    u.spread_rate_units = units.SpeedUnits.FeetPerMinute
    fuel = pr.FuelModel.from_existing(fm, units_preset=u)
    ms = pr.MoistureScenario(m, m + 0.01, m + 0.02, 1.0, 1.0)
    # Behave's wind direction is where the wind comes FROM: from the south blows upslope (north),
    # from the west blows east (90 deg clockwise of upslope)
    wind_from = 270.0 if cross else 180.0
    r = pr.PyrothermelRun(
        fuel,
        ms,
        wind_mph,
        units_preset=u,
        wind_input_mode="direct_midflame",
        wind_direction=wind_from,
        slope=slope_pct,
        aspect=ASPECT_DEG,
    )
    head = r.run_surface_fire_in_direction_of_max_spread()
    direction = float(head["direction"])
    back = r.run_surface_fire_in_direction_of_interest((direction + 180.0) % 360.0)
    return float(head["spread_rate"]), float(back["spread_rate"]), direction


LANDSCAPE_MODELS = (*range(1, 14), *range(101, 110), *range(121, 125), *range(141, 150))
LANDSCAPE_MODELS = (*LANDSCAPE_MODELS, *range(161, 166), *range(181, 190), *range(201, 205))
LANDSCAPE_MOISTURES = (
    (0.03, 0.04, 0.05, 0.30, 0.60),
    (0.06, 0.08, 0.10, 0.75, 0.60),
    (0.06, 0.07, 0.08, 0.60, 0.90),
    (0.09, 0.10, 0.11, 1.20, 1.50),
    (0.12, 0.13, 0.14, 1.50, 1.50),
)
LANDSCAPE_WINDS_MPH = (0.0, 5.0, 10.0, 20.0)
LANDSCAPE_SLOPES_PCT = (0.0, 40.0)
LANDSCAPE_CANOPIES = ((0.0, 0.0, 0.0), (0.5, 15.0, 0.6))  # cover [fraction], height [m], crown ratio
WIND_FROM_DEG = 225.0


def landscape() -> None:
    u = pr.UnitsPreset.us_standard()
    u.slope_units = units.SlopeUnits.Percent
    u.spread_rate_units = units.SpeedUnits.FeetPerMinute
    out = sys.stdout
    out.write("# Behave (pyrothermel 0.1.4) 53-model table, made by scripts/behave_tables.py landscape\n")
    out.write(
        "fuel_model,m1h,m10h,m100h,mherb,mwoody,wind20_mph,wind_from_deg,slope_pct,aspect_deg,"
        "canopy_cover,canopy_height_m,crown_ratio,head_ft_min,head_dir_deg,fli_btu_ft_s,flame_ft,midflame_mph\n"
    )
    for fm in LANDSCAPE_MODELS:
        for ms in LANDSCAPE_MOISTURES:
            for w in LANDSCAPE_WINDS_MPH:
                for s in LANDSCAPE_SLOPES_PCT:
                    for cc, ch, cr in LANDSCAPE_CANOPIES:
                        fuel = pr.FuelModel.from_existing(fm, units_preset=u)
                        r = pr.PyrothermelRun(
                            fuel,
                            pr.MoistureScenario(*ms),
                            w,
                            units_preset=u,
                            wind_input_mode="twenty_foot",
                            wind_direction=WIND_FROM_DEG,
                            slope=s,
                            aspect=ASPECT_DEG,
                            canopy_cover=cc,
                            canopy_height=ch / 0.3048,
                            canopy_ratio=cr,
                        )
                        h = r.run_surface_fire_in_direction_of_max_spread()
                        m = ",".join(f"{v:g}" for v in ms)
                        out.write(
                            f"{fm},{m},{w:g},{WIND_FROM_DEG:g},{s:g},{ASPECT_DEG:g},{cc:g},{ch:g},{cr:g},"
                            f"{h['spread_rate']:.6g},{h['direction']:.4f},{h['fireline_intensity']:.6g},"
                            f"{h['flame_length']:.6g},{h['midflame_windspeed']:.6g}\n"
                        )


CROWN_MODELS = (10, 145, 165, 183, 188)
CROWN_WINDS_KMH = (10.0, 20.0, 30.0, 40.0, 60.0)
CROWN_CBH_M = (1.0, 3.0, 6.0)
CROWN_CBD = (0.05, 0.15, 0.30)
CROWN_FOLIAR = (0.9, 1.2)
CROWN_MOISTURE = (0.06, 0.08, 0.10, 0.75, 0.60)
CROWN_CANOPY = (0.5, 15.0)  # cover [fraction], height [m]


def crown() -> None:
    out = sys.stdout
    out.write("# Behave (pyrothermel 0.1.4) crown table, made by scripts/behave_tables.py crown\n")
    out.write(
        "fuel_model,wind20_kmh,cbh_m,cbd_kgm3,foliar,canopy_cover,canopy_height_m,surface_kmh,surface_fli_kwm,"
        "transition_ratio,active_ratio,fire_type,final_kmh,final_fli_kwm,final_flame_m\n"
    )
    cc, ch = CROWN_CANOPY
    for fm in CROWN_MODELS:
        for w in CROWN_WINDS_KMH:
            for cbh in CROWN_CBH_M:
                for cbd in CROWN_CBD:
                    for fmc in CROWN_FOLIAR:
                        r = pr.PyrothermelRun(
                            # the fuel model in US units: pyrothermel 0.1.4's metric from_existing
                            # gives other fuel parameters (FM1 spreads 2.3x faster)
                            pr.FuelModel.from_existing(fm, units_preset=pr.UnitsPreset.us_standard()),
                            pr.MoistureScenario(*CROWN_MOISTURE, foliar_moisture=fmc),
                            w,
                            wind_input_mode="twenty_foot",
                            canopy_cover=cc,
                            canopy_height=ch,
                            canopy_ratio=(ch - cbh) / ch,
                            canopy_base_height=cbh,
                            canopy_bulk_density=cbd,
                        )
                        s = r.run_surface_fire_in_direction_of_max_spread()
                        c = r.run_crown_fire_scott_and_reinhardt()
                        out.write(
                            f"{fm},{w:g},{cbh:g},{cbd:g},{fmc:g},{cc:g},{ch:g},{s['spread_rate']:.6g},"
                            f"{s['fireline_intensity']:.6g},{c['transition_ratio']:.6g},{c['active_ratio']:.6g},"
                            f"{c['fire_type']},{c['spread_rate']:.6g},{c['fireline_intensity']:.6g},{c['flame_length']:.6g}\n"
                        )


DATA = Path(__file__).resolve().parents[1] / "ros2_ws/src/fire_world_sim/test/data"


def read_csv(name: str) -> list[dict[str, str]]:
    with (DATA / name).open() as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def agreement() -> None:
    """Markdown: per fuel model, our per-cell results against Behave's (behave_53.csv)."""
    import numpy as np
    from fire_world_sim.fires.behavior import FuelMoistures, Moisture, fire_behavior
    from fire_world_sim.fires.fuel_models import FUEL_MODELS

    mph, ft = 0.44704, 0.3048
    btu = 1.055056 / ft
    worst: dict[int, list[float]] = {}
    count: dict[int, int] = {}
    for d in read_csv("behave_53.csv"):
        fm = int(d["fuel_model"])

        def one(key: str, d: dict[str, str] = d) -> np.ndarray:
            return np.array([[float(d[key])]])

        b = fire_behavior(
            np.array([[fm]]),
            one("slope_pct"),
            one("aspect_deg"),
            wind_20ft_mps=float(d["wind20_mph"]) * mph,
            wind_from_deg=float(d["wind_from_deg"]),
            moistures=FuelMoistures(
                Moisture(*(float(d[k]) for k in ("m1h", "m10h", "m100h", "mherb", "mwoody")))
            ),
            canopy_cover=one("canopy_cover"),
            canopy_height_m=one("canopy_height_m"),
            canopy_base_height_m=one("canopy_height_m") * (1.0 - one("crown_ratio")),
        )
        ours = (
            b.ros_mps[0, 0] * 60 / ft,
            b.fireline_intensity_kwpm[0, 0] / btu,
            b.flame_length_m[0, 0] / ft,
            b.midflame_wind_mps[0, 0] / mph,
        )
        theirs = [float(d[k]) for k in ("head_ft_min", "fli_btu_ft_s", "flame_ft", "midflame_mph")]
        errs = [abs(o - t) / t if t > 0 else abs(o) for o, t in zip(ours, theirs, strict=True)]
        moving = float(d["wind20_mph"]) > 0 or float(d["slope_pct"]) > 0
        dd = abs((b.spread_dir_deg[0, 0] - float(d["head_dir_deg"]) + 180.0) % 360.0 - 180.0)
        errs.append(dd if moving and theirs[0] > 0 else 0.0)
        w = worst.setdefault(fm, [0.0] * len(errs))
        worst[fm] = [max(a, e) for a, e in zip(w, errs, strict=True)]
        count[fm] = count.get(fm, 0) + 1
    out = sys.stdout
    out.write("# Per-cell agreement with Behave, all 53 standard fuel models\n\n")
    out.write(
        "Generated by `python scripts/behave_tables.py agreement > docs/behave_agreement.md` from the\n"
        "committed Behave (pyrothermel 0.1.4) table `ros2_ws/src/fire_world_sim/test/data/behave_53.csv`\n"
        "(grid in the script's header: 5 moisture scenarios, 20-ft wind 0-20 mi/h from the south-west,\n"
        "slope 0 / 40 %, open and sheltered canopy). Largest relative difference per model of the head\n"
        "rate of spread, Byram's fireline intensity, flame length and midflame wind (the wind adjustment\n"
        "factor), and the largest difference of the head direction. Wind limit: Behave's (Rothermel 1972,\n"
        "effective wind <= 0.9 I_R), as the landscape command uses by default.\n\n"
    )
    out.write(
        "| model | code | cases | head rate | intensity | flame length | midflame wind | direction [deg] |\n"
    )
    out.write("|---:|---|---:|---:|---:|---:|---:|---:|\n")
    for fm in sorted(worst):
        w = worst[fm]
        out.write(
            f"| {fm} | {FUEL_MODELS[fm].code} | {count[fm]} | {w[0]:.2%} | {w[1]:.2%} | {w[2]:.2%} | "
            f"{w[3]:.2%} | {w[4]:.2f} |\n"
        )
    allw = [max(w[i] for w in worst.values()) for i in range(5)]
    out.write(
        f"| all | | {sum(count.values())} | {allw[0]:.2%} | {allw[1]:.2%} | {allw[2]:.2%} | {allw[3]:.2%} | "
        f"{allw[4]:.2f} |\n"
    )


def main() -> None:
    if len(sys.argv) > 1:
        if sys.argv[1] == "landscape":
            return landscape()
        if sys.argv[1] == "crown":
            return crown()
        if sys.argv[1] == "agreement":
            return agreement()
        raise SystemExit(f"usage: {sys.argv[0]} [landscape|crown|agreement]")
    out = sys.stdout
    out.write(
        "# Behave (pyrothermel 0.1.4) reference table, made by scripts/behave_tables.py; see its header\n"
    )
    out.write("fuel_model,moisture,wind_mph,slope_pct,cross,head_ft_min,back_ft_min,head_dir_deg,lw\n")
    for fm in range(1, 14):
        for m in MOISTURES:
            for w in WINDS_MPH:
                for s in SLOPES_PCT:
                    for cross in (0, 1) if (s > 0 and w > 0) else (0,):
                        head, back, direction = run(fm, m, w, s, cross)
                        if head > 0 and back > 0:
                            e = (head - back) / (head + back)
                            lw = 1.0 / math.sqrt(1.0 - e * e)
                        else:
                            lw = float("nan")
                        out.write(
                            f"{fm},{m:.2f},{w:g},{s:g},{cross},{head:.6g},{back:.6g},{direction:.4f},{lw:.6g}\n"
                        )


if __name__ == "__main__":
    main()
