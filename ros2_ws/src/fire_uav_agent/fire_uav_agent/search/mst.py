"""Fragment-merge minimum spanning tree and the radio radius r_max (CP III-E, Algorithm 1, Eq. 11).

Each agent starts as its own fragment (``fragID_v = v``). Every round:

1. PROBE: every agent broadcasts its fragment id and its lightest outgoing edge, i.e. the nearest
   agent in another fragment (Algorithm 1 GETBEST / REPORT; with all-to-all broadcast the report to
   the root is the same message).
2. MERGE: the root of each fragment (its smallest member id, CP III-E) takes the lightest of its
   members' edges (ONREPORT, line 18) and broadcasts it.
3. Every agent applies all MERGE edges (ONMERGEREQUEST): merged fragments take the smallest member id
   as fragment id and root, the tree's longest edge is ``max(w_f, w_f')`` (line 38).

When one fragment holds all ``n_agents`` (REPORTUP, line 46) the root broadcasts DONE with the
longest tree edge. Choice: the paper's pairwise MERGEREQUEST/ACCEPT/REJECT handshake is replaced by
applying every fragment's chosen edge in the same round (Boruvka's rule). With the strict total order
on edges (length, smaller id, larger id) the chosen edges never close a cycle, so this is the same
tree in at most ceil(log2 n) rounds and needs only the three message kinds of
``fire_uav_msgs/MstFragment``. Agents keep explicit membership lists, as in CP III-E (no GHS levels).

Edge lengths: an agent needs only its own row of distances. In the fleet each agent can compute
every peer's position at a sampled instant from the shared candidate, so the wire messages carry no
positions (choice; the paper does not say how neighbour distances are obtained).

Eq. 11: the radio radius of a candidate is the largest, over sampled mission instants, of the
longest MST edge, i.e. the smallest disc radius keeping the fleet connected at every instant.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np
from fire_uav_common.constants import MstKind

from .errors import MstError


class MstMessage(NamedTuple):
    """Field-for-field ``fire_uav_msgs/MstFragment`` (header omitted)."""

    uav_id: int
    kind: MstKind
    round: int
    sample_index: int
    fragment_id: int
    edge_from: int
    edge_to: int
    edge_length_m: float  # inf if none
    radius_m: float  # longest edge in the sender's fragment so far [m]


def _edge_key(length_m: float, a: int, b: int) -> tuple[float, int, int]:
    """Strict total order on edges (ties on length broken by ids), needed for Boruvka merging."""
    return (length_m, min(a, b), max(a, b))


class MstAgent:
    """One agent's state machine for one sampled instant.

    ``distances_m`` maps every other agent id to its distance from this agent [m].
    Call :meth:`probe`, then :meth:`on_probes` with all PROBEs of the round, then :meth:`on_merges`
    with all MERGEs of the round; repeat until :attr:`done`.
    """

    def __init__(self, uav_id: int, distances_m: Mapping[int, float], *, sample_index: int = 0) -> None:
        self.uav_id = int(uav_id)
        self.distances_m = {int(k): float(v) for k, v in distances_m.items() if int(k) != self.uav_id}
        if any(not (math.isfinite(d) and d >= 0.0) for d in self.distances_m.values()):
            raise MstError(f"agent {self.uav_id}: distances must be finite and >= 0")
        self.sample_index = int(sample_index)
        self.agent_ids = sorted([self.uav_id, *self.distances_m])
        self.n_agents = len(self.agent_ids)
        self.fragment_of: dict[int, int] = {v: v for v in self.agent_ids}  # fragID
        self.fragment_radius_m: dict[int, float] = {v: 0.0 for v in self.agent_ids}  # max_radius
        self.tree_edges: list[tuple[int, int, float]] = []  # known to every agent (broadcast merges)
        self.round = 0
        self.done = self.n_agents == 1

    @property
    def fragment_id(self) -> int:
        return self.fragment_of[self.uav_id]

    @property
    def is_root(self) -> bool:
        return self.fragment_id == self.uav_id

    @property
    def radius_m(self) -> float:
        """Longest edge in this agent's fragment so far [m]."""
        return self.fragment_radius_m[self.fragment_id]

    def members(self, fragment_id: int) -> list[int]:
        return [v for v in self.agent_ids if self.fragment_of[v] == fragment_id]

    def _message(self, kind: MstKind, edge: tuple[int, int, float] | None) -> MstMessage:
        a, b, w = edge if edge is not None else (self.uav_id, self.uav_id, math.inf)
        return MstMessage(
            uav_id=self.uav_id,
            kind=kind,
            round=self.round,
            sample_index=self.sample_index,
            fragment_id=self.fragment_id,
            edge_from=a,
            edge_to=b,
            edge_length_m=w,
            radius_m=self.radius_m,
        )

    def probe(self) -> MstMessage:
        """PROBE: fragment id and this agent's lightest outgoing edge (Algorithm 1 GETBEST)."""
        best = None
        for u, d in self.distances_m.items():
            if self.fragment_of[u] == self.fragment_id:
                continue
            if best is None or _edge_key(d, self.uav_id, u) < _edge_key(best[2], best[0], best[1]):
                best = (self.uav_id, u, d)
        return self._message(MstKind.PROBE, best)

    def on_probes(self, probes: Sequence[MstMessage]) -> MstMessage | None:
        """A fragment root picks its fragment's lightest outgoing edge (ONREPORT) -> MERGE; others None.

        Raises :class:`MstError` when a member's PROBE of this round is missing.
        """
        if self.done or not self.is_root:
            return None
        mine = {
            p.uav_id: p
            for p in probes
            if p.kind == MstKind.PROBE and p.round == self.round and p.sample_index == self.sample_index
        }
        members = self.members(self.fragment_id)
        missing = [v for v in members if v not in mine]
        if missing:
            raise MstError(f"root {self.uav_id}: PROBE missing from members {missing} in round {self.round}")
        best = None
        for v in members:
            p = mine[v]
            if not math.isfinite(p.edge_length_m):
                continue
            key = _edge_key(p.edge_length_m, p.edge_from, p.edge_to)
            if best is None or key < _edge_key(best[2], best[0], best[1]):
                best = (p.edge_from, p.edge_to, p.edge_length_m)
        if best is None:
            raise MstError(f"root {self.uav_id}: fragment has no outgoing edge but is not complete")
        return self._message(MstKind.MERGE, best)

    def on_merges(self, merges: Sequence[MstMessage]) -> MstMessage | None:
        """Apply every MERGE of the round (ONMERGEREQUEST). The final root returns DONE (REPORTUP)."""
        if self.done:
            return None
        roots = {self.fragment_of[v] for v in self.agent_ids}
        got = {
            m.fragment_id: m
            for m in merges
            if m.kind == MstKind.MERGE and m.round == self.round and m.sample_index == self.sample_index
        }
        if set(got) != roots:
            raise MstError(
                f"agent {self.uav_id}: round {self.round} MERGE from fragments {sorted(got)}, "
                f"expected {sorted(roots)}"
            )
        for fid in sorted(got):
            m = got[fid]
            fa, fb = self.fragment_of[m.edge_from], self.fragment_of[m.edge_to]
            if fa == fb:  # both fragments chose the same edge; already merged
                continue
            new = min(fa, fb)
            radius = max(self.fragment_radius_m[fa], self.fragment_radius_m[fb], m.edge_length_m)
            for v in self.agent_ids:
                if self.fragment_of[v] in (fa, fb):
                    self.fragment_of[v] = new
            self.fragment_radius_m[new] = radius
            self.tree_edges.append(
                (min(m.edge_from, m.edge_to), max(m.edge_from, m.edge_to), m.edge_length_m)
            )
        out = None
        if len(self.members(self.fragment_id)) == self.n_agents:
            self.done = True
            if self.is_root:
                out = self._message(MstKind.DONE, None)
        self.round += 1
        return out


