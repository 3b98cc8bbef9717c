"""Tie teaching events to the poses of a continuous trajectory when teaching.csv has no ``step`` column."""

from __future__ import annotations

import numpy as np

from spcotmhp.errors import DatasetError

MAX_CELLS = 100_000_000  # events x poses; the back-pointer table is int32, so this caps it at 400 MB


def align_events(positions: np.ndarray, trajectory: np.ndarray) -> np.ndarray:
    """The non-decreasing trajectory steps t_0 <= t_1 <= ... that minimise sum_e |x_e - trajectory[t_e]|.

    The teaching events were spoken in order along the walk, so each event is attached to a nearby pose
    without going back in time: a robot that passes the same spot twice gets the pass that keeps the order.
    Exact dynamic programming over (event, step), O(E T) time; ties go to the earliest step.

    Args:
        positions: (E, 2) event positions in metres.
        trajectory: (T, 2) poses in metres, in walking order.

    Returns:
        (E,) int64 steps into ``trajectory``.
    """
    positions = np.asarray(positions, dtype=float)
    trajectory = np.asarray(trajectory, dtype=float)
    n_events, n_steps = len(positions), len(trajectory)
    if n_events == 0:
        return np.zeros(0, dtype=np.int64)
    if n_events * n_steps > MAX_CELLS:
        raise DatasetError(
            f"cannot attach {n_events} events to {n_steps} trajectory poses by nearest pose (too large); "
            "add a step column to teaching.csv"
        )
    index = np.arange(n_steps)
    back = np.empty((n_events, n_steps), dtype=np.int32)
    total = np.hypot(*(trajectory - positions[0]).T)
    for e in range(1, n_events):
        best = np.minimum.accumulate(total)
        # earliest argmin of total[:t + 1]: the last step where a strictly smaller running minimum began
        starts = np.empty(n_steps, dtype=bool)
        starts[0] = True
        starts[1:] = total[1:] < best[:-1]
        back[e] = np.maximum.accumulate(np.where(starts, index, 0))
        total = best + np.hypot(*(trajectory - positions[e]).T)
    steps = np.empty(n_events, dtype=np.int64)
    steps[-1] = int(np.argmin(total))
    for e in range(n_events - 1, 0, -1):
        steps[e - 1] = back[e, steps[e]]
    return steps
