"""One mission of a study, on whichever worker runs it: ``fire_mission.inprocess.run_inprocess``
(the real World and Agents on the lockstep harness, no DDS), reduced to the study's measures.

Only deterministic fields are kept (no wall time, no host), so a mission's row is the same
wherever it runs; :func:`run_mission` is what ``fire_bench.sweep`` calls (mode ``call``).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

__all__ = ["run_mission", "reduce_summary"]


def reduce_summary(d: dict, time_limit_s: float) -> dict:
    """The study's measures from a ``summary.json`` dict (``fire_mission.summary``)."""
    contained = d.get("contained_at_s")
    return {
        "outcome": d.get("outcome"),
        "mission_time_s": d.get("mission_time_s"),
        "time_limit_s": time_limit_s,
        "burned_area_m2": d.get("burned_area_m2"),
        "contained_at_s": None if contained is None else float(contained),
        "contained": contained is not None,
        "water_on_burning_kg": d.get("water_on_burning_kg"),
        "water_released_kg": d.get("water_released_kg"),
        "hit_rate": d.get("hit_rate"),
        "drops": d.get("drops_total"),
        "crashes": len(d.get("crashes") or []),
        "collisions": d.get("collisions"),
        "min_separation_m": d.get("min_separation_m"),
        "landed": len(d.get("landed") or []),
    }


def run_mission(
    scenario: str,
    uavs: int,
    seed: int,
    overrides: Sequence[Sequence[Any]] = (),
    scenario_yaml: str | None = None,
    scenario_dir: str | None = None,
    **_: Any,
) -> dict:
    """Run one mission in process; returns its measures plus ``wall_s`` (kept out of the results
    file). ``scenario`` is a scenario name, or, with ``scenario_yaml`` (a scenario file's text, so
    that a worker on another machine needs no access to the client's files), the file's name.
    ``scenario_dir`` is the client's folder of that file: where it exists on the worker, the
    scenario's relative file paths (a landscape, a wind grid) start from it, as they would have
    beside the original file (``paths_relative_to``)."""
    import tempfile
    from pathlib import Path

    import yaml
    from fire_mission.inprocess import run_inprocess
    from fire_uav_common.scenario import load_scenario

    t0 = time.monotonic()
    ov = {str(k): v for k, v in overrides}
    with tempfile.TemporaryDirectory(prefix="study-") as tmp:
        if scenario_yaml is not None:
            path = Path(tmp) / Path(scenario).name
            path.write_text(scenario_yaml, encoding="utf-8")
            own = (yaml.safe_load(scenario_yaml) or {}).get("paths_relative_to")
            if own is None and scenario_dir is not None and Path(scenario_dir).is_dir():
                ov["paths_relative_to"] = scenario_dir
            sc = load_scenario(path, overrides=ov)
        else:
            from fire_uav_agent.testing.harness import scenario_path

            sc = load_scenario(scenario_path(scenario), overrides=ov)
        d = run_inprocess(sc, uavs=uavs, seed=seed)
    out = reduce_summary(d, float(sc.timing.max_duration_s))
    out["wall_s"] = round(time.monotonic() - t0, 2)
    return out