class MstResult(NamedTuple):
    """Outcome of :func:`run_distributed_mst`."""

    radius_m: float  # longest MST edge [m]
    edges: tuple[tuple[int, int, float], ...]  # (a, b, length) with a < b
    rounds: int
    n_messages: int


def _distance_matrix(positions_m: np.ndarray) -> np.ndarray:
    p = np.asarray(positions_m, dtype=float)
    return np.linalg.norm(p[:, None, :] - p[None, :, :], axis=-1)


def run_distributed_mst(
    positions_m: np.ndarray, *, ids: Sequence[int] | None = None, sample_index: int = 0
) -> MstResult:
    """Synchronous lossless simulation of N :class:`MstAgent` exchanging broadcast messages."""
    pos = np.asarray(positions_m, dtype=float)
    if pos.ndim != 2 or pos.shape[1] != 2 or len(pos) == 0:
        raise MstError(f"positions_m must have shape (N, 2), got {pos.shape}")
    n = len(pos)
    ids = list(range(n)) if ids is None else [int(i) for i in ids]
    if len(set(ids)) != n:
        raise MstError("agent ids must be unique")
    dist = _distance_matrix(pos)
    agents = [
        MstAgent(ids[i], {ids[j]: dist[i, j] for j in range(n) if j != i}, sample_index=sample_index)
        for i in range(n)
    ]
    n_messages = 0
    done_msg = None
    rounds = 0
    while not all(a.done for a in agents):
        if rounds > n:
            raise MstError("fragment merge did not terminate")  # pragma: no cover
        probes = [a.probe() for a in agents]
        merges = [m for a in agents if (m := a.on_probes(probes)) is not None]
        dones = [m for a in agents if (m := a.on_merges(merges)) is not None]
        n_messages += len(probes) + len(merges) + len(dones)
        done_msg = dones[0] if dones else done_msg
        rounds += 1
    edges = tuple(agents[0].tree_edges)
    radius = done_msg.radius_m if done_msg is not None else 0.0
    return MstResult(radius_m=float(radius), edges=edges, rounds=rounds, n_messages=n_messages)


