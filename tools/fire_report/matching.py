"""Which true fire each fleet fire track estimates, by position.

The fleet's track ids (``(uav_id << 16) | n`` for a detection, ``PRIOR_FIRE_ID_BASE + k`` for a
briefed fire) are not the world's fire numbers, so the report matches them by where they are.

Rule: for a track, every published sample (any UAV, status active) at time t is compared with
each true fire burning at t (truth interpolated linearly to t); the track goes to the fire with
the smallest *median* distance over the samples where both exist (median: a few samples of a
track that jumped when it merged do not decide it), if that median is within ``gate_m``.
Greedy per track, not one-to-one (Hungarian): two agents that saw the same fire at once
publish two ids for it until they merge, and both belong to that fire.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from fire_uav_common.constants import FireStatus

from .errors import ReportInputError

__all__ = ["match_tracks_to_fires", "DEFAULT_GATE_M"]

#: [m] a track whose median distance to every true fire exceeds this is unmatched
DEFAULT_GATE_M = 100.0


def match_tracks_to_fires(
    estimates: Mapping[tuple[int, int], Mapping[str, np.ndarray]],
    truth: Mapping[int, Mapping[str, np.ndarray]],
    gate_m: float = DEFAULT_GATE_M,
    active_status: int = int(FireStatus.ACTIVE),
) -> dict[int, int]:
    """Track id -> true fire id (see the module doc); unmatched tracks are left out.

    ``estimates``: per (uav, track id) arrays t [s], x, y [m], status (``active_status`` = active);
    ``truth``: per fire id arrays t [s], x, y [m], status.
    """
    if not gate_m > 0:
        raise ReportInputError(f"gate_m must be > 0, got {gate_m}")
    samples: dict[int, list[np.ndarray]] = {}
    for (_uav, tid), e in estimates.items():
        t = np.asarray(e.get("t", ()), dtype=float)
        if t.size == 0:
            continue
        keep = np.ones(t.size, bool)
        if "status" in e and len(e["status"]) == t.size:
            keep = np.asarray(e["status"]) == active_status
        samples.setdefault(tid, []).append(
            np.column_stack([t, np.asarray(e["x"], float), np.asarray(e["y"], float)])[keep]
        )
    out: dict[int, int] = {}
    for tid in sorted(samples):
        s = np.vstack(samples[tid])
        best, best_d = None, np.inf
        for fid in sorted(truth):
            f = truth[fid]
            ft = np.asarray(f.get("t", ()), dtype=float)
            if ft.size == 0 or s.size == 0:
                continue
            burning = np.ones(ft.size, bool)
            if "status" in f and len(f["status"]) == ft.size:
                burning = np.asarray(f["status"]) == active_status
            if not burning.any():
                continue
            ft_b = ft[burning]
            inside = (s[:, 0] >= ft_b[0]) & (s[:, 0] <= ft_b[-1])
            if not inside.any():
                continue
            fx = np.interp(s[inside, 0], ft_b, np.asarray(f["x"], float)[burning])
            fy = np.interp(s[inside, 0], ft_b, np.asarray(f["y"], float)[burning])
            d = float(np.median(np.hypot(s[inside, 1] - fx, s[inside, 2] - fy)))
            if d < best_d:
                best, best_d = fid, d
        if best is not None and best_d <= gate_m:
            out[tid] = best
    return out
