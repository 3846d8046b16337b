"""Fragment-merge MST (CP Algorithm 1) and the radio radius r_max (Eq. 11)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from fire_uav_agent.search.errors import MstError
from fire_uav_agent.search.mst import (
    MstAgent,
    MstKind,
    centralised_mst_radius_m,
    mission_radius_m,
    run_distributed_mst,
)
from scipy.sparse.csgraph import minimum_spanning_tree
from scipy.spatial.distance import pdist, squareform

MSG_DIR = Path(__file__).resolve().parents[2] / "fire_uav_msgs" / "msg"


def _scipy_tree(points: np.ndarray) -> tuple[float, float]:
    tree = minimum_spanning_tree(squareform(pdist(points)))
    return float(tree.data.max()), float(tree.data.sum())


@pytest.mark.parametrize("seed", range(25))
def test_distributed_radius_equals_centralised_mst(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 16))
    pts = rng.uniform(0.0, 2000.0, size=(n, 2))
    res = run_distributed_mst(pts)
    radius, weight = _scipy_tree(pts)
    assert res.radius_m == pytest.approx(radius)
    assert sum(e[2] for e in res.edges) == pytest.approx(weight)  # the same tree, not only its radius
    assert len(res.edges) == n - 1
    assert res.rounds <= math.ceil(math.log2(n))


def test_equal_lengths_do_not_create_cycles() -> None:
    pts = np.array([[x, y] for x in range(4) for y in range(3)], dtype=float) * 100.0  # many ties
    res = run_distributed_mst(pts)
    assert len(res.edges) == len(pts) - 1
    assert res.radius_m == pytest.approx(100.0)
    assert res.radius_m == pytest.approx(centralised_mst_radius_m(pts))


def test_single_agent_and_coincident_agents() -> None:
    assert run_distributed_mst(np.array([[5.0, 5.0]])).radius_m == 0.0
    pts = np.array([[0.0, 0.0], [0.0, 0.0], [300.0, 400.0]])
    assert run_distributed_mst(pts).radius_m == pytest.approx(500.0)
    assert centralised_mst_radius_m(pts) == pytest.approx(500.0)


def test_mission_radius_is_max_over_instants() -> None:
    rng = np.random.default_rng(7)
    pos = rng.uniform(0.0, 1000.0, size=(30, 5, 2))
    r_max, radii = mission_radius_m(pos)
    expected = [_scipy_tree(pos[k])[0] for k in range(30)]
    np.testing.assert_allclose(radii, expected)
    assert r_max == pytest.approx(max(expected))
    assert mission_radius_m(pos, backend="centralised")[0] == pytest.approx(r_max)
    with pytest.raises(MstError, match="backend"):
        mission_radius_m(pos, backend="gossip")


def test_state_machine_messages_one_round() -> None:
    # three agents on a line: 0 --100-- 1 --300-- 2
    d = {0: {1: 100.0, 2: 400.0}, 1: {0: 100.0, 2: 300.0}, 2: {0: 400.0, 1: 300.0}}
    agents = [MstAgent(i, d[i], sample_index=4) for i in range(3)]
    probes = [a.probe() for a in agents]
    assert [(p.kind, p.fragment_id, p.edge_to, p.edge_length_m) for p in probes] == [
        (MstKind.PROBE, 0, 1, 100.0),
        (MstKind.PROBE, 1, 0, 100.0),
        (MstKind.PROBE, 2, 1, 300.0),
    ]
    merges = [m for a in agents if (m := a.on_probes(probes)) is not None]
    assert len(merges) == 3 and all(m.kind == MstKind.MERGE and m.sample_index == 4 for m in merges)
    dones = [m for a in agents if (m := a.on_merges(merges)) is not None]
    assert len(dones) == 1
    assert dones[0].kind == MstKind.DONE and dones[0].uav_id == 0 and dones[0].radius_m == 300.0
    assert all(a.done and a.fragment_id == 0 for a in agents)


def test_missing_messages_are_errors_not_silent() -> None:
    d = {0: {1: 1.0, 2: 2.0}, 1: {0: 1.0, 2: 1.5}, 2: {0: 2.0, 1: 1.5}}
    agents = [MstAgent(i, d[i]) for i in range(3)]
    probes = [a.probe() for a in agents]
    merges = [m for a in agents if (m := a.on_probes(probes)) is not None]
    with pytest.raises(MstError, match="MERGE from fragments"):
        agents[0].on_merges(merges[:2])
    # after round 0 fragment {0,1,2} is complete; force a root to miss a member's probe instead
    b = [MstAgent(i, d[i]) for i in range(3)]
    with pytest.raises(MstError, match="PROBE missing"):
        b[0].on_probes([])


def test_kinds_match_wire_format() -> None:
    text = (MSG_DIR / "MstFragment.msg").read_text()
    consts = dict(re.findall(r"uint8 KIND_(\w+) = (\d+)", text))
    assert {k: int(v) for k, v in consts.items()} == {k.name: int(k) for k in MstKind}
