"""What a plan says about its places (the explanation's facts): the places the final path drives through, with
their roles, and the goal options behind "closest of 3 bedrooms".

Both describe the path the robot drives, not only Eq. 28's node sequence: a leg (or smoothing) that crosses a
place which is not a node of the sequence names it, and "closest" compares the final paths (assembled,
smoothed, cut on arrival) into every instance of the goal's name.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol

import numpy as np

from spcotmhp.planning._paths import path_territories
from spcotmhp.planning.assemble import path_length
from spcotmhp.planning.plan import GoalOption, PlanPlace
from spcotmhp.planning.search import SearchResult
from spcotmhp.planning.search import octile as search_octile

if TYPE_CHECKING:
    from spcotmhp.learning.model import SpatialConceptModel
    from spcotmhp.planning.graph import PlanningGraph
    from spcotmhp.planning.graph_settings import PlannerSettings


class PlannerView(Protocol):
    """What the explanation reads of a :class:`~spcotmhp.planning.planner.HierarchicalPlanner` (a protocol, so
    that this module does not import the planner that imports it)."""

    model: SpatialConceptModel
    settings: PlannerSettings
    names: list[str]
    shown: list[str]
    numbering: dict[int, tuple[int, int]]
    diameter_cells: float

    def metric_path(self, graph: PlanningGraph, cell: np.ndarray, result: SearchResult) -> tuple[np.ndarray, bool]:
        """The final crop cells of ``result``'s plan and whether smoothing changed them."""
        ...


def path_places(
    planner: PlannerView,
    graph: PlanningGraph,
    start_place: int,
    x0: np.ndarray,
    result: SearchResult,
    points: np.ndarray,
    cells: np.ndarray,
) -> list[PlanPlace]:
    """Start, then the places the final path drives through, in order, with their roles: the territories
    (:mod:`spcotmhp.learning.territory`) along the path, ignoring stretches shorter than the robot's
    diameter (grazing a corner is not passing through), with the waypoints and the goal of Eq. 28's chosen
    sequence marked where the path reaches them (``points``: the map-frame points of ``result.nodes``). The
    dwell rule never hides the goal the path ends in (a small territory, or a path cut on arrival), and a goal
    the path reaches outside its territory still follows every place passed before it.
    ``start_place``: the most probable place of the start, arg max p(i_0 | x_0)."""
    last = result.completes_last  # the goal stage
    places = graph.node_place[result.nodes].tolist()
    marks = [  # the nodes that complete a stage, in order
        (k, "goal" if last in done else "waypoint", xy)
        for k, done, xy in zip(places, result.completed, points.tolist(), strict=True)
        if done
    ]
    # the places along the path, and the last territory the path is in (-1: none)
    along, ends_in = path_territories(graph.territory, cells, planner.diameter_cells)
    seq = along.tolist()
    if ends_in >= 0 and marks and ends_in == marks[-1][0] and (not seq or seq[-1] != ends_in):
        seq.append(ends_in)  # the path ends in the goal: arriving counts, however short the stay
    out = [place(planner, start_place, "start", x0)]
    pos = 1 if seq and seq[0] == start_place else 0
    for k, role, xy in marks:
        nxt = seq.index(k, pos) if k in seq[pos:] else (len(seq) if role == "goal" else None)
        for v in seq[pos:nxt] if nxt is not None else []:
            if v != out[-1].id:
                out.append(place(planner, v, "via"))
        out.append(place(planner, k, role, xy))
        pos = nxt + 1 if nxt is not None else pos
    return out


def place(planner: PlannerView, k: int, role: str, xy: Sequence[float] | np.ndarray | None = None) -> PlanPlace:
    """Place ``k`` in the role ``role``, numbered among the places of its name ("bedroom #2" of 3)."""
    number, count = planner.numbering[k]
    point = None if xy is None else (float(xy[0]), float(xy[1]))
    return PlanPlace(k, planner.shown[k], role, number, count, point)


def goal_options(
    planner: PlannerView,
    graph: PlanningGraph,
    cell: np.ndarray,
    result: SearchResult,
    goal_places: np.ndarray,
    chosen_length: float,
) -> list[GoalOption]:
    """The best plan into each goal instance (Eq. 28 ending there) with the length of its final path (the
    same assembly, smoothing and arrival as the chosen plan), so that "closest of 3 bedrooms" is a statement
    about the paths the robot would drive; only when the name is shared. The instances are taken in order of
    a lower bound of that length, the octile distances from the start through the option's anchors (the
    cells that smoothing keeps; :meth:`~spcotmhp.planning.search.SearchResult.anchor_octiles`, all options in
    one compiled pass); one whose bound already exceeds the shortest path found so far (the chosen one's or
    a shorter option's) cannot be the closest and gets the bound instead (``exact=False``), so a building
    with 90 offices does not smooth 90 paths per plan."""
    if np.count_nonzero(goal_places) < 2:
        return []
    options, pending = [], []
    end_place = int(graph.node_place[result.nodes[-1]])
    res = planner.model.require_map().resolution
    order = np.argsort(graph.node_place, kind="stable")  # each place's nodes, ascending
    bounds = np.searchsorted(graph.node_place[order], np.arange(len(goal_places) + 1))
    ends, kept = [], []
    nodes, terminal, bounds = order.tolist(), result.terminal[order].tolist(), bounds.tolist()  # Python's speed
    for k in np.flatnonzero(goal_places).tolist():
        lo, hi = bounds[k], bounds[k + 1]
        if not any(math.isfinite(v) for v in terminal[lo:hi]):
            continue
        node = nodes[max(range(lo, hi), key=terminal.__getitem__)]  # the first maximum, as np.argmax
        if k == end_place:
            options.append(GoalOption(k, place(planner, k, "goal").label, chosen_length, result.log_prob))
            continue
        ends.append(node)
        kept.append(k)
    lengths = result.anchor_octiles(np.array(ends, dtype=np.int64), graph.node_cell, cell)
    for node, k, length in zip(ends, kept, lengths.tolist(), strict=True):
        pending.append((res * length, k, place(planner, k, "goal").label, node))
    shortest = chosen_length
    for bound, k, label, node in sorted(pending, key=lambda p: p[0]):
        if planner.settings.arrival_quantile is None and bound > shortest + 1e-9:
            options.append(GoalOption(k, label, bound, float(result.terminal[node]), exact=False))
            continue
        alt = result.ending_at(node)
        length = path_length(planner.metric_path(graph, cell, alt)[0], res)
        shortest = min(shortest, length)
        options.append(GoalOption(k, label, length, alt.log_prob))
    return sorted(options, key=lambda o: -o.log_prob)


def octile(a: np.ndarray, b: np.ndarray) -> float:
    """The shortest 8-connected length between two cells, in cells (:func:`spcotmhp.planning.search.octile`)."""
    return float(search_octile(int(a[0]), int(a[1]), int(b[0]), int(b[1])))
