"""A raster fire is not declared out over its burnt-out centre while its edge still burns.

Constructed case: a burnt disc of radius 150 m around (500, 500) with a burning arc at its east
edge (the remnant of a flank attack). The world's fire sensor reports the fire's centroid and the
radius of its burned area only while a burning cell is within the 70 m sensor range, so a UAV over
the centroid sees nothing; the front picture (its own sightings) still holds the burning arc.
"""

from __future__ import annotations

import numpy as np
from fire_uav_agent.consensus import FireConsensus
from fire_uav_agent.fire_front import FrontConfig, FrontPicture
from fire_uav_common.constants import CellState

CS = 10.0
CX, CY, R = 500.0, 500.0, 150.0


def _picture_with_burning_edge(t_s: float) -> FrontPicture:
    fp = FrontPicture(FrontConfig((0.0, 1000.0, 0.0, 1000.0), CS))
    g = np.arange(CS / 2, 1000.0, CS)
    xx, yy = np.meshgrid(g, g)
    r = np.hypot(xx - CX, yy - CY)
    state = np.full(xx.shape, CellState.UNBURNED)
    state[r <= R] = CellState.BURNED
    state[(r <= R) & (r > R - 20.0) & (xx > CX + 120.0)] = CellState.BURNING  # the east arc
    fp.observe(xx.ravel(), yy.ravel(), state.ravel(), t_s)
    return fp


def _seen_then_over_centre(burning: np.ndarray | None) -> FireConsensus:
    fc = FireConsensus(0)
    # seen at t = 10 s from the east edge (a burning cell in range): centroid + burned radius
    fc.observe(np.array([[10.0, CX, CY, R]]), (CX + 140.0, CY), 10.0, burning)
    for k in range(20):  # 2 s over the centroid: no burning cell within 70 m, no detection
        fc.observe(np.zeros((0, 4)), (CX + 5.0, CY), 11.0 + 0.1 * k, burning)
    return fc


def test_known_burning_cells_near_a_raster_track_block_negative_evidence() -> None:
    fp = _picture_with_burning_edge(10.0)
    burning = fp.burning_xy(11.0)
    assert len(burning) > 0 and np.all(np.hypot(burning[:, 0] - CX, burning[:, 1] - CY) > 70.0)
    assert not _seen_then_over_centre(burning).all_out()
    # without the front picture (the FF rule alone) the same looks end it: the false extinction
    assert _seen_then_over_centre(None).all_out()


def test_once_the_edge_is_seen_burnt_the_fire_ends_over_its_centre() -> None:
    fp = _picture_with_burning_edge(10.0)
    b = fp.burning_xy(10.0)
    fp.observe(b[:, 0], b[:, 1], np.full(len(b), CellState.BURNED), 10.5)  # the arc put out
    assert len(fp.burning_xy(11.0)) == 0
    assert _seen_then_over_centre(fp.burning_xy(11.0)).all_out()


def test_burning_cells_far_from_a_track_or_too_old_do_not_keep_it() -> None:
    """Cells beyond the association gate belong to another fire; cells older than the picture's
    ``max_age_s`` (240 s) have left it, so a ghost track still ends."""
    far = np.array([[CX + 2.5 * R, CY]])  # gate = max(40, 2 x 150) = 300 m < 375 m
    assert _seen_then_over_centre(far).all_out()
    fp = _picture_with_burning_edge(10.0)
    assert len(fp.burning_xy(10.0 + 240.0)) > 0 and len(fp.burning_xy(10.0 + 241.0)) == 0
