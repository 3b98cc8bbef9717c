"""Path smoothing (Algorithm 1, line 13, "Path_Smoothing(x, m)") as post-processing for the compared methods of
Experiment I, so that a table can give every method the same post-processing:

* :func:`moving_average`: the paper's smoothing, "moving average smoothing with a window size of 5" (Section
  4.2, Conditions): every pose of the path is replaced by the mean of the poses in a centred window of 5; near
  the ends the window shrinks symmetrically (2k + 1 poses around pose k from the start), so the start and the
  end stay where they are. As in the paper there is no collision check: an averaged corner may cut a wall.
* :func:`spcotmhp_smoothing`: ours (:mod:`spcotmhp.planning.assemble`), for a path assembled from the planning
  graph's legs by another method (HPP-I/II): re-planning each piece between the cells where a stage is
  completed inside the territories it runs through (:func:`~spcotmhp.planning.assemble.shorten`), then
  line-of-sight shortcuts (:func:`~spcotmhp.planning.assemble.smooth_anchored`), each kept only if
  :func:`~spcotmhp.planning.assemble.better` -- :func:`~spcotmhp.planning.assemble.smooth_on_graph`, the one
  function :class:`~spcotmhp.planning.planner.HierarchicalPlanner` uses for SpCoTMHP.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from spcotmhp.planning.assemble import smooth_on_graph
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.plan import Plan
from spcotmhp.planning.protocol import Planner, StartPose

PAPER_WINDOW = 5


def moving_average(path: np.ndarray, window: int = PAPER_WINDOW) -> np.ndarray:
    """The (n, 2) path with pose k replaced by the mean of poses k - h .. k + h, h = min((window - 1) // 2, k,
    n - 1 - k) (a centred window, shrunk at the ends so that the first and last poses are kept).

    Raises:
        ValueError: ``window`` is not an odd integer >= 1.

    >>> moving_average(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 1.0]]), window=3).round(3).tolist()
    [[0.0, 0.0], [0.667, 0.333], [1.333, 0.667], [2.0, 1.0]]
    """
    if not isinstance(window, int) or window < 1 or window % 2 == 0:
        raise ValueError(f"window must be an odd integer >= 1, got {window!r}")
    pts = np.asarray(path, dtype=float).reshape(-1, 2)
    n = len(pts)
    if n < 3 or window == 1:
        return pts.copy()
    k = np.arange(n)
    h = np.minimum((window - 1) // 2, np.minimum(k, n - 1 - k))
    csum = np.vstack([np.zeros((1, 2)), np.cumsum(pts, axis=0)])
    return (csum[k + h + 1] - csum[k - h]) / (2 * h + 1)[:, None]


def spcotmhp_smoothing(
    graph: PlanningGraph,
    cells: np.ndarray,
    ends: Sequence[int],
    nodes: Sequence[int] | np.ndarray,
    anchors: Sequence[int],
) -> np.ndarray:
    """SpCoTMHP's line 13 on an assembled crop-cell path of ``graph`` (``ends[e]``: the index where node
    ``nodes[e]`` is reached; ``anchors``: the indices where a stage is completed, kept): the planner's own
    :func:`~spcotmhp.planning.assemble.smooth_on_graph`."""
    return smooth_on_graph(graph, cells, ends, nodes, anchors)[0]


class MovingAveragePlanner:
    """A :class:`~spcotmhp.planning.protocol.Planner` whose paths are another planner's with the paper's moving
    average (:func:`moving_average`) applied; ``cells`` stay the grid path it was averaged from."""

    def __init__(self, planner: Planner, window: int = PAPER_WINDOW) -> None:
        self.planner, self.window = planner, window

    def plan(self, instruction: Any, start: StartPose, *, rng: np.random.Generator | None = None) -> Plan:
        plan = self.planner.plan(instruction, start, rng=rng)
        path = moving_average(plan.path, self.window)
        length = float(np.hypot(*np.diff(path, axis=0).T).sum())
        return replace(plan, path=path, length_m=length, notes=[*plan.notes, "moving average"])
