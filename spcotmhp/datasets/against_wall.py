"""A dataset whose place was taught against a wall: the teaching positions of one place moved onto the free cells
that touch an occupied cell (a wall, a counter, a wardrobe) nearest the place's mean, as people stand when they name
a kitchen at its counter.

The place's teaching box then holds only cells within the robot's inscribed radius of an obstacle: a robot whose
footprint stays clear of obstacles cannot put its centre inside it. This is the case the footprint success rule of
:mod:`spcotmhp.evaluation.metrics` is for (``benchmarks/footprint_scoring.py`` measures both rules on it). The
trajectory, words and truth are kept as they are, so the dataset is meant for supervised parameters.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.ndimage import binary_dilation

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError


def wall_cells(dataset: Dataset) -> np.ndarray:
    """(n, 2) the free cells of the map with an occupied cell among their 8 neighbours."""
    occ = dataset.map
    touching = occ.free & binary_dilation(occ.occupied, structure=np.ones((3, 3), bool))
    return np.argwhere(touching)


def against_wall(dataset: Dataset, place: int) -> Dataset:
    """``dataset`` with the n teaching positions of true place ``place`` moved to the centres of the n
    :func:`wall_cells` cells nearest the one nearest the place's mean, in teaching order (a strip along the wall
    there; module docstring); named ``<name>-wall<place>``.

    >>> from spcotmhp.datasets.synthetic_battery import battery_home
    >>> home = against_wall(battery_home(0), 2)
    >>> home.name
    'battery-0-wall2'

    Raises:
        DatasetError: no truth.csv, no such place, or a map with no free cell beside an obstacle.
    """
    if dataset.truth_place is None:
        raise DatasetError(f"{dataset.name}: moving a place's teaching positions needs truth.csv")
    truth = np.asarray(dataset.truth_place)
    mine = truth == place
    if not mine.any():
        raise DatasetError(f"{dataset.name}: no teaching event of place {place} (truth.csv has 0..{truth.max()})")
    cells = wall_cells(dataset)
    if not len(cells):
        raise DatasetError(f"{dataset.name}: the map has no free cell beside an obstacle")
    centres = dataset.map.cell_to_world(cells)
    positions = np.array(dataset.positions, dtype=float)
    anchor = centres[np.argmin(np.linalg.norm(centres - positions[mine].mean(axis=0), axis=1))]
    strip = np.argsort(np.linalg.norm(centres - anchor, axis=1), kind="stable")[: int(mine.sum())]
    positions[mine] = centres[np.resize(strip, int(mine.sum()))]
    return replace(dataset, name=f"{dataset.name}-wall{place}", positions=positions)
