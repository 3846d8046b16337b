"""The study file: which missions a study runs, and how they pair.

A study is the product scenarios x airframes x fleet sizes x tactics x seeds. One *arm* is one
(scenario, airframe, UAVs, tactic); within one seed every arm of a scenario starts from the same
fire (see :mod:`fire_study.variation`). Example::

    name: tactics_grass
    scenarios: [grass_running, grass_brush_hill]   # names under fire_world_sim/scenarios, or paths
    tactics: [head, flank, auto]                   # mission.tactic
    uavs: [3, 6, 10]                               # fleet sizes
    seeds: {first: 1, count: 5}                    # or a list of integers >= 0
    airframes: {default: {}}                       # optional: name -> scenario overrides (vehicle.*)
    overrides: {mission.monitors_per_fire: 0}      # optional: for every mission
    time_limit_s: 900                              # optional: timing.max_duration_s
    fire_variation: {wind_direction_sd_deg: 10}    # optional: per-seed fire (variation.py)
    measures: [burned_area_m2, contained_at_s]     # optional: what the report compares

Every problem is a :class:`StudyError` naming the file and the field.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .errors import StudyError

__all__ = ["MEASURES", "Arm", "Study", "load_study", "study_from_dict"]

#: measure -> (label, unit, better): what a mission row holds and how the report reads it
MEASURES: dict[str, tuple[str, str, str]] = {
    "burned_area_m2": ("burned area", "m^2", "lower"),
    "contained_at_s": ("time to containment", "s", "lower"),
    "water_on_burning_kg": ("water on burning cells", "kg", "higher"),
    "water_released_kg": ("water released", "kg", "higher"),
    "hit_rate": ("hit rate", "-", "higher"),
    "drops": ("drops", "-", "higher"),
    "crashes": ("crashes", "-", "lower"),
    "min_separation_m": ("closest approach", "m", "higher"),
}
DEFAULT_MEASURES = ("burned_area_m2", "contained_at_s", "water_on_burning_kg", "crashes", "min_separation_m")
_FIELDS = {
    "name", "description", "scenarios", "tactics", "uavs", "seeds", "airframes", "overrides",
    "time_limit_s", "fire_variation", "measures",
}  # fmt: skip
_REQUIRED = ("name", "scenarios", "tactics", "uavs", "seeds")


@dataclass(frozen=True, order=True)
class Arm:
    """One arm of a study: every seed of it runs the same configuration."""

    scenario: str
    airframe: str
    uavs: int
    tactic: str

    def label(self) -> str:
        af = "" if self.airframe == "default" else f" {self.airframe}"
        return f"{self.scenario}{af} {self.uavs} UAVs {self.tactic}"


@dataclass(frozen=True)
class Study:
    name: str
    file: str
    scenarios: tuple[str, ...]
    tactics: tuple[str, ...]
    uavs: tuple[int, ...]
    seeds: tuple[int, ...]
    airframes: tuple[tuple[str, tuple[tuple[str, Any], ...]], ...]
    overrides: tuple[tuple[str, Any], ...]
    time_limit_s: float | None
    fire_variation: tuple[tuple[str, float], ...]
    measures: tuple[str, ...]
    description: str = ""

    def arms(self) -> list[Arm]:
        return [
            Arm(sc, af, n, t)
            for sc in self.scenarios
            for af, _ in self.airframes
            for n in self.uavs
            for t in self.tactics
        ]

    def canonical(self) -> dict:
        """Everything that decides the missions' results, as plain JSON (not the file's layout)."""
        return {
            "name": self.name,
            "scenarios": list(self.scenarios),
            "tactics": list(self.tactics),
            "uavs": list(self.uavs),
            "seeds": list(self.seeds),
            "airframes": {k: dict(v) for k, v in self.airframes},
            "overrides": dict(self.overrides),
            "time_limit_s": self.time_limit_s,
            "fire_variation": dict(self.fire_variation),
        }

    def digest(self) -> str:
        """sha256 of :meth:`canonical` (the measures and description only change the report)."""
        text = json.dumps(self.canonical(), sort_keys=True, separators=(",", ":"), default=str)
        return hashlib.sha256(text.encode()).hexdigest()


def _fail(file: str, field: str, what: str) -> StudyError:
    return StudyError(f"{file}: {field}: {what}")


def _list(file: str, d: Mapping, key: str) -> list:
    v = d[key]
    if isinstance(v, (str, int, float)) and not isinstance(v, bool):
        v = [v]
    if not isinstance(v, list):
        raise _fail(file, key, f"expected a list, got {type(v).__name__}")
    if not v:
        raise _fail(file, key, "is empty: a study needs at least one value (an empty arm)")
    if len(set(map(str, v))) != len(v):
        raise _fail(file, key, f"has a value twice: {v}")
    return v


def _int(file: str, field: str, v: Any, lo: int) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        raise _fail(file, field, f"must be an integer, got {v!r}")
    if v < lo:
        raise _fail(file, field, f"must be >= {lo}, got {v}")
    return v


def _seeds(file: str, v: Any) -> tuple[int, ...]:
    if isinstance(v, Mapping):
        unknown = set(v) - {"first", "count"}
        if unknown or "count" not in v:
            raise _fail(file, "seeds", f"expected {{first: N, count: K}} or a list, got {dict(v)}")
        first = _int(file, "seeds.first", v.get("first", 1), 0)
        count = _int(file, "seeds.count", v["count"], 1)
        return tuple(range(first, first + count))
    out = tuple(_int(file, f"seeds[{i}]", s, 0) for i, s in enumerate(_list(file, {"seeds": v}, "seeds")))
    return out


def _overrides(file: str, field: str, v: Any) -> tuple[tuple[str, Any], ...]:
    if v is None:
        return ()
    if not isinstance(v, Mapping):
        raise _fail(
            file, field, f"expected a mapping of dotted scenario fields to values, got {type(v).__name__}"
        )
    for k in v:
        if k in ("mission.tactic", "uavs.count", "seed"):
            raise _fail(file, f"{field}.{k}", "is set by the study's tactics / uavs / seeds, not an override")
    return tuple(sorted((str(k), val) for k, val in v.items()))


def _scenario_file(file: str, field: str, name: str) -> Path:
    p = Path(name)
    if p.suffix in (".yaml", ".yml"):
        if not p.is_absolute():
            p = Path(file).parent / p
        if not p.is_file():
            raise _fail(file, field, f"scenario file {name!r} not found")
        return p
    import fire_world_sim
    from fire_uav_agent.testing.harness import scenario_path

    try:
        return scenario_path(name)
    except FileNotFoundError:
        root = Path(fire_world_sim.__file__).resolve().parents[1] / "scenarios"
        known = sorted(q.stem for q in root.glob("*.yaml"))
        raise _fail(file, field, f"unknown scenario {name!r} (known: {', '.join(known)})") from None


def study_from_dict(raw: Any, file: str = "<study>") -> Study:
    """Validate a parsed study mapping; ``file`` names it in errors."""
    if not isinstance(raw, Mapping):
        raise _fail(file, "(top level)", f"must be a mapping, got {type(raw).__name__}")
    unknown = sorted(set(raw) - _FIELDS)
    if unknown:
        raise _fail(file, unknown[0], f"unknown field (known: {', '.join(sorted(_FIELDS))})")
    for key in _REQUIRED:
        if key not in raw or raw[key] is None:
            raise _fail(file, key, "missing")
    name = raw["name"]
    if not isinstance(name, str) or not name.strip() or "/" in name:
        raise _fail(file, "name", f"must be a non-empty string without '/', got {name!r}")
    from fire_uav_common.scenario import TACTICS, ScenarioError, load_scenario

    scenarios = tuple(str(s) for s in _list(file, raw, "scenarios"))
    paths = [_scenario_file(file, f"scenarios[{i}]", s) for i, s in enumerate(scenarios)]
    tactics = tuple(_list(file, raw, "tactics"))
    for i, t in enumerate(tactics):
        if t not in TACTICS:
            raise _fail(file, f"tactics[{i}]", f"unknown tactic {t!r} (known: {', '.join(TACTICS)})")
    uavs = tuple(_int(file, f"uavs[{i}]", n, 1) for i, n in enumerate(_list(file, raw, "uavs")))
    seeds = _seeds(file, raw["seeds"])
    af_raw = raw.get("airframes") or {"default": {}}
    if not isinstance(af_raw, Mapping) or not af_raw:
        raise _fail(file, "airframes", "expected a non-empty mapping of name -> scenario overrides")
    airframes = tuple((str(k), _overrides(file, f"airframes.{k}", v)) for k, v in af_raw.items())
    overrides = _overrides(file, "overrides", raw.get("overrides"))
    tl = raw.get("time_limit_s")
    if tl is not None and (isinstance(tl, bool) or not isinstance(tl, (int, float)) or not tl > 0):
        raise _fail(file, "time_limit_s", f"must be a number > 0, got {tl!r}")
    from .variation import check_variation

    fv_raw = raw.get("fire_variation") or {}
    try:
        fv = check_variation(fv_raw)
    except ValueError as e:
        raise _fail(file, "fire_variation", str(e)) from None
    measures = tuple(raw.get("measures") or DEFAULT_MEASURES)
    if not isinstance(raw.get("measures", []), (list, type(None))):
        raise _fail(file, "measures", f"expected a list, got {type(raw['measures']).__name__}")
    for i, m in enumerate(measures):
        if m not in MEASURES:
            raise _fail(file, f"measures[{i}]", f"unknown measure {m!r} (known: {', '.join(MEASURES)})")
    study = Study(
        name=name.strip(),
        file=file,
        scenarios=scenarios,
        tactics=tactics,
        uavs=uavs,
        seeds=seeds,
        airframes=airframes,
        overrides=overrides,
        time_limit_s=None if tl is None else float(tl),
        fire_variation=fv,
        measures=measures,
        description=str(raw.get("description") or ""),
    )
    # every arm's scenario must load with its overrides (a bad override field fails here, once)
    for sc, p in zip(scenarios, paths, strict=True):
        if fv:
            from .variation import fire_variation

            try:
                fire_variation(p, seeds[0], dict(fv))
            except ValueError as e:
                raise _fail(file, "fire_variation", f"scenario {sc}: {e}") from None
        for af, ov in airframes:
            try:
                load_scenario(p, overrides=mission_overrides(study, sc, af, uavs[0], tactics[0], None))
            except ScenarioError as e:
                where = f"airframes.{af}" if ov else "overrides"
                raise _fail(file, where, f"scenario {sc}: {e}") from None
    return study


def mission_overrides(
    study: Study, scenario: str, airframe: str, uavs: int, tactic: str, seed: int | None
) -> dict[str, Any]:
    """The scenario overrides of one mission: the study's, the airframe's, the tactic, the time
    limit and (with a seed) the seed's fire variation, which depends on the scenario and the seed
    only -- never on the airframe, fleet size or tactic (the pairing of the arms)."""
    ov: dict[str, Any] = dict(study.overrides)
    ov.update(dict(study.airframes)[airframe])
    ov["mission.tactic"] = tactic
    if study.time_limit_s is not None:
        ov["timing.max_duration_s"] = study.time_limit_s
    if seed is not None and study.fire_variation:
        from .variation import fire_variation

        ov.update(fire_variation(scenario_path_of(study, scenario), seed, dict(study.fire_variation)))
    return ov


def scenario_path_of(study: Study, scenario: str) -> Path:
    return _scenario_file(study.file, "scenarios", scenario)


def load_study(path: str | Path) -> Study:
    """Read and validate a study YAML file."""
    import yaml

    file = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as e:
        raise StudyError(f"{file}: cannot read: {e.strerror or e}") from None
    try:
        raw = yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise StudyError(f"{file}: invalid YAML: {' '.join(str(e).split())}") from None
    if raw is None:
        raise StudyError(f"{file}: file is empty")
    return study_from_dict(raw, file)
