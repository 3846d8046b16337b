"""Freshness-weighted consensus of fire estimates (FF III-C, Eqs. 26-29).

Each agent keeps one entry per fleet-wide fire id: centre [m; map], extent (Gaussian sigma) [m],
drift [m/s] and ``last_measurement_s``, the sim time of the newest measurement fused in. Per
control step: :meth:`FireConsensus.predict` (drift), :meth:`fuse` (consensus over the alive
peers' last known pictures), :meth:`observe` (own detections, after fusion so that what this
agent broadcasts carries its freshest measurement).

**Weights (Eqs. 26-29).** The text intends: each agent i holds, per contributor j, the age
Lm_i[j] of j's newest measurement (1 for a measurement made now, FF III-C step 1 "reset the
Last Measurement time to 1"); row i of Q_c is the element-wise inverse of Lm_i normalised by
its sum (Eq. 28), so row i is stochastic and fresher data weigh more. Eq. 29 *as printed* puts
1/1.375 in every entry of row 1 and 0.825/1.375 in row 2, which is neither stochastic nor what
the text describes; :func:`consensus_matrix` implements the text:
Q_c[i, j] = (1 / Lm_i[j]) / sum_j (1 / Lm_i[j]). Ages are in control steps:
``age = 1 + (t_now - last_measurement) / T``.

**Drift.** Each agent fits its own detections of a fire: the least-squares slope of centre
against time over the last ``drift_window_s`` (once they span ``drift_min_span_s``), with its
standard error sigma_v = sigma_pos / sqrt(sum (t - t_mean)^2). FF III-C fuses a drift without
saying how it is measured; an alpha-beta gain on step-to-step innovations (our first choice)
amplified the 2 m position noise by 1/T and left estimates 30-90 deg off with a +-4.5 m/s spread.
The fit is the minimum-variance linear estimator for a constant drift: ~0.07 m/s after 10 s of
continuous sight at sigma_pos 2 m and 10 Hz (validated against the world's truth in
tests/test_fleet_behaviour.py).

Fused quantities: position, extent and drift; the fused entry's ``last_measurement_s`` is the
newest among the contributors (it now contains that measurement). Peer entries are moved by
their drift to the current time before fusion.

**Extent after a hit.** A drop halves a fire's sigma (FF V-B) at once, and every measurement
made before it is then wrong. Eq. 28 averages the extents of all contributors with weights
1/age, and every agent's entry carries the newest measurement time among *its* contributors, so
the pre-hit extents kept ~half the weight: measured on the FF scenario (5 UAVs, known fires),
the fleet's extent was 50-160 % above the truth 1-4 s after each hit, and 2 of 11 drops missed
for it. So the extent (only) is fused over the freshest contributors (age within one step of
the freshest), and an own detection moves it by ``alpha_extent`` = 0.5 (sensor sigma 1 m).

**Extinction (step 4).** Averaging extents cannot make a fire go out (a convex combination of
extents above the threshold stays above it), so extinction is a freshness-ordered status.
The world's sensor reports burning fires only, so a detection proves the fire burns and the
extent never ends a fire (a filtered extent dipped below the threshold while the fire burned,
and the fleet landed with it still burning: system runs); an entry becomes EXTINGUISHED
when this agent flew within ``negative_range_m`` of the estimated
centre for ``negative_steps`` steps without detecting it (only where the fire, if it still
burns, must be in sight: ``negative range + position uncertainty <= sensor range``, the
uncertainty growing with the age of the newest measurement, see :meth:`FireConsensus.negative_range`);
an EXTINGUISHED report from a peer is
adopted when its ``last_measurement_s`` is not older than ours; an extinguished entry revives
only on evidence strictly newer than its extinction.

Deviation from FF III-C step 4 (threshold on the estimated extent): see above; a fire is
ended by negative evidence (flying close and no longer seeing it).
The known effect of an own drop (:meth:`FireConsensus.note_drop`) halves the extent but never
ends a fire by itself: a drop on a stale or duplicate estimate, released where the fire no
longer is, would otherwise put the fleet's fire out on paper while it burns (found: known fires,
3 UAVs, with another loss pattern the fleet landed after 3 of 5 drops on fire 0). Negative
evidence on a stale estimate was the other half of that path: an estimate predicted for tens of
seconds with a wrong drift sat 50+ m from the fire, a UAV flew over the estimate, saw nothing
and declared the fire out, and the freshest-status rule spread it.

**Raster fires.** The negative-evidence rule above assumes that a fire
still burning is in sight from near its centre (FF III-C step 4: FF's fires are Gaussians around
their centre). A raster fire's reported centre is the centroid of its burned ground and its
extent the radius of that area (100-200 m for a fire of a few ha, above the 70 m sensor range),
so the centre is burnt out while the front burns at the edge: on ``grass_brush_hill`` (flank,
6 UAVs, seeds 1 and 3) a UAV passing over the centroid saw nothing for 5 steps, declared the fire
out, the freshest-status rule spread it, and the fleet landed with the fire burning. Our choice:
:meth:`FireConsensus.observe` takes the cells the agent's front picture holds as burning
(``fire_front.FrontPicture.burning_xy``, seen within its ``max_age_s`` and not seen burnt since)
and counts no negative evidence against a track with one within its association gate. A fire
is then ended only once every burning cell known near it has been seen burnt or has aged out,
and a UAV then looks at its centre and sees nothing. FF fires pass no cells: unchanged.

**Fire ids.** A detection is associated with the nearest active entry within
``max(gate_min_m, gate_sigmas * extent)``; otherwise it opens a new entry with fleet-wide id
``(uav_id << 16) | counter`` (unique without coordination, fits FireEstimate.fire_id uint32 and
MissionEvent.fire_id int32 for uav_id < 32768). Two agents that detect the same fire in the same
step create two ids; entries closer than the gate are merged into the *smaller* id, which every
agent chooses alike, and an alias table maps the retired id for later peer reports.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field, replace

import numpy as np

from .errors import InputError
from .peer_link import FireEntry, PeerFires

__all__ = ["PRIOR_FIRE_ID_BASE", "ConsensusConfig", "FireConsensus", "consensus_matrix", "consensus_row"]

#: fleet-wide ids of briefed fires (known-fires mode): PRIOR_FIRE_ID_BASE + k for the k-th fire of
#: the briefing; above every detection id (uav_id < 256, so (uav_id << 16) | n < 2**24), int32-safe
PRIOR_FIRE_ID_BASE = 1 << 24


def consensus_row(ages: np.ndarray) -> np.ndarray:
    """One row of Q_c (Eqs. 27-28 as the text intends): normalised inverse ages (ages >= 1)."""
    a = np.asarray(ages, dtype=float)
    if a.ndim != 1 or a.size == 0 or np.any(~np.isfinite(a)) or np.any(a <= 0):
        raise InputError(f"ages must be a non-empty vector of positive numbers, got {ages!r}")
    inv = 1.0 / a
    return inv / inv.sum()


def consensus_matrix(lm: np.ndarray) -> np.ndarray:
    """Q_c from the matrix whose row i is Lm_i (Eq. 26); see the module doc about Eq. 29."""
    lm = np.asarray(lm, dtype=float)
    return np.vstack([consensus_row(r) for r in lm])


@dataclass(frozen=True)
class ConsensusConfig:
    control_period_s: float = 0.1
    sensor_range_m: float = 70.0  # FF II-C standoff
    gate_min_m: float = 40.0  # association gate floor [m]
    gate_sigmas: float = 2.0  # association gate in extents
    alpha_pos: float = 0.5  # weight of a new own detection (position)
    alpha_extent: float = 0.5  # weight of a new own detection (extent; sensor sigma ~1 m)
    drift_window_s: float = 30.0  # [s] own detections kept for the drift fit
    drift_min_span_s: float = 5.0  # [s] fit the drift once the detections span this long
    drift_min_samples: int = 20
    drift_max_samples: int = 600
    position_sigma_m: float = 2.0  # [m] fire sensor's centre noise (scenario sensors.fire)
    position_margin_m: float = 10.0  # [m] a measured centre's uncertainty (noise + filter lag)
    drift_unknown_mps: float = 1.0  # [m/s] drift uncertainty without an own fit (fires in FF < 1 m/s)
    negative_range_min_m: float = 15.0  # [m] negative evidence range of the stalest estimate
    drop_confirm_s: float = 1.0  # [s] an own drop counts as a hit only on a fire seen this recently
    extinction_extent_m: float = (
        2.0  # FF III-C step 4; informational: the extent never ends a fire (module doc)
    )
    negative_range_m: float = 50.0  # must fly this close to the centre to see "no fire"
    negative_steps: int = 5


@dataclass
class _Track:
    fire_id: int
    active: bool
    x_m: float
    y_m: float
    extent_m: float
    vx_mps: float
    vy_mps: float
    lm_s: float  # newest measurement fused in
    own_meas_s: float = -math.inf  # time of this agent's last own detection
    unseen_steps: int = 0
    position_unc_m: float = 10.0  # [m] uncertainty of the centre at lm_s
    drift_sigma_mps: float = math.inf  # [m/s] standard error of the own drift fit (inf: none)
    hist: deque = field(default_factory=deque)  # own detections (t_s, x_m, y_m)

    def entry(self) -> FireEntry:
        return FireEntry(
            fire_id=self.fire_id,
            active=self.active,
            x_m=self.x_m,
            y_m=self.y_m,
            extent_m=self.extent_m if self.active else 0.0,
            vx_mps=self.vx_mps,
            vy_mps=self.vy_mps,
            last_measurement_s=self.lm_s,
        )


class FireConsensus:
    """One agent's fire picture (see module doc)."""

    def __init__(self, uav_id: int, config: ConsensusConfig | None = None) -> None:
        self.uav_id = uav_id
        self.cfg = config or ConsensusConfig()
        self.tracks: dict[int, _Track] = {}
        self.alias: dict[int, int] = {}
        self._counter = 0

    # --- helpers ---------------------------------------------------------------------------
    def _resolve(self, fire_id: int) -> int:
        seen = set()
        while fire_id in self.alias and fire_id not in seen:
            seen.add(fire_id)
            fire_id = self.alias[fire_id]
        return fire_id

    def _gate(self, extent_m: float) -> float:
        return max(self.cfg.gate_min_m, self.cfg.gate_sigmas * extent_m)

    def _burning_near(self, tr: _Track, burning_xy: np.ndarray | None) -> bool:
        """Whether a known burning cell [m] lies within the track's association gate (raster fires)."""
        if burning_xy is None or len(burning_xy) == 0:
            return False
        b = np.asarray(burning_xy, dtype=float).reshape(-1, 2)
        d2 = (b[:, 0] - tr.x_m) ** 2 + (b[:, 1] - tr.y_m) ** 2
        return bool(np.any(d2 <= self._gate(tr.extent_m) ** 2))

    def negative_range(self, tr: _Track, t_s: float) -> float:
        """Range [m] within which not seeing ``tr`` counts as evidence that it is out (<= 0: none).

        The fire, if it burns, is within ``position_unc + drift_unc * age`` of the estimate
        (age since the newest measurement; drift uncertainty 3 sigma_v of the own fit, else
        ``drift_unknown_mps``), so a UAV within ``sensor_range - that`` of the estimate must see it;
        never less than ``negative_range_min_m`` (the very stale estimate: see the code).
        """
        dv = 3.0 * tr.drift_sigma_mps if math.isfinite(tr.drift_sigma_mps) else self.cfg.drift_unknown_mps
        dv = min(dv, self.cfg.drift_unknown_mps)
        age = max(0.0, t_s - tr.lm_s) if math.isfinite(tr.lm_s) else math.inf
        unc = tr.position_unc_m + dv * age
        # capped: a UAV over the very centre of a stale estimate may still end it (ghost and
        # duplicate tracks must end, or the fleet circles them for ever); the fire is then more
        # than sensor_range - negative_range_min_m from its estimate
        unc = min(unc, self.cfg.sensor_range_m - self.cfg.negative_range_min_m)
        return min(self.cfg.negative_range_m, self.cfg.sensor_range_m - unc)

    def _fit_drift(self, tr: _Track) -> None:
        """Least-squares drift of the own detections in the window (module doc, "Drift")."""
        h = tr.hist
        while h and h[-1][0] - h[0][0] > self.cfg.drift_window_s:
            h.popleft()
        while len(h) > self.cfg.drift_max_samples:
            h.popleft()
        if len(h) < self.cfg.drift_min_samples or h[-1][0] - h[0][0] < self.cfg.drift_min_span_s:
            return
        a = np.asarray(h, dtype=float)
        t = a[:, 0] - a[:, 0].mean()
        stt = float(t @ t)
        tr.vx_mps = float(t @ (a[:, 1] - a[:, 1].mean()) / stt)
        tr.vy_mps = float(t @ (a[:, 2] - a[:, 2].mean()) / stt)
        tr.drift_sigma_mps = self.cfg.position_sigma_m / math.sqrt(stt)

    def _age(self, lm_s: float, t_s: float) -> float:
        return 1.0 + max(0.0, t_s - lm_s) / self.cfg.control_period_s

    def entries(self) -> tuple[FireEntry, ...]:
        return tuple(self.tracks[f].entry() for f in sorted(self.tracks))

    def active(self) -> list[FireEntry]:
        return [e for e in self.entries() if e.active]

    def all_out(self) -> bool:
        """True if at least one fire is known and every known fire is extinguished."""
        return bool(self.tracks) and not any(t.active for t in self.tracks.values())

    # --- step parts ------------------------------------------------------------------------
    def predict(self, dt_s: float) -> None:
        for t in self.tracks.values():
            if t.active:
                t.x_m += t.vx_mps * dt_s
                t.y_m += t.vy_mps * dt_s

    def fuse(self, peers: dict[int, PeerFires], t_now_s: float) -> list[int]:
        """Consensus over the alive peers' last known pictures. Returns ids new to this agent."""
        per_fire: dict[int, list[tuple[FireEntry, float]]] = {}
        for j in sorted(peers):
            pf = peers[j]
            t_msg = (pf.step + 1) * self.cfg.control_period_s
            for e in pf.fires:
                fid = self._resolve(e.fire_id)
                per_fire.setdefault(fid, []).append((e, t_now_s - t_msg))
        new_ids: list[int] = []
        for fid in sorted(per_fire):
            reports = per_fire[fid]
            mine = self.tracks.get(fid)
            if mine is None:
                # adopt; merge() below folds it into a nearby entry with a smaller id
                e, _ = max(reports, key=lambda r: r[0].last_measurement_s)
                mine = _Track(
                    fid, e.active, e.x_m, e.y_m, e.extent_m, e.vx_mps, e.vy_mps, e.last_measurement_s
                )
                if e.active:
                    mine.lm_s = -math.inf  # its numbers come from the reports below
                self.tracks[fid] = mine
                new_ids.append(fid)
            # status: freshest extinction report wins (module doc)
            for e, _ in reports:
                if not e.active and e.last_measurement_s >= mine.lm_s and mine.active:
                    mine.active = False
                    mine.lm_s = e.last_measurement_s
                elif e.active and not mine.active and e.last_measurement_s > mine.lm_s:
                    mine.active = True
                    mine.extent_m = e.extent_m
            if not mine.active:
                continue
            vals = []
            ages = []
            if math.isfinite(mine.lm_s):
                vals.append((mine.x_m, mine.y_m, mine.extent_m, mine.vx_mps, mine.vy_mps))
                ages.append(self._age(mine.lm_s, t_now_s))
            newest = mine.lm_s
            for e, dt_old in reports:
                if not e.active:
                    continue
                vals.append(
                    (e.x_m + e.vx_mps * dt_old, e.y_m + e.vy_mps * dt_old, e.extent_m, e.vx_mps, e.vy_mps)
                )
                ages.append(self._age(e.last_measurement_s, t_now_s))
                newest = max(newest, e.last_measurement_s)
            if not vals:
                continue
            ages_a = np.array(ages)
            w = consensus_row(ages_a)
            x, y, _, vx, vy = w @ np.array(vals)
            # extent: only the freshest contributors (module doc, "Extent after a hit")
            fresh = ages_a <= ages_a.min() + 1.0
            ext = float(consensus_row(ages_a[fresh]) @ np.array(vals)[fresh, 2])
            mine.x_m, mine.y_m, mine.extent_m, mine.vx_mps, mine.vy_mps = x, y, ext, vx, vy
            if newest > mine.lm_s:
                mine.position_unc_m = min(mine.position_unc_m, self.cfg.position_margin_m)
            mine.lm_s = newest
        self.merge()
        return [f for f in new_ids if f in self.tracks]

    def observe(
        self,
        detections: np.ndarray,
        own_xy: tuple[float, float] | None,
        t_now_s: float,
        burning_xy: np.ndarray | None = None,
    ) -> list[int]:
        """Fuse own detections, rows (t_s, x_m, y_m, extent_m). Returns ids first seen here.

        ``burning_xy``: (N, 2) centres [m] of the cells this agent's front picture holds as burning
        (raster fires only; None for FF fires): no negative evidence against a track with one
        within its association gate (module doc, "Raster fires").
        """
        new_ids: list[int] = []
        seen: set[int] = set()
        dets = np.asarray(detections, dtype=float).reshape(-1, 4)
        dets = dets[np.all(np.isfinite(dets), axis=1)]
        for t_s, x, y, ext in dets[np.argsort(dets[:, 0], kind="stable")]:
            best, best_d = None, math.inf
            for tr in self.tracks.values():
                d = math.hypot(tr.x_m - x, tr.y_m - y)
                gate = self._gate(tr.extent_m if tr.active else ext)
                if d <= gate and d < best_d:
                    best, best_d = tr, d
            if best is None:
                self._counter += 1
                fid = (self.uav_id << 16) | self._counter
                best = _Track(fid, True, float(x), float(y), float(ext), 0.0, 0.0, float(t_s), float(t_s))
                best.position_unc_m = self.cfg.position_margin_m
                self.tracks[fid] = best
                new_ids.append(fid)
            else:
                if not best.active:
                    if t_s <= best.lm_s:
                        continue
                    best.active, best.x_m, best.y_m, best.extent_m = True, float(x), float(y), float(ext)
                    best.hist.clear()
                else:
                    a, ae = self.cfg.alpha_pos, self.cfg.alpha_extent
                    best.x_m += a * (x - best.x_m)
                    best.y_m += a * (y - best.y_m)
                    best.extent_m += ae * (ext - best.extent_m)
                best.lm_s = max(best.lm_s, float(t_s))
                best.own_meas_s = float(t_s)
                best.position_unc_m = self.cfg.position_margin_m
            best.hist.append((float(t_s), float(x), float(y)))
            self._fit_drift(best)
            best.unseen_steps = 0
            seen.add(best.fire_id)
        # negative evidence: close to an active centre but no detection of it
        if own_xy is not None:
            for tr in self.tracks.values():
                if not tr.active or tr.fire_id in seen:
                    continue
                if self._burning_near(tr, burning_xy):
                    tr.unseen_steps = 0  # a raster fire still burning away from its centre
                    continue
                if math.hypot(tr.x_m - own_xy[0], tr.y_m - own_xy[1]) <= self.negative_range(tr, t_now_s):
                    tr.unseen_steps += 1
                    if tr.unseen_steps >= self.cfg.negative_steps:
                        tr.active = False
                        tr.lm_s = t_now_s
                else:
                    tr.unseen_steps = 0
        self.merge()
        return [f for f in new_ids if f in self.tracks]

    def brief(
        self,
        priors: tuple[tuple[float, float, float], ...],
        t_s: float = 0.0,
        position_sigma_m: float = 10.0,
    ) -> list[int]:
        """Known-fires mode: start with the briefing's (x_m, y_m, extent_m) per fire as measured at ``t_s``.

        Every agent gets the same briefing, so the ids ``PRIOR_FIRE_ID_BASE + k`` agree fleet-wide
        without a message; detections of a briefed fire associate with it (gate of the module doc).
        ``position_sigma_m``: the briefing's centre noise per axis; 3 of it bound the centre's error.
        """
        ids = []
        for k, (x, y, ext) in enumerate(priors):
            fid = PRIOR_FIRE_ID_BASE + k
            tr = _Track(fid, True, float(x), float(y), float(ext), 0.0, 0.0, float(t_s))
            tr.position_unc_m = 3.0 * position_sigma_m
            self.tracks[fid] = tr
            ids.append(fid)
        return ids

    def note_drop(self, fire_id: int, xy_m: tuple[float, float], t_s: float, footprint_m: float) -> bool:
        """Own drop released at ``xy_m`` on ``fire_id`` at ``t_s``: apply the known effect of a hit.

        FF V-B models a drop as dividing the fire's area by four (sigma halves). Where the release
        is within ``max(footprint_m, extent)`` of the estimated centre (the water reaches the core)
        and this agent saw the fire within ``drop_confirm_s`` (the centre is not a stale or
        duplicate estimate), the estimate's extent halves at once and carries ``t_s`` as its
        newest measurement, so the consensus (freshest data weigh most, Eqs. 27-28) spreads the
        smaller extent before the next detection confirms it. The model never ends a fire: below
        the threshold the fire is ended by the next looks (negative evidence; module doc).
        Returns whether the estimate changed.
        """
        tr = self.tracks.get(self._resolve(fire_id))
        if tr is None or not tr.active:
            return False
        if math.hypot(tr.x_m - xy_m[0], tr.y_m - xy_m[1]) > max(footprint_m, tr.extent_m):
            return False
        if t_s - tr.own_meas_s > self.cfg.drop_confirm_s:
            return False
        tr.extent_m /= 2.0
        tr.lm_s = max(tr.lm_s, float(t_s))
        return True

    def merge(self) -> None:
        """Fold active entries within the association gate of each other into the smaller id."""
        ids = sorted(self.tracks)
        for a_i, a in enumerate(ids):
            ta = self.tracks.get(a)
            if ta is None:
                continue
            for b in ids[a_i + 1 :]:
                tb = self.tracks.get(b)
                if tb is None or not (ta.active and tb.active):
                    continue
                if math.hypot(ta.x_m - tb.x_m, ta.y_m - tb.y_m) <= self._gate(max(ta.extent_m, tb.extent_m)):
                    if tb.lm_s > ta.lm_s:  # keep the fresher numbers under the smaller id
                        self.tracks[a] = ta = replace(tb, fire_id=a)
                    del self.tracks[b]
                    self.alias[b] = a