def centralised_mst_radius_m(positions_m: np.ndarray) -> float:
    """Longest edge of the Euclidean MST by scipy (reference for tests, fast path for batches)."""
    pos = np.asarray(positions_m, dtype=float)
    if len(pos) < 2:
        return 0.0
    d = _distance_matrix(pos)
    # scipy treats 0 as "no edge": keep coincident agents connected with a tiny positive length
    off = ~np.eye(len(pos), dtype=bool)
    d[off & (d == 0.0)] = 1e-300
    from scipy.sparse.csgraph import minimum_spanning_tree  # when a search role needs it

    tree = minimum_spanning_tree(d)
    return float(tree.data.max()) if tree.nnz else 0.0


def mission_radius_m(positions_m: np.ndarray, *, backend: str = "distributed") -> tuple[float, np.ndarray]:
    """Eq. 11: ``r_max = max_k r(t_k)`` over sampled instants; positions (K, N, 2) [m].

    ``backend`` is ``"distributed"`` (Algorithm 1 simulated) or ``"centralised"`` (scipy; same value,
    see the tests). Returns ``(r_max, r(t_k) for all k)``.
    """
    pos = np.asarray(positions_m, dtype=float)
    if pos.ndim != 3 or pos.shape[2] != 2:
        raise MstError(f"positions_m must have shape (K, N, 2), got {pos.shape}")
    if backend == "distributed":
        radii = np.array([run_distributed_mst(pos[k], sample_index=k).radius_m for k in range(len(pos))])
    elif backend == "centralised":
        radii = np.array([centralised_mst_radius_m(pos[k]) for k in range(len(pos))])
    else:
        raise MstError(f"unknown backend {backend!r}; use 'distributed' or 'centralised'")
    return float(radii.max()) if radii.size else 0.0, radii
