"""Where a robot would stop: the cells a goal, waypoint or Nav2 route node of a place may be put on.

Rule (a departure from the paper, which snaps the place's mean to the nearest traversable cell): a place's
candidate points (:func:`~spcotmhp.planning.places.candidate_nodes`) are put on its **stop cells**, the cells

* of low cost: costmap_2d's published cost below ``STOP_COST`` = 50 of 100 (raw cost below 128 of 254, the middle
  of the inflation's 1..252 scale: the cost has halved from its value at the inscribed radius, which puts the
  robot's centre ln(252 / 128) / cost_scaling_factor beyond the inscribed radius, a margin the robot's own
  inflation settings set, not a constant of ours) and, for a footprint polygon, below its circumscribed cost
  (:meth:`~spcotmhp.metric.costmap.CostMapSettings.circumscribed_cost`: there the footprint is clear of
  obstacles at every heading, so the robot can turn in place where it stops);
* inside the place: its own territory (the place is the most probable one there) and its ``candidate_quantile``
  ellipse;
* reachable: in the free region planned from (the same 4-connected component as the start).

The first candidate, the paper's mean, becomes the place's most probable stop cell: the cell holding the mean
when that is a stop cell (150 of the 163 places measured keep their point), else the stop cell of
the highest N(x | mu, Sigma) at its centre (the nearest to the mean in Mahalanobis distance); the sampled
candidates (N > 1) move to their nearest stop cell. A place without a stop cell keeps the previous rule (the
nearest traversable cell of its territory) and is listed in the graph's ``info["stop_fallback"]``.
``GraphSettings.stop_cost`` = None restores the previous rule everywhere.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.metric.costmap import COST_TRANSLATION_TABLE, CostMapSettings

STOP_COST = 50.0
"""Published cost (0..100) a stop cell stays below (module docstring)."""


def stop_threshold(costmap: dict, resolution: float, stop_cost: float = STOP_COST) -> float:
    """The published cost a stop cell must stay below: ``stop_cost``, and for a footprint its circumscribed cost's
    published value (a circle's circumscribed cost is the inscribed 253, published 99: no constraint)."""
    circumscribed = CostMapSettings(**costmap).circumscribed_cost(resolution)
    return float(min(stop_cost, int(COST_TRANSLATION_TABLE[circumscribed])))


def published_cost(log_p: np.ndarray) -> np.ndarray:
    """The published cost (0..100) of each traversable cell from log p(x|m) = log((100 - cost) / 100); inf on the
    others."""
    with np.errstate(invalid="ignore"):
        cost = np.rint(100.0 * (1.0 - np.exp(log_p)))
    return np.where(np.isfinite(log_p), cost, np.inf)


def stop_cells(log_p: np.ndarray, threshold: float) -> np.ndarray:
    """(H, W) bool: traversable cells whose published cost is below ``threshold``."""
    return published_cost(log_p) < threshold


def window_stops(
    costmap: dict, resolution: float, stop_cost: float | None, log_p: np.ndarray, centres: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """(stop cells by cost, cell centres) of a window of log p(x|m) for the candidate nodes, or None when
    ``stop_cost`` is None (the paper's rule)."""
    if stop_cost is None:
        return None
    return stop_cells(log_p, stop_threshold(costmap, resolution, stop_cost)), centres


def most_probable(centres: np.ndarray, mu: np.ndarray, Sigma: np.ndarray) -> int:
    """Index of the point of ``centres`` (n, 2) of highest N(x | mu, Sigma): the smallest Mahalanobis distance
    (the first on ties, so the choice is deterministic)."""
    d = centres - mu
    inv = np.linalg.inv(Sigma)
    return int(np.argmin(np.einsum("ni,ij,nj->n", d, inv, d)))
