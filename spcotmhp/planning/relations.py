"""Relations that pick one of several places with the same name ("the bedroom closest to the bath"), answered by
the map: which instance of a name a relation means, by a rule stated here, or a refusal naming the candidates.

A relation is part of a place phrase of an instruction (:class:`Relation`, read by the grammar); the planner asks
:func:`resolve` for the instances it means among those the phrase's name gives (``candidates``, a (K,) mask of
places). Each rule uses one term of the learned model:

* ``closest`` / ``farthest`` ("closest to", "nearest", "near", "by"; "farthest from"): the instance whose planning
  point (its node of the planning graph, Algorithm 1 line 2) has the shortest / longest geodesic to a planning
  point of the other place, measured along the partial path of Eq. 27 (the path the robot would drive, in metres).
* ``next_to`` ("next to", "beside", "adjacent to"): the instance whose territory (the cells where it is the most
  probable place, Eq. 3) touches a territory of the other place, or which psi (Eq. 7) connects to it (the place
  graph's edges, Figure 3). Exactly one instance may be next to it: two or more, or none, are refused.
* ``between`` ("between the kitchen and the bath"): the instance with the smallest detour
  d(Y, X) + d(X, Z) - d(Y, Z) on the geodesics above (an instance on the way from one to the other has a detour
  near 0).
* ``largest`` / ``smallest``: the instance whose Gaussian N(mu_k, Sigma_k) (Eqs. 5-6) covers the largest / smallest
  area, pi sqrt(det Sigma_k) (its 1-sigma ellipse).

Ties are said in the robot's own terms (issue 34): two instances whose geodesics (or detours) differ by less than
the robot's diameter, or whose areas' equal-area circles differ in diameter by less than it, are equally close (or
large) for a robot, whose place points are estimates it cannot place more finely than its own size. On such a tie
every tied instance satisfies the relation: the stage keeps them all, the plan ends at the one the Eq. 28 search
finds best (the one its path reaches at the least cost from the robot's start), and the explanation says they were
tied, with their measures; "next to" with two or more instances next to the other place is the same. Refused
(:class:`~spcotmhp.errors.UnresolvedRelation`) only where the map holds no answer: the other place is unknown, no
instance is connected to it, or none is next to it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from spcotmhp.errors import PlanningError, UnresolvedRelation
from spcotmhp.language.meaning import Relation
from spcotmhp.planning.assemble import path_length

if TYPE_CHECKING:
    from spcotmhp.planning.graph import PlanningGraph


class PlaceGeometry:
    """What relations measure on one planning graph and model: geodesic lengths between places' planning points
    (memoised), territory contacts and connected places, and the places' Gaussian areas.

    ``node_place``: (M,) the place of each planning node; ``path_length(i, j)``: metres of the partial path from
    node i into node j (inf when there is none); ``touching``: (K, K) places whose territories touch or which the
    place graph connects; ``areas``: (K,) pi sqrt(det Sigma_k); ``diameter_m``: the robot's diameter."""

    def __init__(
        self,
        node_place: np.ndarray,
        path_length: Callable[[int, int], float],
        touching: np.ndarray,
        areas: np.ndarray,
        diameter_m: float,
    ) -> None:
        self.node_place = np.asarray(node_place)
        self._length = path_length
        self.touching = np.asarray(touching, dtype=bool)
        self.areas = np.asarray(areas, dtype=float)
        self.diameter_m = float(diameter_m)
        self._memo: dict[tuple[int, int], float] = {}

    def distance(self, a: int, b: int) -> float:
        """Geodesic metres between places a and b: the shortest partial path from a node of one into a node of
        the other, either way (inf when no node of one reaches the other; 0 for a place and itself)."""
        if a == b:
            return 0.0
        key = (min(a, b), max(a, b))
        if key not in self._memo:
            na, nb = np.flatnonzero(self.node_place == a), np.flatnonzero(self.node_place == b)
            best = min((self._length(int(i), int(j)) for i in na for j in nb), default=math.inf)
            self._memo[key] = min(best, min((self._length(int(j), int(i)) for i in na for j in nb), default=math.inf))
        return self._memo[key]

    def nearest(self, k: int, others: np.ndarray) -> float:
        """Geodesic metres from place k to the nearest of the places ``others`` (a (K,) mask)."""
        return min((self.distance(k, int(o)) for o in np.flatnonzero(others)), default=math.inf)


