"""Place connectivity from the walk and from the map's free space (hand-made maps and the SIGVerse homes)."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.datasets import load_bundled
from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import ModelError
from spcotmhp.learning.connectivity import (
    apply_connectivity,
    map_adjacency,
    nearest_free_cells,
    psi_from_adjacency,
    walk_adjacency,
)
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.metric.maps import OccupancyMap

pytestmark = pytest.mark.filterwarnings("ignore::spcotmhp.datasets.loader.DatasetWarning")


def three_rooms() -> OccupancyMap:
    """Rooms A | B | C side by side (3 m x 3 m each, 0.1 m cells), a door in each inner wall, and a closed room D
    below B."""
    data = np.full((42, 94), 100, dtype=np.int8)
    data[1:31, 1:31] = 0  # A: x 0.1..3.1
    data[1:31, 32:62] = 0  # B
    data[1:31, 63:93] = 0  # C
    data[11:19, 31] = 0  # door A-B (0.8 m: the 0.22 m robot fits)
    data[11:19, 62] = 0  # door B-C
    data[33:41, 32:62] = 0  # D, closed
    return OccupancyMap(data=data, resolution=0.1)


def model_at(means: list[tuple[float, float]], sd: float = 0.7) -> SpatialConceptModel:
    K = len(means)
    return SpatialConceptModel(
        mu=np.array(means, dtype=float),
        Sigma=np.tile(np.eye(2) * sd**2, (K, 1, 1)),
        psi=np.full((K, K), 1.0 / K),
        pi=np.array([1.0]),
        phi=np.full((1, K), 1.0 / K),
        W=np.array([[1.0]]),
        vocabulary=["x"],
    )


def test_rooms_in_a_row():
    m = model_at([(1.6, 1.6), (4.7, 1.6), (7.8, 1.6), (4.7, 3.7)])
    A = map_adjacency(m, three_rooms())
    want = np.array([[1, 1, 0, 0], [1, 1, 1, 0], [0, 1, 1, 0], [0, 0, 0, 1]])
    np.testing.assert_array_equal(A, want)  # A-C passes through B; D cannot be reached
    dens = map_adjacency(m, three_rooms(), rule="density", radius=1.0)
    np.testing.assert_array_equal(dens, want)


def test_inactive_places_are_left_out():
    m = model_at([(1.6, 1.6), (4.7, 1.6), (7.8, 1.6)])
    m.active_places = np.array([True, False, True])
    A = map_adjacency(m, three_rooms())
    np.testing.assert_array_equal(A, [[1, 0, 1], [0, 0, 0], [1, 0, 1]])  # with B gone, A and C touch


def test_means_inside_walls_start_from_the_nearest_free_cell():
    grid = three_rooms()
    np.testing.assert_array_equal(nearest_free_cells(grid, np.array([[3.15, 1.0], [-5.0, -5.0]])), [[10, 30], [1, 1]])


def test_walk_adjacency_from_a_trajectory():
    m = model_at([(1.6, 1.6), (4.7, 1.6), (7.8, 1.6)])
    x = np.concatenate([np.linspace(1.0, 8.0, 71), np.linspace(8.0, 4.0, 41)])
    traj = np.stack([x, np.full_like(x, 1.6)], axis=1)
    data = Dataset(name="walk", map=three_rooms(), positions=traj[:2], tokens=[["a"], ["b"]], trajectory=traj)
    np.testing.assert_array_equal(walk_adjacency(m, data), [[1, 1, 0], [1, 1, 1], [0, 1, 1]])
    # without a trajectory: consecutive events
    data.trajectory = None
    np.testing.assert_array_equal(
        walk_adjacency(m, data, event_places=np.array([0, 2, 2])), [[1, 0, 1], [0, 1, 0], [1, 0, 1]]
    )


def test_psi_from_adjacency_hand_case():
    A = np.array([[1, 1, 0], [1, 1, 1], [0, 1, 1]])
    psi = psi_from_adjacency(A)
    np.testing.assert_allclose(psi[0], [1.1 / 2.3, 1.1 / 2.3, 0.1 / 2.3])
    np.testing.assert_allclose(psi[1], [1.1 / 3.3] * 3)
    with pytest.raises(ModelError, match="square"):
        psi_from_adjacency(np.ones((2, 3)))
    with pytest.raises(ModelError, match="0 or 1"):
        psi_from_adjacency(np.full((2, 2), 2))


def test_errors():
    m = model_at([(1.6, 1.6), (4.7, 1.6)])
    with pytest.raises(ModelError, match="needs a map"):
        map_adjacency(m)
    with pytest.raises(ModelError, match="rule must be one of"):
        map_adjacency(m, three_rooms(), rule="vibes")
    with pytest.raises(ModelError, match="no free cell"):
        map_adjacency(m, OccupancyMap(data=np.full((5, 5), 100, np.int8), resolution=0.1))
    data = Dataset(name="d", map=three_rooms(), positions=np.zeros((2, 2)), tokens=[["a"], ["b"]])
    with pytest.raises(ModelError, match="connectivity must be one of"):
        apply_connectivity(m, data, "telepathy")


def test_precision_recall_on_the_sigverse_homes():
    """Against adjacency.csv of the three bundled homes, places = supervised means (measured 0.84 / 0.93)."""
    tp = fp = fn = 0
    for name in ("3LDK_01", "3LDK_05", "3LDK_06"):
        data = load_bundled(name, lang="en")
        A = map_adjacency(fit_supervised(data), data.map).astype(bool)
        truth = data.adjacency.astype(bool)
        off = ~np.eye(len(truth), dtype=bool)
        tp += (A & truth & off).sum()
        fp += (A & ~truth & off).sum()
        fn += (~A & truth & off).sum()
    assert tp / (tp + fp) >= 0.8
    assert tp / (tp + fn) >= 0.9
