"""Statistics of a study, from scipy and statsmodels (nothing estimated by hand).

* per arm and measure: mean, median, and 95 % bootstrap confidence intervals of both
  (``scipy.stats.bootstrap``; BCa from 8 seeds up, percentile below, where BCa's jackknife is
  unstable);
* per pair of tactics (within one scenario, airframe and fleet size), over the seeds both arms
  ran (paired: within a seed both start from the same fire): the mean difference B - A and the
  relative difference mean(B) / mean(A) - 1, each with a paired bootstrap CI, and the Wilcoxon
  signed-rank test of the differences (``scipy.stats.wilcoxon``, exact for small samples);
* containment as time to event: Kaplan-Meier per arm (``statsmodels`` ``SurvfuncRight``), a
  mission never contained censored at its time limit;
* a plain-language verdict per pair: "no detectable difference" whenever the CI of the relative
  difference spans zero.

The bootstrap's generator is seeded, so a report of the same results is the same report.
A mission never contained enters the paired comparison of ``contained_at_s`` at its time limit
(a lower bound of its true time: such a difference understates the gap).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .spec import MEASURES, Arm

__all__ = [
    "ArmStats",
    "ArmContainment",
    "PairStats",
    "arm_stats",
    "bootstrap_ci",
    "containment",
    "measure_value",
    "paired_stats",
    "verdict",
]

CONFIDENCE = 0.95
RESAMPLES = 9999
BCA_MIN_N = 8


def measure_value(row: dict, measure: str) -> float | None:
    """The row's value of ``measure`` (never-contained: the time limit, module doc); None if missing."""
    if measure == "contained_at_s" and not row.get("contained"):
        return float(row["time_limit_s"])
    v = row.get(measure)
    return None if v is None else float(v)


def bootstrap_ci(
    samples: Sequence[np.ndarray], statistic: Callable[..., Any], paired: bool = False
) -> tuple[float, float]:
    """95 % bootstrap CI of ``statistic`` (scipy.stats.bootstrap; it takes ``axis``, like np.mean);
    (nan, nan) below 2 values."""
    from scipy.stats import bootstrap

    n = len(samples[0])
    if n < 2:
        return math.nan, math.nan
    data = tuple(np.asarray(s, dtype=float) for s in samples)
    if all(np.all(d == d[0]) for d in data):  # every resample gives the same value
        v = float(statistic(*data))
        return v, v
    for method in ("BCa", "percentile") if n >= BCA_MIN_N else ("percentile",):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = bootstrap(
                data,
                statistic,
                paired=paired,
                vectorized=True,
                confidence_level=CONFIDENCE,
                n_resamples=RESAMPLES,
                method=method,
                rng=np.random.default_rng(20261204),
            )
        lo, hi = float(res.confidence_interval.low), float(res.confidence_interval.high)
        if math.isfinite(lo) and math.isfinite(hi):
            return lo, hi
    return math.nan, math.nan


@dataclass(frozen=True)
class ArmStats:
    arm: Arm
    measure: str
    n: int
    mean: float
    mean_ci: tuple[float, float]
    median: float
    median_ci: tuple[float, float]
    values: tuple[float, ...]


def _rows_of(rows: Sequence[dict], arm: Arm) -> list[dict]:
    return sorted(
        (
            r
            for r in rows
            if (r["scenario"], r["airframe"], r["uavs"], r["tactic"])
            == (arm.scenario, arm.airframe, arm.uavs, arm.tactic)
        ),
        key=lambda r: r["seed"],
    )


def arm_stats(rows: Sequence[dict], arm: Arm, measure: str) -> ArmStats:
    vals = [v for r in _rows_of(rows, arm) if (v := measure_value(r, measure)) is not None]
    x = np.asarray(vals, dtype=float)
    if len(x) == 0:
        nan = (math.nan, math.nan)
        return ArmStats(arm, measure, 0, math.nan, nan, math.nan, nan, ())
    return ArmStats(
        arm,
        measure,
        len(x),
        float(np.mean(x)),
        bootstrap_ci((x,), np.mean),
        float(np.median(x)),
        bootstrap_ci((x,), np.median),
        tuple(float(v) for v in x),
    )


@dataclass(frozen=True)
class PairStats:
    a: Arm
    b: Arm
    measure: str
    seeds: tuple[int, ...]
    diffs: tuple[float, ...]  # B - A per seed
    mean_diff: float
    mean_diff_ci: tuple[float, float]
    rel: float  # mean(B) / mean(A) - 1
    rel_ci: tuple[float, float]
    wilcoxon_p: float | None


def _rel(a: np.ndarray, b: np.ndarray, axis: int = -1) -> np.ndarray:
    """mean(b) / mean(a) - 1 along ``axis`` (the bootstrap's vectorised statistic)."""
    ma = np.mean(a, axis=axis)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(ma == 0, np.nan, np.mean(b, axis=axis) / ma - 1.0)