def resolve(
    relation: Relation,
    candidates: np.ndarray,
    others: Sequence[np.ndarray],
    geometry: PlaceGeometry,
    name: Callable[[int], str],
) -> tuple[np.ndarray, dict[int, str]]:
    """The (K,) mask of the instances among ``candidates`` that ``relation`` means (one, or the tied ones: module
    docstring), and how the explanation says each was picked ("the one closest to the bath"); ``others``: the (K,)
    masks of the relation's other places (one per argument); ``name(k)``: how place k is called ("bedroom #2").

    Raises:
        UnresolvedRelation: no instance satisfies the relation (module docstring).

    >>> geo = PlaceGeometry(np.arange(3), lambda i, j: [[0, 4, 9], [4, 0, 5], [9, 5, 0]][i][j], np.eye(3, dtype=bool),
    ...                     np.array([1.0, 2.0, 3.0]), 0.44)
    >>> from spcotmhp.language.meaning import PlaceRef
    >>> bath = PlaceRef(("bath",), "bath")
    >>> mask, said = resolve(Relation("closest", (bath,)), np.array([1, 1, 0], bool), [np.array([0, 0, 1], bool)],
    ...                      geo, lambda k: f"bedroom #{k + 1}")
    >>> np.flatnonzero(mask).tolist(), said
    ([1], {1: 'the one closest to the bath'})
    >>> geo = PlaceGeometry(np.arange(3), lambda i, j: [[0, 4, 6.2], [4, 0, 6.0], [6.2, 6.0, 0]][i][j],
    ...                     np.eye(3, dtype=bool), np.array([1.0, 2.0, 3.0]), 0.44)
    >>> mask, said = resolve(Relation("closest", (bath,)), np.array([1, 1, 0], bool), [np.array([0, 0, 1], bool)],
    ...                      geo, lambda k: f"bedroom #{k + 1}")
    >>> np.flatnonzero(mask).tolist(), said[1]
    ([0, 1], "the one closest to the bath, tied with bedroom #1: 6.0 and 6.2 m, less apart than the robot's 0.44 m")
    """
    cand = [int(k) for k in np.flatnonzero(candidates)]
    others = [np.asarray(o, dtype=bool) for o in others]
    out = np.zeros(len(candidates), dtype=bool)
    if relation.kind == "next_to":
        near = _next_to(relation, cand, others[0], geometry, name)
        out[near] = True
        if len(near) == 1:
            return out, {near[0]: _said(relation)}
        where = relation.describe()
        return out, {
            k: f"one of {len(near)} {where}, with {' and '.join(name(o) for o in near if o != k)}" for k in near
        }
    measure, unit = _measure(relation, cand, others, geometry, len(candidates))
    reachable = {k: v for k, v in measure.items() if math.isfinite(v)}
    if not reachable:
        raise UnresolvedRelation(
            f"no place called {_label(name, cand)} is connected to the "
            f"{' and the '.join(a.label for a in relation.args)} on the map, so none is {relation.describe()}"
        )
    largest_first = relation.kind in ("farthest", "largest")
    ranked = sorted(reachable, key=lambda k: -reachable[k] if largest_first else reachable[k])
    best = ranked[0]
    scale = _circle_diameter if relation.kind in ("largest", "smallest") else float
    tied = [k for k in ranked if abs(scale(reachable[k]) - scale(reachable[best])) < geometry.diameter_m]
    out[tied] = True
    if len(tied) == 1:
        return out, {best: _said(relation)}
    return out, _tied(relation, tied, reachable, unit, geometry.diameter_m, name)


