"""Consensus over a raster fire's front: what an agent shares on ``/fleet/front`` and how it merges.

Each agent publishes (``FireFront``, every ``front_every_steps``) its current active front --
own sightings and cells learnt from peers alike, so knowledge travels over several hops -- plus
*retractions*: cells it published last time that are no longer on its front, with their newer
state (BURNED after a drop, UNBURNED never) and observation time -- plus every BURNING or
BURNED cell observed (by anyone) within the last ``recent_s`` seconds that is not on the front.
A receiver merges every cell with :meth:`FrontPicture.merge` (newest observation wins per cell).

Why the recent cells: a cell an agent never had on its own front (first seen BURNED after a drop,
or burning inside the fire) was otherwise never shared, so a peer that saw it BURNING earlier kept
it on its front for ever (test_front_consensus.py has the case). Every
new sighting now reaches the peers, repeated in each message for ``recent_s`` (3 messages at the
default 1 Hz), so one lost message does not lose it. With a connected fleet and
no new sightings, every agent's front converges to the same set after as many rounds as the
graph's diameter: merging is a per-cell maximum over (time, state), which is associative,
commutative and idempotent (a join), so the order and duplication of messages do not matter.
Positions [m; map frame], times [s sim].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from fire_uav_common.constants import CellState

from .errors import ConfigError
from .fire_front import FrontCells, FrontPicture

__all__ = ["FrontSharing", "PeerFront", "concat", "same_cell_size"]

#: cell sides closer than this (relative) are the same raster's: both come as float32 on the wire
CELL_SIZE_REL_TOL = 1e-6


@dataclass(frozen=True)
class PeerFront:
    """A peer's ``FireFront``, ROS-free. ``cell_size_m`` [m]: the raster cell side of the sender's
    picture (``FireFront.cell_size_m``); its cells are merged by their centres into a picture of
    this side only (:func:`same_cell_size`)."""

    uav_id: int
    sequence: int
    step: int
    cells: FrontCells
    cell_size_m: float


def same_cell_size(a_m: float, b_m: float) -> bool:
    """Whether two pictures' cell sides [m] are one raster's (within float32 rounding).

    :meth:`FrontPicture.merge` puts each shared cell into the receiver's cell holding its centre:
    cells of another side would land one per receiver cell (a coarser sender's front a sparse
    scatter of isolated cells, each counted on the front) and be taken as that cell's state. Every
    agent learns the side from the same world's ``FireCells``, so a different one is a foreign or
    broken sender; NaN or 0 is never the same."""
    return math.isclose(a_m, b_m, rel_tol=CELL_SIZE_REL_TOL) and a_m > 0


def concat(a: FrontCells, b: FrontCells) -> FrontCells:
    return FrontCells(
        np.r_[a.x_m, b.x_m],
        np.r_[a.y_m, b.y_m],
        np.r_[a.state, b.state].astype(np.int64),
        np.r_[a.t_obs_s, b.t_obs_s],
        np.r_[a.ros_mps, b.ros_mps],
    )


class FrontSharing:
    """Builds one agent's outgoing front messages (front + retractions)."""

    def __init__(self, recent_s: float = 3.0) -> None:
        if not recent_s >= 0:
            raise ConfigError(f"FrontSharing: recent_s must be >= 0 [s], got {recent_s}")
        self.recent_s = recent_s
        self._sent_x = np.zeros(0)
        self._sent_y = np.zeros(0)

    def message(self, picture: FrontPicture, t_s: float) -> FrontCells:
        """Cells to publish at ``t_s`` [s]: the active front and the retractions (module doc)."""
        front = picture.front(t_s)
        out = front
        if self._sent_x.size:
            old = picture.cells_at(self._sent_x, self._sent_y)
            fi, fj, _ = picture.index(front.x_m, front.y_m)
            oi, oj, _ = picture.index(old.x_m, old.y_m)
            on_front = np.isin(oi * picture.nx + oj, fi * picture.nx + fj)
            keep = ~on_front & np.isfinite(old.t_obs_s)
            if keep.any():
                out = concat(
                    front,
                    FrontCells(
                        old.x_m[keep], old.y_m[keep], old.state[keep], old.t_obs_s[keep], old.ros_mps[keep]
                    ),
                )
        self._sent_x, self._sent_y = front.x_m.copy(), front.y_m.copy()
        return concat(out, self._recent(picture, t_s, out))

    def _recent(self, picture: FrontPicture, t_s: float, out: FrontCells) -> FrontCells:
        """BURNING / BURNED cells observed within ``recent_s`` of ``t_s`` and not in ``out``."""
        with np.errstate(invalid="ignore"):
            mask = (picture.t_obs >= t_s - self.recent_s) & np.isin(
                picture.state, (CellState.BURNING, CellState.BURNED)
            )
        if out.x_m.size:
            oi, oj, ok = picture.index(out.x_m, out.y_m)
            mask[oi[ok], oj[ok]] = False
        i, j = np.nonzero(mask)
        x, y = picture.centre_xy(i, j)
        return FrontCells(
            x, y, picture.state[i, j].astype(np.int64), picture.t_obs[i, j], np.full(i.size, np.nan)
        )
