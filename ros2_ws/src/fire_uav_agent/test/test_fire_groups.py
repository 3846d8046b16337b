"""``tactics.fire_groups`` (the ``auto`` tactic's fires) against two references.

Truths: (1) the implementation before the numpy components (cKDTree pairs fed to scipy's
``connected_components`` through a sparse matrix, relabelled by first cell), copied here, since the
missions must not change by a bit; (2) an independent one, breadth-first search over the dense
matrix of squared distances ``dx*dx + dy*dy <= link_m**2`` (cKDTree's test for "distance at most
r"), with fires numbered by their first cell. Fronts: random cells of a 5 m raster (as
``fire_front`` makes them) at several densities, random real positions, and chains whose gaps are
exactly ``link_m`` (along x, along y, on a 3-4-5 diagonal) or one ulp more.
"""

from __future__ import annotations

import numpy as np
import pytest
from fire_uav_agent.fire_front import FrontCells
from fire_uav_agent.tactics import fire_groups
from fire_uav_common.constants import CellState
from hypothesis import given, settings
from hypothesis import strategies as st


def front(x, y) -> FrontCells:
    x = np.asarray(x, dtype=float)
    n = x.size
    return FrontCells(
        x, np.asarray(y, dtype=float), np.full(n, int(CellState.BURNING)), np.zeros(n), np.full(n, np.nan)
    )


def groups_scipy(f: FrontCells, link_m: float) -> np.ndarray:
    """The implementation of commit 1a20769 (reference for bit-identical missions)."""
    n = len(f)
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(np.column_stack([f.x_m, f.y_m])).query_pairs(link_m, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, labels = connected_components(graph, directed=False)
    _, first = np.unique(labels, return_index=True)
    order = np.argsort(np.argsort(first))
    return order[labels].astype(np.int64)


def groups_bfs(f: FrontCells, link_m: float) -> np.ndarray:
    """Independent: breadth-first search over the dense adjacency, fires numbered as found."""
    x, y = f.x_m, f.y_m
    dx, dy = x[:, None] - x[None, :], y[:, None] - y[None, :]
    adj = dx * dx + dy * dy <= link_m * link_m
    lab = np.full(x.size, -1, dtype=np.int64)
    g = 0
    for s in range(x.size):
        if lab[s] >= 0:
            continue
        todo = [s]
        lab[s] = g
        while todo:
            k = todo.pop()
            for m in np.flatnonzero(adj[k] & (lab < 0)):
                lab[m] = g
                todo.append(int(m))
        g += 1
    return lab


def check(f: FrontCells, link_m: float) -> np.ndarray:
    got = fire_groups(f, link_m)
    assert got.dtype == np.int64
    np.testing.assert_array_equal(got, groups_scipy(f, link_m))
    np.testing.assert_array_equal(got, groups_bfs(f, link_m))
    return got


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n=st.integers(1, 300),
    span_cells=st.integers(5, 200),
    link_m=st.sampled_from([5.0, 7.5, 10.0, 25.0, 100.0]),
)
def test_raster_fronts_match_both_references(seed: int, n: int, span_cells: int, link_m: float) -> None:
    """Cells of a 5 m raster (centres x0 + (j + 0.5) * 5 m): many pairs exactly 5, 10, 25 or 100 m
    apart, so exact ties at ``link_m`` are the common case, not the exception."""
    rng = np.random.default_rng(seed)
    cells = rng.choice(span_cells * span_cells, size=min(n, span_cells * span_cells), replace=False)
    i, j = np.divmod(cells, span_cells)
    check(front(3.0 + (j + 0.5) * 5.0, -40.0 + (i + 0.5) * 5.0), link_m)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(0, 120), link_m=st.floats(0.5, 300.0))
def test_real_positions_match_both_references(seed: int, n: int, link_m: float) -> None:
    rng = np.random.default_rng(seed)
    check(front(rng.uniform(-500, 1500, n), rng.uniform(0, 1000, n)), link_m)


@pytest.mark.parametrize(
    ("step_xy", "link_m"),
    [((100.0, 0.0), 100.0), ((0.0, 100.0), 100.0), ((60.0, 80.0), 100.0), ((5.0, 0.0), 5.0)],
)
def test_chains_at_exactly_link_m_are_one_fire_and_one_ulp_more_breaks_them(step_xy, link_m) -> None:
    """Gaps of exactly ``link_m`` (60^2 + 80^2 = 100^2 in floats, exactly) chain: one fire; with
    one gap ulps longer the chain splits there, into the fires before and after it."""
    k = np.arange(12.0)
    x, y = 250.0 + k * step_xy[0], 10.0 + k * step_xy[1]
    assert check(front(x, y), link_m).tolist() == [0] * 12
    order = np.r_[7:12, 0:7]  # the chain listed out of order: fires numbered by their first cell
    assert check(front(x[order], y[order]), link_m).tolist() == [0] * 12
    # open a gap after the 5th cell: everything beyond it moves a few ulps away
    far = k >= 5
    x2 = np.where(far, x + np.sign(step_xy[0]) * 4e-13 * max(1.0, step_xy[0]), x)
    y2 = np.where(far, y + np.sign(step_xy[1]) * 4e-13 * max(1.0, step_xy[1]), y)
    labels = check(front(x2, y2), link_m)
    assert labels.tolist() == [0] * 5 + [1] * 7
    # listed from cell 7 on: the far fire (cells 7-11, then 5-6) is fire 0, the near one fire 1
    assert check(front(x2[order], y2[order]), link_m).tolist() == [0] * 5 + [1] * 5 + [0] * 2


def test_interleaved_fires_are_numbered_by_their_first_cell() -> None:
    """Cells of three fires listed interleaved (by hand: fire of cell 0, then of cell 1, ...)."""
    x = [900.0, 0.0, 500.0, 10.0, 905.0, 510.0, 20.0]
    assert check(front(x, [0.0] * 7), 30.0).tolist() == [0, 1, 2, 1, 0, 2, 1]


def test_a_long_snake_needs_many_hops_and_is_one_fire() -> None:
    """A serpentine front of 400 cells whose fire is one chain only through its whole length (the
    rows are 40 m apart, joined at alternate ends): label propagation must run to the end."""
    xs, ys = [], []
    for r in range(10):
        cols = range(40) if r % 2 == 0 else range(39, -1, -1)
        for c in cols:
            xs.append(c * 5.0)
            ys.append(r * 40.0)
        # the joint to the next row, at this row's last column
        last = 39 * 5.0 if r % 2 == 0 else 0.0
        xs.extend([last] * 7)
        ys.extend([r * 40.0 + 5.0 * m for m in range(1, 8)])
    order = np.random.default_rng(3).permutation(len(xs))
    labels = check(front(np.array(xs)[order], np.array(ys)[order]), 5.0)
    assert set(labels.tolist()) == {0}
