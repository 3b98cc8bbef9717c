"""Path-planning metrics of Experiment I (paper Section 4.2, Tables 4 and 5): SPL, N-SPL, W-SPL, WN-SPL.

SPL (success weighted by path length; Anderson et al. 2018) averages, over tasks, ``S * l / max(p, l)`` with
``S`` the task's success (0/1), ``p`` the planned path's length in metres and ``l`` the length of the shortest
free-space path that would have succeeded (computed per task by :mod:`spcotmhp.evaluation.tasks`). The
variants weight the same ratio by a different success:

* ``S``  (SPL):    the path ends inside the region of *any* place named like the goal;
* ``N``  (N-SPL):  the path ends inside the region of the goal instance *closest from the initial position*
  (the paper's definition: the instance with the shortest free-space path from the start, waypoint or not);
* ``W``  (W-SPL):  some pose of the path *after it has left its start cell* lies inside the region of a place
  named like the waypoint (a path does not pass a waypoint by starting in it);
* ``WN`` (WN-SPL): both W and N.

Our variant of N, ``N_via`` (columns N-SPL (via) and WN-SPL (via)), takes as "closest" the goal instance where
the shortest path *through a waypoint* ends; on basic tasks the two coincide.

A region is the axis-aligned box of a place's teaching positions grown by a margin (0.1 m). Tasks with
``l = 0`` (the start already satisfies the task) are not made (:mod:`~spcotmhp.evaluation.tasks`), since their
ratio ``0 / max(p, 0)`` is undefined for a path that stays put.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np

REGION_MARGIN_M = 0.1


@dataclass(frozen=True)
class Box:
    """An axis-aligned rectangle in map-frame metres (inclusive bounds)."""

    xmin: float
    ymin: float
    xmax: float
    ymax: float

    @classmethod
    def around(cls, points: np.ndarray, margin: float = REGION_MARGIN_M) -> Box:
        """The bounding box of (n, 2) points grown by ``margin`` on every side."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        lo, hi = pts.min(axis=0) - margin, pts.max(axis=0) + margin
        return cls(float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    def contains(self, xy: np.ndarray) -> np.ndarray:
        """Boolean (...,) : which of the (..., 2) points lie inside (bounds included)."""
        xy = np.asarray(xy, dtype=float)
        x, y = xy[..., 0], xy[..., 1]
        return (x >= self.xmin) & (x <= self.xmax) & (y >= self.ymin) & (y <= self.ymax)


def path_length(path_xy: np.ndarray) -> float:
    """Euclidean length in metres of a polyline given as (n, 2) points (0 for fewer than two points)."""
    pts = np.asarray(path_xy, dtype=float).reshape(-1, 2)
    if len(pts) < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())


def densify(path_xy: np.ndarray, step: float) -> np.ndarray:
    """The polyline resampled so that consecutive points are at most ``step`` apart (vertices kept), so that a
    box crossed between two far-apart vertices is still seen."""
    pts = np.asarray(path_xy, dtype=float).reshape(-1, 2)
    if len(pts) < 2:
        return pts
    seg = np.diff(pts, axis=0)
    n = np.maximum(1, np.ceil(np.linalg.norm(seg, axis=1) / step).astype(int))
    t = np.concatenate([np.arange(k) / k for k in n])
    start = np.repeat(pts[:-1], n, axis=0)
    return np.vstack([start + np.repeat(seg, n, axis=0) * t[:, None], pts[-1:]])


def in_any(xy: np.ndarray, boxes: Iterable[Box]) -> bool:
    """Whether any of the (n, 2) points lies inside any of the boxes."""
    pts = np.asarray(xy, dtype=float).reshape(-1, 2)
    return any(bool(b.contains(pts).any()) for b in boxes)


@dataclass(frozen=True)
class Outcome:
    """How one planned path did on one task (the per-task terms of every metric)."""

    success: bool
    n_success: bool
    w_success: bool | None
    p: float
    l: float
    ratio: float
    time_s: float
    n_via_success: bool | None = None
    collides: bool = False


def efficiency(p: float, l: float) -> float:
    """The path-length weight ``l / max(p, l)`` of SPL (1 when both are 0).

    >>> efficiency(12.0, 9.0)  # a 12 m path where the shortest is 9 m
    0.75
    """
    if p < 0 or l < 0 or not (np.isfinite(l) and np.isfinite(p)):
        raise ValueError(f"path lengths must be finite and >= 0, got p = {p}, l = {l}")
    denom = max(p, l)
    return 1.0 if denom == 0 else l / denom


