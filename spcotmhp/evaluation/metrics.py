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

Two success rules (:data:`SUCCESS_RULE`), both reported for every method:

* **footprint** (the primary figures, keys ``spl``, ``n_spl``, ...): a pose reaches a place when the robot's
  *centre* lies within the robot's inscribed radius r of the place's box, i.e. inside the box grown by a disc of
  radius r (the box's Minkowski sum with the disc, :meth:`Box.grown`): the robot's body then touches the place.
  SPL (Anderson et al. 2018) leaves the success distance to the task ("within a distance d of the goal"); the box
  alone asks the robot's centre to stand where, against furniture or a wall, no centre fits (every cell of a
  kitchen taught against its counter can be inscribed), so a planner that keeps the footprint clear of obstacles
  would be scored as failing exactly because it is safe. The reference length l is the shortest path over the
  cells the robot's centre may occupy (cost below inscribed) to the place's target inside that grown box: the
  robot cell nearest the mean of its teaching positions there (:mod:`~spcotmhp.evaluation.reference` says why
  not to the grown box's edge);
* **strict** (the paper's rule, keys ``strict_spl``, ``strict_n_spl``, ...): the centre inside the box itself,
  and l to the place's position (the robot cell nearest the mean, wherever it lies).

A box is the axis-aligned box of a place's teaching positions grown by a margin (0.1 m). Tasks with
``l = 0`` (the start already satisfies the task) are not made (:mod:`~spcotmhp.evaluation.tasks`), since their
ratio ``0 / max(p, 0)`` is undefined for a path that stays put.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace

import numpy as np

REGION_MARGIN_M = 0.1


SUCCESS_RULE = (
    "Success: the path's last pose within the robot's inscribed radius ({radius:.2f} m) of the goal place's box "
    "(its teaching positions' bounding box + 0.1 m), i.e. the robot's body reaches the place; l is the shortest "
    "path of the robot's centre (cells below the inscribed cost) to the cell nearest the place's mean inside that "
    "grown box. Strict (the paper's rule): the last pose inside the box itself, l to the robot cell nearest the "
    "place's mean."
)
"""The success rule every table states (format with ``radius``, the inscribed radius in metres)."""


@dataclass(frozen=True)
class Box:
    """An axis-aligned rectangle in map-frame metres (inclusive bounds), optionally grown by a disc of
    ``radius`` metres (its Minkowski sum with the disc: the points within ``radius`` of the rectangle)."""

    xmin: float
    ymin: float
    xmax: float
    ymax: float
    radius: float = 0.0

    @classmethod
    def around(cls, points: np.ndarray, margin: float = REGION_MARGIN_M) -> Box:
        """The bounding box of (n, 2) points grown by ``margin`` on every side."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        lo, hi = pts.min(axis=0) - margin, pts.max(axis=0) + margin
        return cls(float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    def grown(self, radius: float) -> Box:
        """The box grown by a disc of ``radius`` metres (radii add up).

        >>> Box(0.0, 0.0, 1.0, 1.0).grown(0.5).contains(np.array([[1.3, 1.3], [1.4, 1.4]])).tolist()
        [True, False]
        """
        if not (np.isfinite(radius) and radius >= 0):
            raise ValueError(f"a box grows by a finite radius >= 0, got {radius}")
        return replace(self, radius=self.radius + float(radius))

    def distance(self, xy: np.ndarray) -> np.ndarray:
        """(...,) Euclidean distance of the (..., 2) points to the rectangle (0 inside; the radius ignored)."""
        xy = np.asarray(xy, dtype=float)
        dx = np.maximum(np.maximum(self.xmin - xy[..., 0], xy[..., 0] - self.xmax), 0.0)
        dy = np.maximum(np.maximum(self.ymin - xy[..., 1], xy[..., 1] - self.ymax), 0.0)
        return np.hypot(dx, dy)

    def contains(self, xy: np.ndarray) -> np.ndarray:
        """Boolean (...,) : which of the (..., 2) points lie inside (bounds included; within ``radius`` of the
        rectangle when grown, up to 1e-9 m of rounding)."""
        xy = np.asarray(xy, dtype=float)
        if self.radius == 0.0:
            x, y = xy[..., 0], xy[..., 1]
            return (x >= self.xmin) & (x <= self.xmax) & (y >= self.ymin) & (y <= self.ymax)
        return self.distance(xy) <= self.radius + 1e-9


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
    strict: Outcome | None = None  # the same path under the paper's strict rule (module docstring)


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


def failed(l: float, time_s: float, advanced: bool, via: bool = False, strict_l: float | None = None) -> Outcome:
    """The outcome of a method that returned no path (every success is 0; under the strict rule too when its
    reference length ``strict_l`` is given)."""
    strict = None if strict_l is None else failed(strict_l, time_s, advanced, via)
    return Outcome(
        False,
        False,
        False if advanced else None,
        0.0,
        float(l),
        0.0,
        float(time_s),
        False if via else None,
        strict=strict,
    )


def task_terms(outcomes: Sequence[Outcome], prefix: str = "") -> dict[str, np.ndarray]:
    """Per-task terms whose means are the metrics (one home for each metric's definition): spl = S * ratio,
    n_spl = N * ratio, success, n_success, collides and, for advanced tasks, w_spl = W * ratio, wn_spl =
    W * N * ratio, w_success and (when scored) n_spl_via, wn_spl_via; then the same under the strict rule with
    keys ``strict_...`` when every outcome carries its strict reading. Keys in the order :func:`summarise`
    reports them.

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
    out = {"spl": s * r, "n_spl": n * r}
    if advanced.pop():
        w = np.array([o.w_success for o in outcomes], dtype=float)
        out.update(w_spl=w * r, wn_spl=w * n * r, w_success=w)
        if all(o.n_via_success is not None for o in outcomes):
            nv = np.array([o.n_via_success for o in outcomes], dtype=float)
            out.update(n_spl_via=nv * r, wn_spl_via=w * nv * r)
    out["success"] = s
    if not prefix:
        out["collides"] = np.array([o.collides for o in outcomes], dtype=float)
    out["n_success"] = n
    out = {prefix + k: v for k, v in out.items()}
    strict = [o.strict for o in outcomes]
    if not prefix and all(o is not None for o in strict):
        out.update(task_terms([o for o in strict if o is not None], "strict_"))
    return out


def summarise(outcomes: Sequence[Outcome]) -> dict[str, float | int]:
    """Mean metrics over tasks (the means of :func:`task_terms`: spl, n_spl, success, n_success, collides (the
    share of paths that leave the free space, :func:`off_free_space`) and, when the tasks have waypoints, w_spl,
    wn_spl, w_success; when they have N_via, n_spl_via and wn_spl_via; the strict rule's ``strict_...`` when
    scored), then time_median_s, time_p95_s and n_tasks.

    Raises:
        ValueError: no outcomes, or a mix of basic and advanced outcomes.
    """
    terms = task_terms(outcomes)
    t = np.array([o.time_s for o in outcomes], dtype=float)
    out: dict[str, float | int] = {k: float(np.mean(v)) for k, v in terms.items()}
    out["time_median_s"] = float(np.median(t))
    out["time_p95_s"] = float(np.percentile(t, 95))
    out["n_tasks"] = len(outcomes)
    return out
