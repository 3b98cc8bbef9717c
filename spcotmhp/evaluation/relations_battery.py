"""The relation battery: "the bedroom closest to the kitchen" and its kin, planned on seeded homes whose names
repeat (three bedrooms each: :func:`~spcotmhp.datasets.synthetic_battery.battery_home`), each plan checked against
the rule the instruction states, computed here independently of the planner.

For every name with two or more instances X and every other place Y (Z) of the home, from a seeded start:
"go to the X closest to the Y", "... farthest from the Y", "... next to the Y", "... between the Y and the Z",
"go to the largest X", "go to the smallest X". The oracle (:class:`Oracle`) measures what
:mod:`spcotmhp.planning.relations` states, by other means: geodesic lengths of the cost-optimal paths between the
places' planning points by scipy's Dijkstra over the planner's step costs (Eq. 26's map term, 8-connected,
diagonals sqrt 2); territory contacts cell by cell; areas from the Gaussians. Each request is

* ``right``: the plan ends at an instance the rule names (on a tie within the robot's diameter, or several next to
  the other place, any of them: issue 34), and the explanation says the relation (and the tie);
* ``none named``: refused (:class:`~spcotmhp.errors.UnresolvedRelation`) where the rule names no instance (none
  next to the other place, none connected to it), as it should be;
* ``refused``: refused although the rule names one;
* ``wrong``: planned to another instance, or planned where the rule names none, or an explanation that does not
  say the relation or the tie (silently wrong).
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import dijkstra

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import SpcotmhpError, UnresolvedRelation
from spcotmhp.planning.planner import HierarchicalPlanner

KINDS = ("closest", "farthest", "next_to", "between", "largest", "smallest")
PHRASES = {
    "closest": "go to the {x} closest to the {y}",
    "farthest": "go to the {x} farthest from the {y}",
    "next_to": "go to the {x} next to the {y}",
    "between": "go to the {x} between the {y} and the {z}",
    "largest": "go to the largest {x}",
    "smallest": "go to the smallest {x}",
}


@dataclass
class RelationResult:
    """The relation battery's counts on one home, by kind of relation, and the texts of what went wrong."""

    home: str
    counts: Counter = field(default_factory=Counter)  # (kind, verdict) -> requests
    wrong: list[str] = field(default_factory=list)


class Oracle:
    """The stated rules of :mod:`spcotmhp.planning.relations`, measured independently of the planner's graph
    queries (module docstring)."""

    def __init__(self, planner: HierarchicalPlanner) -> None:
        graph = planner.graph
        self.planner = planner
        self.cost = np.asarray(graph.map_cost, dtype=float)
        self.shape = self.cost.shape
        self.resolution = planner.resolution
        self.diameter = planner.diameter_cells * planner.resolution
        self.node_place = np.asarray(graph.node_place)
        self.node_cell = np.asarray(graph.node_cell)
        self.matrix = _grid_graph(self.cost)
        self.contacts = _contacts_by_loop(np.asarray(graph.territory), planner.model.K) | np.asarray(graph.connected)
        self.areas = np.array([math.pi * math.sqrt(max(np.linalg.det(s), 0.0)) for s in planner.model.Sigma])
        self._lengths: dict[int, np.ndarray] = {}

    def distance(self, a: int, b: int) -> float:
        """Metres of the cost-optimal path between a node of place a and a node of place b (the shortest such)."""
        if a == b:
            return 0.0
        best = math.inf
        for p, q in ((a, b), (b, a)):  # the shorter of the two directions, as the rule says
            for i in np.flatnonzero(self.node_place == p):
                lengths = self._from_node(int(i))
                best = min([best, *(float(lengths[int(j)]) for j in np.flatnonzero(self.node_place == q))])
        return best

    def _from_node(self, i: int) -> np.ndarray:
        """Metres of the cost-optimal path from node i to every node (inf where none)."""
        if i not in self._lengths:
            w = self.shape[1]
            source = int(self.node_cell[i, 0]) * w + int(self.node_cell[i, 1])
            _, pred = dijkstra(self.matrix, indices=source, return_predecessors=True)
            out = np.full(len(self.node_place), math.inf)
            for j, (r, c) in enumerate(self.node_cell):
                out[j] = _path_metres(pred, source, int(r) * w + int(c), w) * self.resolution
            self._lengths[i] = out
        return self._lengths[i]

    def expected(self, kind: str, candidates: list[int], others: list[list[int]]) -> tuple[int, ...]:
        """The instances the rule names (several on a tie within the robot's diameter, or several next to the other
        place), or none (nothing next to it, nothing connected)."""
        if kind == "next_to":
            return tuple(k for k in candidates if any(self.contacts[k, o] for o in others[0] if o != k))
        if kind in ("largest", "smallest"):
            measure = {k: 2.0 * math.sqrt(float(self.areas[k]) / math.pi) for k in candidates}  # equal-area circle
        elif kind == "between":
            measure = {
                k: min(
                    self.distance(y, k) + self.distance(k, z) - self.distance(y, z)
                    for y in others[0]
                    for z in others[1]
                )
                for k in candidates
            }
        else:
            measure = {k: min(self.distance(k, o) for o in others[0] if o != k) for k in candidates}
        finite = {k: v for k, v in measure.items() if math.isfinite(v)}
        if not finite:
            return ()
        best = (max if kind in ("farthest", "largest") else min)(finite.values())
        return tuple(k for k, v in finite.items() if abs(v - best) < self.diameter)


