"""The fire of one seed: seeded variation of a scenario's wind and ignitions, the same for every arm.

Today's fire models draw no random numbers: a raster fire (ignition, pre-burn before t = 0,
weather) is a function of the scenario alone, and the seed only drives the sensors' noise, the
vehicles' process noise, the prior fire estimates and the injected packet loss, each from its
own stream keyed by (seed, purpose, UAV id) (``fire_uav_common.rng.stream``). So the fire is the
same for every fleet size and tactic -- and also for every seed, which makes seeds of a study
replicate only the noise. ``fire_variation`` lets a study vary the fire per seed:

* ``wind_speed_sd_mps`` [m/s]: one N(0, sd^2) offset added to every wind entry's speed (>= 0);
* ``wind_direction_sd_deg`` [deg]: one N(0, sd^2) rotation of every wind entry's direction;
* ``ignition_sd_m`` [m]: an N(0, sd^2) offset per axis for each ignition (raster) or fire
  centre (analytic).

The draws come from ``stream(seed, "study_fire", crc32(scenario file name))`` and nothing else:
they never depend on the airframe, fleet size or tactic, so within one seed every arm of a
scenario starts from the same fire, up to the moment the fleet acts on it. All draws are made
whatever the sd (an sd of 0 uses its draw with weight 0), so one sd never shifts another's.
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

__all__ = ["KEYS", "check_variation", "fire_variation"]

KEYS = ("wind_speed_sd_mps", "wind_direction_sd_deg", "ignition_sd_m")


def check_variation(raw: Any) -> tuple[tuple[str, float], ...]:
    """Validated ``fire_variation`` mapping (ValueError naming the key otherwise)."""
    if not isinstance(raw, Mapping):
        raise ValueError(f"expected a mapping of {', '.join(KEYS)}, got {type(raw).__name__}")
    out = []
    for k, v in raw.items():
        if k not in KEYS:
            raise ValueError(f"unknown key {k!r} (known: {', '.join(KEYS)})")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not v >= 0:
            raise ValueError(f"{k} must be a number >= 0, got {v!r}")
        out.append((str(k), float(v)))
    return tuple(sorted(out))


def fire_variation(scenario_file: Path, seed: int, sd: Mapping[str, float]) -> dict[str, Any]:
    """Scenario overrides (whole lists: ``fires.raster.wind``, ``fires.raster.ignitions``,
    ``fires.analytic``) for ``seed``'s fire of the scenario in ``scenario_file``."""
    import yaml
    from fire_uav_common.rng import stream

    raw = yaml.safe_load(Path(scenario_file).read_text(encoding="utf-8")) or {}
    fires = raw.get("fires") or {}
    rng = stream(int(seed), "study_fire", zlib.crc32(Path(scenario_file).name.encode()))
    d_speed, d_dir = rng.normal(size=2)
    s_speed = float(sd.get("wind_speed_sd_mps", 0.0))
    s_dir = float(sd.get("wind_direction_sd_deg", 0.0))
    s_ign = float(sd.get("ignition_sd_m", 0.0))
    out: dict[str, Any] = {}
    raster = fires.get("raster")
    if isinstance(raster, Mapping):
        wind = [dict(w) for w in raster.get("wind") or []]
        if s_speed or s_dir:
            gridded = [i for i, w in enumerate(wind) if isinstance(w, Mapping) and w.get("grid") is not None]
            if gridded:
                raise ValueError(
                    f"{Path(scenario_file).name}: fires.raster.wind[{gridded[0]}] is a wind grid; a grid is "
                    "not varied (set wind_speed_sd_mps and wind_direction_sd_deg to 0 for this scenario)"
                )
        for w in wind if (s_speed or s_dir) else []:
            w["speed_mps"] = round(max(0.0, float(w["speed_mps"]) + s_speed * float(d_speed)), 6)
            w["direction_deg"] = round(float(w["direction_deg"]) + s_dir * float(d_dir), 6)
        ign = [dict(p) for p in raster.get("ignitions") or []]
        for p in ign:
            dx, dy = rng.normal(size=2)
            p["x_m"] = round(float(p["x_m"]) + s_ign * float(dx), 6)
            p["y_m"] = round(float(p["y_m"]) + s_ign * float(dy), 6)
        if wind and (s_speed or s_dir):
            out["fires.raster.wind"] = wind
        if ign and s_ign:
            out["fires.raster.ignitions"] = ign
    analytic = fires.get("analytic")
    if isinstance(analytic, list) and s_ign:
        moved = [dict(f) for f in analytic]
        for f in moved:
            dx, dy = rng.normal(size=2)
            f["x_m"] = round(float(f["x_m"]) + s_ign * float(dx), 6)
            f["y_m"] = round(float(f["y_m"]) + s_ign * float(dy), 6)
        out["fires.analytic"] = moved
    return out