def paired_stats(rows: Sequence[dict], a: Arm, b: Arm, measure: str) -> PairStats:
    """B against A over the seeds both ran (module doc)."""
    from scipy.stats import wilcoxon

    va = {r["seed"]: measure_value(r, measure) for r in _rows_of(rows, a)}
    vb = {r["seed"]: measure_value(r, measure) for r in _rows_of(rows, b)}
    seeds = tuple(s for s in sorted(set(va) & set(vb)) if va[s] is not None and vb[s] is not None)
    xa = np.asarray([va[s] for s in seeds], dtype=float)
    xb = np.asarray([vb[s] for s in seeds], dtype=float)
    d = xb - xa
    p: float | None = None
    if len(d) >= 1 and np.any(d != 0):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            p = float(wilcoxon(xb, xa).pvalue)
    elif len(d) >= 1:
        p = 1.0
    rel = float(_rel(xa, xb)) if len(d) else math.nan
    rel_ci = bootstrap_ci((xa, xb), _rel, paired=True) if float(np.sum(xa)) != 0 else (math.nan, math.nan)
    return PairStats(
        a,
        b,
        measure,
        seeds,
        tuple(float(v) for v in d),
        float(np.mean(d)) if len(d) else math.nan,
        bootstrap_ci((d,), np.mean),
        rel,
        rel_ci,
        p,
    )


_VERB = {
    "burned_area_m2": ("burns", "burns"),
    "contained_at_s": ("contains the fire", "contains it"),
}


def verdict(p: PairStats) -> str:
    """One sentence for a pair (module doc)."""
    label, unit, _ = MEASURES[p.measure]
    where = f"on {p.a.scenario}{'' if p.a.airframe == 'default' else ' (' + p.a.airframe + ')'} with {p.a.uavs} UAVs"
    n = len(p.seeds)
    if n < 2 or not all(math.isfinite(v) for v in p.rel_ci):
        if n >= 2 and all(math.isfinite(v) for v in p.mean_diff_ci):
            lo, hi = p.mean_diff_ci
            if lo <= 0 <= hi:
                return f"{where}, no detectable difference in {label} between {p.b.tactic} and {p.a.tactic} ({n} paired seeds)"
            more = "more" if p.mean_diff > 0 else "less"
            return (
                f"{where}, {p.b.tactic} gives {abs(p.mean_diff):.3g} {unit} {more} {label} than {p.a.tactic} "
                f"(95 % CI {lo:.3g} to {hi:.3g} {unit}, {n} paired seeds)"
            )
        return f"{where}, {label}: too few paired seeds ({n}) to compare {p.b.tactic} with {p.a.tactic}"
    lo, hi = (100 * v for v in p.rel_ci)
    pv = "" if p.wilcoxon_p is None else f"; Wilcoxon p = {p.wilcoxon_p:.2g}"
    ci = f"95 % CI {lo:+.0f} to {hi:+.0f} %, {n} paired seeds{pv}"
    if lo <= 0 <= hi:
        return f"{where}, no detectable difference in {label} between {p.b.tactic} and {p.a.tactic} ({ci})"
    less = p.rel < 0
    if p.measure == "burned_area_m2":
        what = f"{p.b.tactic} burns {abs(100 * p.rel):.0f} % {'less' if less else 'more'} than {p.a.tactic}"
    elif p.measure == "contained_at_s":
        what = f"{p.b.tactic} contains the fire {abs(100 * p.rel):.0f} % {'sooner' if less else 'later'} than {p.a.tactic}"
    else:
        what = f"{p.b.tactic} gives {abs(100 * p.rel):.0f} % {'less' if less else 'more'} {label} than {p.a.tactic}"
    return f"{where}, {what} ({ci})"


@dataclass(frozen=True)
class ArmContainment:
    arm: Arm
    n: int
    contained: int
    times_s: tuple[float, ...]  # KM step times [s]
    fraction: tuple[float, ...]  # 1 - S(t): fraction contained by t
    median_s: float | None  # KM median time to containment (None: not reached)
    limit_s: float


def containment(rows: Sequence[dict], arm: Arm) -> ArmContainment:
    """Kaplan-Meier of the time to containment (statsmodels SurvfuncRight), censored at the limit."""
    rs = _rows_of(rows, arm)
    limit = max((float(r["time_limit_s"]) for r in rs), default=math.nan)
    if not rs:
        return ArmContainment(arm, 0, 0, (), (), None, limit)
    t = np.asarray(
        [r["contained_at_s"] if r.get("contained") else r["time_limit_s"] for r in rs], dtype=float
    )
    e = np.asarray([1 if r.get("contained") else 0 for r in rs], dtype=int)
    if e.sum() == 0:
        return ArmContainment(arm, len(rs), 0, (0.0, limit), (0.0, 0.0), None, limit)
    from statsmodels.duration.survfunc import SurvfuncRight

    sf = SurvfuncRight(t, e)
    q = sf.quantile(0.5)
    times = (0.0, *(float(v) for v in sf.surv_times), limit)
    frac = (0.0, *(1.0 - float(v) for v in sf.surv_prob), 1.0 - float(sf.surv_prob[-1]))
    return ArmContainment(
        arm,
        len(rs),
        int(e.sum()),
        times,
        frac,
        None if q is None or not math.isfinite(q) else float(q),
        limit,
    )