def score_path(
    path_xy: np.ndarray,
    goal_boxes: Sequence[Box],
    closest_goal: int,
    l: float,
    time_s: float,
    waypoint_boxes: Sequence[Box] | None = None,
    step: float = 0.05,
    closest_goal_via: int | None = None,
    start_box: Box | None = None,
) -> Outcome:
    """The outcome of one path.

    Args:
        path_xy: (n, 2) planned path in metres; an empty path (no plan) scores as :func:`failed`.
        goal_boxes: the regions of every place named like the goal.
        closest_goal: index into ``goal_boxes`` of the instance closest from the initial position (for N).
        l: the shortest successful path length (metres, > 0).
        time_s: online planning time.
        waypoint_boxes: regions of every place named like the waypoint (advanced tasks), else None.
        step: densification step (metres) for the waypoint test.
        closest_goal_via: index into ``goal_boxes`` of the instance closest via a waypoint (for N_via; None:
            not scored).
        start_box: the start cell; poses before the path first leaves it do not pass a waypoint (None: every
            pose counts).

    Raises:
        ValueError: ``l`` is not finite and > 0.
    """
    if not (np.isfinite(l) and l > 0):
        raise ValueError(f"the reference length l must be finite and > 0, got {l}")
    pts = np.asarray(path_xy, dtype=float).reshape(-1, 2)
    if len(pts) == 0:
        return failed(l, time_s, waypoint_boxes is not None, closest_goal_via is not None)
    end = pts[-1]
    success = bool(any(b.contains(end) for b in goal_boxes))
    n_success = bool(goal_boxes[closest_goal].contains(end))
    n_via = None if closest_goal_via is None else bool(goal_boxes[closest_goal_via].contains(end))
    w_success = None
    if waypoint_boxes is not None:
        dense = densify(pts, step)
        if start_box is not None:
            left = np.flatnonzero(~start_box.contains(dense))
            dense = dense[left[0] :] if len(left) else dense[:0]
        w_success = in_any(dense, waypoint_boxes)
    p = path_length(pts)
    return Outcome(success, n_success, w_success, p, float(l), efficiency(p, l), float(time_s), n_via)


def off_free_space(
    path_xy: np.ndarray, free: np.ndarray, cell_of: Callable[[np.ndarray], np.ndarray], step: float
) -> bool:
    """Whether some pose of the path (resampled every ``step`` metres, :func:`densify`) lies on a cell that is
    not free (``free``: (H, W) bool; ``cell_of``: metres -> (row, col)), or off the map."""
    cells = cell_of(densify(path_xy, step))
    inside = (cells >= 0).all(axis=1) & (cells < np.array(free.shape)).all(axis=1)
    return bool(not inside.all() or not free[cells[:, 0], cells[:, 1]].all())


def failed(l: float, time_s: float, advanced: bool, via: bool = False) -> Outcome:
    """The outcome of a method that returned no path (every success is 0)."""
    return Outcome(False, False, False if advanced else None, 0.0, float(l), 0.0, float(time_s), False if via else None)


def summarise(outcomes: Sequence[Outcome]) -> dict[str, float | int]:
    """Mean metrics over tasks: spl, n_spl, success, n_success, collides (the share of paths that leave the free
    space, :func:`off_free_space`), time_median_s, time_p95_s, n_tasks and, when
    the tasks have waypoints, w_spl, wn_spl, w_success; when they have N_via, n_spl_via and wn_spl_via.

    Raises:
        ValueError: no outcomes, or a mix of basic and advanced outcomes.
    """
    if not outcomes:
        raise ValueError("no task outcomes to summarise")
    advanced = {o.w_success is not None for o in outcomes}
    if len(advanced) != 1:
        raise ValueError("outcomes mix basic tasks (no waypoint) and advanced tasks (with waypoint)")
    r = np.array([o.ratio for o in outcomes])
    s = np.array([o.success for o in outcomes], dtype=float)
    n = np.array([o.n_success for o in outcomes], dtype=float)
    t = np.array([o.time_s for o in outcomes], dtype=float)
    out: dict[str, float | int] = {"spl": float(np.mean(s * r)), "n_spl": float(np.mean(n * r))}
    if advanced.pop():
        w = np.array([o.w_success for o in outcomes], dtype=float)
        out["w_spl"] = float(np.mean(w * r))
        out["wn_spl"] = float(np.mean(w * n * r))
        out["w_success"] = float(np.mean(w))
        if all(o.n_via_success is not None for o in outcomes):
            nv = np.array([o.n_via_success for o in outcomes], dtype=float)
            out["n_spl_via"] = float(np.mean(nv * r))
            out["wn_spl_via"] = float(np.mean(w * nv * r))
    out["success"] = float(np.mean(s))
    out["collides"] = float(np.mean([o.collides for o in outcomes]))
    out["n_success"] = float(np.mean(n))
    out["time_median_s"] = float(np.median(t))
    out["time_p95_s"] = float(np.percentile(t, 95))
    out["n_tasks"] = len(outcomes)
    return out