def evaluate_relations(dataset: Dataset, seed: int = 0, per_kind: int = 6) -> RelationResult:
    """The relation battery on one home with supervised parameters (truth labels): ``per_kind`` seeded requests
    of each kind for every repeated name (module docstring)."""
    from spcotmhp.learning.supervised import fit_supervised

    planner = HierarchicalPlanner(fit_supervised(dataset))
    oracle = Oracle(planner)
    rng = np.random.default_rng(seed)
    names = planner.names
    active = [int(k) for k in np.flatnonzero(planner.model.active_places) if int(k) in set(oracle.node_place.tolist())]
    by_name: dict[str, list[int]] = {}
    for k in active:
        by_name.setdefault(names[k], []).append(k)
    free = np.argwhere(np.isfinite(oracle.cost))
    out = RelationResult(dataset.name)
    for x, cands in by_name.items():
        if len(cands) < 2 or len(x.split()) > 1:
            continue
        others = [n for n in by_name if n != x and all(w not in x.split() for w in n.split())]
        if len(others) < 2:
            continue
        for kind in KINDS:
            for _ in range(per_kind if kind not in ("largest", "smallest") else 1):
                y, z = (str(n) for n in rng.choice(others, size=2, replace=False))
                text = PHRASES[kind].format(x=x, y=y, z=z)
                args = {"largest": [], "smallest": [], "between": [by_name[y], by_name[z]]}.get(kind, [by_name[y]])
                want = oracle.expected(kind, cands, args)
                start = planner.model.require_map().cell_to_world(planner.graph.to_map(free[rng.integers(len(free))]))
                verdict = _verdict(planner, text, tuple(start), want, kind)
                out.counts[kind, verdict] += 1
                if verdict == "wrong":
                    out.wrong.append(f"{dataset.name}: {text!r} (rule: {list(want)})")
    return out


def _verdict(planner: HierarchicalPlanner, text: str, start: tuple, want: tuple[int, ...], kind: str) -> str:
    try:
        plan = planner.plan(text, start)
    except UnresolvedRelation:
        return "none named" if not want else "refused"
    except SpcotmhpError:
        return "refused"
    said = "the largest one" if kind == "largest" else "the smallest one" if kind == "smallest" else "the one "
    said = said if kind != "next_to" or len(want) == 1 else "next to"
    tie = len(want) == 1 or ("tied with" in plan.explanation or f"one of {len(want)} next to" in plan.explanation)
    if plan.goal.id not in want or said not in plan.explanation or not tie:
        return "wrong"
    return "right"


def _grid_graph(cost: np.ndarray) -> csr_matrix:
    """The 8-connected grid as a sparse graph: entering a cell costs its step cost, diagonals times sqrt 2."""
    h, w = cost.shape
    rows, cols, vals = [], [], []
    ok = np.isfinite(cost)
    index = np.arange(h * w).reshape(h, w)
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1), (0, -1), (-1, 0), (-1, -1), (-1, 1)):
        r0, r1 = max(0, -dr), h - max(0, dr)
        c0, c1 = max(0, -dc), w - max(0, dc)
        a = index[r0:r1, c0:c1]
        b = index[r0 + dr : r1 + dr, c0 + dc : c1 + dc]
        both = ok[r0:r1, c0:c1] & ok[r0 + dr : r1 + dr, c0 + dc : c1 + dc]
        step = math.sqrt(2.0) if dr and dc else 1.0
        rows.append(a[both])
        cols.append(b[both])
        vals.append(cost[r0 + dr : r1 + dr, c0 + dc : c1 + dc][both] * step)
    return coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(h * w, h * w)
    ).tocsr()


def _path_metres(pred: np.ndarray, source: int, target: int, w: int) -> float:
    """Length in cells of the predecessor path from ``source`` to ``target`` (inf when none)."""
    if target == source:
        return 0.0
    if pred[target] < 0:
        return math.inf
    total, node = 0.0, target
    while node != source:
        prev = int(pred[node])
        dr, dc = abs(node // w - prev // w), abs(node % w - prev % w)
        total += math.sqrt(2.0) if dr and dc else 1.0
        node = prev
    return total


def _contacts_by_loop(territory: np.ndarray, K: int) -> np.ndarray:
    """(K, K) places whose territories share an edge of two cells, cell by cell."""
    out = np.zeros((K, K), dtype=bool)
    h, w = territory.shape
    for r in range(h):
        for c in range(w):
            a = territory[r, c]
            if a < 0:
                continue
            for rr, cc in ((r + 1, c), (r, c + 1)):
                if rr < h and cc < w and territory[rr, cc] >= 0 and territory[rr, cc] != a:
                    out[a, territory[rr, cc]] = out[territory[rr, cc], a] = True
    return out
