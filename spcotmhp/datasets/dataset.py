"""The in-memory form of a dataset folder: map, teaching events and the optional extras."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from spcotmhp.metric.maps import OccupancyMap


@dataclass
class Dataset:
    """Observations for learning (and truth for evaluation) in one environment.

    Attributes:
        name: environment name (the folder name by default).
        map: the occupancy grid.
        positions: (E, 2) teaching positions x_e in metres, map frame.
        tokens: E token lists S_e (already tokenised; English lower-cased).
        lang: "en" or "ja", the language of ``tokens``.
        features: optional (E, D) non-negative image feature counts f_e.
        trajectory: optional (T, 2) continuous robot positions (the path walked while teaching).
        event_steps: optional (E,) index into ``trajectory`` of each teaching event (non-decreasing).
        truth_place: optional (E,) true place index of each event (evaluation / supervised fit only).
        truth_concept: optional (E,) true concept index of each event.
        adjacency: optional (P, P) symmetric 0/1 place adjacency over the truth places (diagonal 1).
        place_names: optional names of the truth places, index = truth place.
        costmap_ros: optional (H, W) int costmap recorded from ROS, OccupancyGrid order.
        path: the folder it was loaded from.
    """

    name: str
    map: OccupancyMap
    positions: np.ndarray
    tokens: list[list[str]]
    lang: str = "en"
    features: np.ndarray | None = None
    trajectory: np.ndarray | None = None
    event_steps: np.ndarray | None = None
    truth_place: np.ndarray | None = None
    truth_concept: np.ndarray | None = None
    adjacency: np.ndarray | None = None
    place_names: list[str] | None = None
    costmap_ros: np.ndarray | None = None
    path: Path | None = field(default=None, compare=False)

    @property
    def n_events(self) -> int:
        return int(self.positions.shape[0])

    @property
    def vocabulary(self) -> list[str]:
        """Sorted distinct tokens."""
        return sorted({t for toks in self.tokens for t in toks})
