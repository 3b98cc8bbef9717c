"""Hand-built teaching for the taught-merge report and split (issue 35, item 5): two rooms side by side, 6 m x 4 m
at 0.1 m, each taught with its own name, with a wall between them (a door off the line between the rooms), a door
on that line, or no wall at all (one open room taught with two names)."""

from __future__ import annotations

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.taught_split import refit
from spcotmhp.metric.maps import OccupancyMap

CENTRES = ((1.5, 2.0), (4.5, 2.0))
"""The two rooms' teaching centres (metres): 3 m apart, the wall at x = 3.0-3.1 m between them."""
FRAME = ("this", "is", "the", "we", "are", "in", "here", "it", "name", "of", "place", "called", "you")
"""The words around the name in the teaching templates (said by the background in a settled sample)."""
OFFSETS = ((0.0, 0.0), (0.4, 0.3), (-0.4, 0.3), (0.3, -0.4), (-0.3, -0.4), (0.5, -0.1), (-0.5, 0.1))


def rooms_map(between: str) -> OccupancyMap:
    """The map: outer walls; ``between`` "wall" (a wall at column 30 with a 0.7 m door at y 3.1-3.8, off the line
    between the centres), "door" (the same wall with its 0.8 m door at y 1.6-2.4, on that line) or "none"."""
    data = np.zeros((40, 60), dtype=np.int8)
    data[[0, -1], :] = 100
    data[:, [0, -1]] = 100
    if between != "none":
        data[:, 30] = 100
        rows = slice(31, 38) if between == "wall" else slice(16, 24)
        data[rows, 30] = 0
    return OccupancyMap(data, resolution=0.1)


def two_names(between: str, names=("bedroom", "playroom"), counts=(5, 5), centres=CENTRES) -> Dataset:
    """Each name taught ``counts`` times ("this is the NAME") around its room's centre, rooms in turn."""
    xy, tokens = [], []
    for name, n, (cx, cy) in zip(names, counts, centres, strict=True):
        for dx, dy in OFFSETS[:n]:
            xy.append((cx + dx, cy + dy))
            tokens.append(["this", "is", "the", name])
    return Dataset(f"two-rooms-{between}", rooms_map(between), np.array(xy), tokens)


def forced(data: Dataset, places: np.ndarray, concepts: np.ndarray) -> SpCoTMHP:
    """A short fit of ``data`` whose final sample is then replaced by a given one: ``places``, ``concepts``, and
    the word switches of a settled sampler (the name words said by the concept, "this is the" by the background);
    ``refit`` re-exports the model from it as the sampler exports its own."""
    est = SpCoTMHP(iterations=2, seed=0).fit(data)
    a = est.model_.learner["arrays"]
    vocab = est.model_.vocabulary
    a["tok_z"] = np.array([vocab[w] not in FRAME for w in a["tok_word"]], dtype=bool)
    return refit(est, data, np.asarray(places, dtype=np.int64), np.asarray(concepts, dtype=np.int64))


def merged_fit(data: Dataset) -> SpCoTMHP:
    """``forced`` with the merge the issue saw: every event in place 0 and concept 0."""
    zeros = np.zeros(data.n_events, dtype=np.int64)
    return forced(data, zeros, zeros.copy())