def _tied(
    relation: Relation, tied: list[int], measure: dict[int, float], unit: str, diameter: float, name: Callable
) -> dict[int, str]:
    """How the explanation says each of several tied instances was picked, with the others and the measures."""
    values = " and ".join(f"{measure[o]:.1f}" for o in sorted(tied, key=lambda o: measure[o]))
    return {
        k: f"{_said(relation)}, tied with {' and '.join(name(o) for o in tied if o != k)}: {values} {unit}, less "
        f"apart than the robot's {diameter:.2f} m"
        for k in tied
    }


def _circle_diameter(area: float) -> float:
    """The diameter of the circle of ``area`` (m²): areas compared in the robot's length."""
    return 2.0 * math.sqrt(max(area, 0.0) / math.pi)


def _measure(
    relation: Relation, cand: list[int], others: list[np.ndarray], geometry: PlaceGeometry, n: int
) -> tuple[dict[int, float], str]:
    """Each candidate's measure under the relation's rule (module docstring) and its unit."""
    if relation.kind in ("largest", "smallest"):
        return {k: float(geometry.areas[k]) for k in cand}, "m²"
    if relation.kind == "between":
        pairs = [(int(a), int(b)) for a in np.flatnonzero(others[0]) for b in np.flatnonzero(others[1])]
        detour = {
            k: min((geometry.distance(a, k) + geometry.distance(k, b) - geometry.distance(a, b) for a, b in pairs),
                   default=math.inf)
            for k in cand
        }  # fmt: skip
        return detour, "m of detour"
    return {k: geometry.nearest(k, others[0] & ~_only(k, n)) for k in cand}, "m"


def place_geometry(graph: PlanningGraph, resolution: float, diameter_m: float) -> PlaceGeometry:
    """The :class:`PlaceGeometry` of a planning graph (its nodes, partial paths and territories; the model's
    Gaussians)."""
    model = graph.model
    K = model.K

    def length(i: int, j: int) -> float:
        try:
            return path_length(graph.edge_path(i, j), resolution)
        except PlanningError:
            return math.inf

    touching = territory_contacts(graph.territory, K) | np.asarray(graph.connected, dtype=bool)
    areas = math.pi * np.sqrt(np.clip(np.linalg.det(model.Sigma), 0.0, None))
    return PlaceGeometry(graph.node_place, length, touching, areas, diameter_m)


def territory_contacts(territory: np.ndarray, K: int) -> np.ndarray:
    """(K, K) places whose territories (place of each cell, -1 for none) share an edge of two cells.

    >>> territory_contacts(np.array([[0, 0, 1], [2, -1, 1]]), 3).astype(int).tolist()
    [[0, 1, 1], [1, 0, 0], [1, 0, 0]]
    """
    out = np.zeros((K, K), dtype=bool)
    for a, b in ((territory[:, :-1], territory[:, 1:]), (territory[:-1, :], territory[1:, :])):
        pair = (a >= 0) & (b >= 0) & (a != b)
        out[a[pair], b[pair]] = True
    return out | out.T


def _said(relation: Relation) -> str:
    """How the explanation says which instance a relation picked: "the one closest to the bath", "the largest
    one"."""
    if relation.kind in ("largest", "smallest"):
        return f"the {relation.kind} one"
    return f"the one {relation.describe()}"


def _only(k: int, n: int) -> np.ndarray:
    out = np.zeros(n, dtype=bool)
    out[k] = True
    return out


def _label(name: Callable[[int], str], places: Sequence[int]) -> str:
    names = sorted({name(k).split(" #")[0] for k in places})
    return " or ".join(f"'{n}'" for n in names)


def _next_to(
    relation: Relation, cand: list[int], other: np.ndarray, geometry: PlaceGeometry, name: Callable[[int], str]
) -> list[int]:
    """The candidates whose territory touches one of ``other`` or which the place graph connects to one."""
    near = [k for k in cand if (geometry.touching[k] & other & (np.arange(len(other)) != k)).any()]
    if not near:
        raise UnresolvedRelation(
            f"none of {', '.join(name(k) for k in cand)} is {relation.describe()} (no territory touches it and the "
            "robot never walked straight between them): name the place another way"
        )
    return near
