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

Ties refuse: when the runner-up's measure is within :data:`TIE_FRACTION` of the best's (relative) or within the
robot's diameter (geodesics), the relation does not single out one place for a person either, so the planner says
which instances are about equal and asks for another word rather than guessing. A relation whose other place is
unknown, or which no instance satisfies, is refused the same way (:class:`~spcotmhp.errors.UnresolvedRelation`).
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

TIE_FRACTION = 0.10
"""Two instances whose measures differ by less than this fraction of the larger are a tie (refused): place points
are estimates (Gaussian means snapped to free cells), and a person judging "closest" by walking distance or
"largest" by eye does not tell apart differences of a tenth."""


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
) -> tuple[np.ndarray, str]:
    """The (K,) mask of the one instance among ``candidates`` that ``relation`` means, and how the explanation
    says it ("the one closest to the bath"); ``others``: the (K,) masks of the relation's other places (one per
    argument); ``name(k)``: how place k is called in messages ("bedroom #2").

    Raises:
        UnresolvedRelation: no instance satisfies the relation, or two or more are about equal (module
            docstring); the message names the instances and their measures.

    >>> geo = PlaceGeometry(np.arange(3), lambda i, j: [[0, 4, 9], [4, 0, 5], [9, 5, 0]][i][j], np.eye(3, dtype=bool),
    ...                     np.array([1.0, 2.0, 3.0]), 0.44)
    >>> from spcotmhp.language.meaning import PlaceRef
    >>> bath = PlaceRef(("bath",), "bath")
    >>> mask, said = resolve(Relation("closest", (bath,)), np.array([1, 1, 0], bool), [np.array([0, 0, 1], bool)],
    ...                      geo, lambda k: f"bedroom #{k + 1}")
    >>> np.flatnonzero(mask).tolist(), said
    ([1], 'the one closest to the bath')
    """
    cand = [int(k) for k in np.flatnonzero(candidates)]
    others = [np.asarray(o, dtype=bool) for o in others]
    if relation.kind == "next_to":
        return _next_to(relation, cand, others[0], geometry, name), _said(relation)
    measure, unit, floor = _measure(relation, cand, others, geometry, len(candidates))
    reachable = {k: v for k, v in measure.items() if math.isfinite(v)}
    if not reachable:
        raise UnresolvedRelation(
            f"no place called {_label(name, cand)} is connected to the "
            f"{' and the '.join(a.label for a in relation.args)} on the map, so none is {relation.describe()}"
        )
    largest_first = relation.kind in ("farthest", "largest")
    ranked = sorted(reachable, key=lambda k: -reachable[k] if largest_first else reachable[k])
    best = ranked[0]
    if len(ranked) > 1:
        runner = ranked[1]
        gap = abs(reachable[best] - reachable[runner])
        scale = max(abs(reachable[best]), abs(reachable[runner]))
        if gap < max(TIE_FRACTION * scale, floor):
            raise UnresolvedRelation(
                f"{name(best)} ({reachable[best]:.1f} {unit}) and {name(runner)} ({reachable[runner]:.1f} {unit}) "
                f"are within {TIE_FRACTION:.0%} (or the robot's size) of each other, so '{relation.describe()}' "
                "does not single one out: say which, with another word"
            )
    out = np.zeros(len(candidates), dtype=bool)
    out[best] = True
    return out, _said(relation)


def _measure(
    relation: Relation, cand: list[int], others: list[np.ndarray], geometry: PlaceGeometry, n: int
) -> tuple[dict[int, float], str, float]:
    """Each candidate's measure under the relation's rule (module docstring), its unit, and the absolute margin
    under which two measures tie (the robot's diameter for lengths)."""
    if relation.kind in ("largest", "smallest"):
        return {k: float(geometry.areas[k]) for k in cand}, "m²", 0.0
    if relation.kind == "between":
        pairs = [(int(a), int(b)) for a in np.flatnonzero(others[0]) for b in np.flatnonzero(others[1])]
        detour = {
            k: min((geometry.distance(a, k) + geometry.distance(k, b) - geometry.distance(a, b) for a, b in pairs),
                   default=math.inf)
            for k in cand
        }  # fmt: skip
        return detour, "m of detour", geometry.diameter_m
    return {k: geometry.nearest(k, others[0] & ~_only(k, n)) for k in cand}, "m", geometry.diameter_m


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
) -> np.ndarray:
    """The one candidate whose territory touches one of ``other`` or which the place graph connects to one."""
    near = [k for k in cand if (geometry.touching[k] & other & (np.arange(len(other)) != k)).any()]
    if not near:
        raise UnresolvedRelation(
            f"none of {', '.join(name(k) for k in cand)} is {relation.describe()} (no territory touches it and the "
            "robot never walked straight between them): name the place another way"
        )
    if len(near) > 1:
        raise UnresolvedRelation(
            f"{' and '.join(name(k) for k in near)} are all {relation.describe()}: say which, with another word"
        )
    out = np.zeros(len(other), dtype=bool)
    out[near[0]] = True
    return out
