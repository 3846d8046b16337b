#!/usr/bin/env python3
"""Reference Rothermel tables from Behave (its C++ core through the ``pyrothermel`` bindings).

Offline only, not part of the tests or CI (the tests read the committed CSV). Regenerate with:

    pip install pyrothermel==0.1.4
    python scripts/behave_tables.py > ros2_ws/src/fire_world_sim/test/data/behave_tables.csv

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

import math
import sys

import pyrothermel as pr
from pyrothermel import units

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


def main() -> None:
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
