"""Territories (the partition of the robot's free space among the places) and the adjacency they induce."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.territory import place_territories, territory_adjacency
from spcotmhp.metric.maps import OccupancyMap

FOUR = ndimage.generate_binary_structure(2, 1)


def rooms() -> OccupancyMap:
    """Rooms A | B | C in a row (3 m x 3 m, 0.1 m cells), 0.8 m doors between them, room D below B, closed."""
    data = np.full((42, 94), 100, dtype=np.int8)
    data[1:31, 1:31] = 0
    data[1:31, 32:62] = 0
    data[1:31, 63:93] = 0
    data[11:19, 31] = 0
    data[11:19, 62] = 0
    data[33:41, 32:62] = 0
    return OccupancyMap(data=data, resolution=0.1)


def model_at(means, sds, occ) -> SpatialConceptModel:
    K = len(means)
    Sigma = np.array([np.eye(2) * s**2 for s in sds])
    return SpatialConceptModel(
        mu=np.array(means, float),
        Sigma=Sigma,
        psi=np.full((K, K), 1.0 / K),
        pi=np.array([1.0]),
        phi=np.full((1, K), 1.0 / K),
        W=np.array([[1.0]]),
        vocabulary=["x"],
        map=occ,
    )


def test_every_free_cell_of_a_seeded_component_is_labelled_and_territories_are_connected():
    occ = rooms()
    m = model_at([(1.6, 1.6), (4.7, 1.6), (7.8, 1.6), (4.7, 3.7)], [0.7] * 4, occ)
    mask = occ.data == 0
    t = place_territories(m, mask, occ.cell_centres())
    assert (t[~mask] == -1).all() and (t[mask] >= 0).all()
    for k in range(4):
        _, n = ndimage.label(t == k, structure=FOUR)
        assert n == 1
    A = territory_adjacency(t, 4)
    np.testing.assert_array_equal(A, [[1, 1, 0, 0], [1, 1, 1, 0], [0, 1, 1, 0], [0, 0, 0, 1]])


def test_a_place_whose_mean_is_in_a_wall_or_under_a_broad_gaussian_still_owns_cells():
    occ = rooms()
    # place 1's mean lies in the wall between A and B; place 2 is a broad Gaussian that dominates all of B
    m = model_at([(1.6, 1.6), (3.15, 0.6), (4.7, 1.6), (7.8, 1.6)], [0.7, 0.05, 5.0, 0.7], occ)
    mask = occ.data == 0
    t = place_territories(m, mask, occ.cell_centres())
    assert (t == 1).any()
    A = territory_adjacency(t, 4)
    assert A[1].sum() >= 2  # it has at least one edge besides itself


def test_a_stray_fragment_goes_to_the_place_that_reaches_it_first():
    # a corridor: a narrow Gaussian in the middle splits a broad one's most-probable region into two pieces;
    # the piece away from the broad place's mean is grown over by the narrow one
    data = np.full((5, 60), 100, dtype=np.int8)
    data[1:4, 1:59] = 0
    occ = OccupancyMap(data=data, resolution=0.1)
    m = model_at([(1.0, 0.25), (3.0, 0.25)], [3.0, 0.3], occ)
    mask = occ.data == 0
    t = place_territories(m, mask, occ.cell_centres())
    raw = np.argmax(np.stack([m.log_place_density(occ.cell_centres())[..., k] for k in range(2)]), axis=0)
    assert ndimage.label((raw == 0) & mask, structure=FOUR)[1] == 2  # two pieces before
    assert ndimage.label(t == 0, structure=FOUR)[1] == 1  # one territory after
    assert (t[:, 40:][mask[:, 40:]] == 1).all()


@pytest.mark.parametrize("seed", range(6))
def test_place_graph_is_connected_on_generated_homes(seed):
    from scipy.sparse.csgraph import connected_components

    from spcotmhp.datasets.synthetic_battery import battery_home
    from spcotmhp.learning.connectivity import map_adjacency
    from spcotmhp.learning.supervised import fit_supervised

    data = battery_home(seed)
    model = fit_supervised(data, adjacency="map")
    A = map_adjacency(model, data.map)
    assert connected_components(A, directed=False)[0] == 1


def test_partition_extra_seeds_add_a_piece_or_a_single_cell_by_hand():
    """planning/regions.py's extra seeds: a place's piece holding the cell, else the cell alone (taking it from the
    piece it lies in), never a cell another single-cell seed holds; without them, place_territories' partition."""
    from spcotmhp.learning.territory import partition

    labels = np.array([[0, 0, -1, 1, 1], [0, 0, -1, 1, 0]])  # two free components; (1, 4) a stray piece of 0
    anchors = np.array([[0, 0], [0, 3], [1, 3]])  # place 2 is most probable nowhere: it keeps its anchor (1, 3)
    base = partition(labels, anchors)
    np.testing.assert_array_equal(base, [[0, 0, -1, 1, 1], [0, 0, -1, 2, 1]])
    piece = partition(labels, anchors, np.array([0]), np.array([[1, 4]]))  # the stray piece becomes a seed of 0
    np.testing.assert_array_equal(piece, [[0, 0, -1, 1, 1], [0, 0, -1, 2, 0]])
    alone = partition(labels, anchors, np.array([0]), np.array([[0, 4]]))  # a cell of 1's piece: taken, then grown
    np.testing.assert_array_equal(alone, [[0, 0, -1, 1, 0], [0, 0, -1, 2, 0]])
    pinned = partition(labels, anchors, np.array([0]), np.array([[1, 3]]))  # place 2's anchor: not taken
    np.testing.assert_array_equal(pinned, base)


def test_a_place_under_a_stronger_neighbour_keeps_its_anchor_not_its_rim():
    """Issue 24 item 2: a name taught once beside a room is a one-event place, a broad Gaussian of small weight.
    At its own mean the room's place is more probable, so its most probable cells form a rim far from its mean;
    its territory used to be that rim's largest piece, and "go to" it ended 1.1-3.7 m from where it was taught.
    Its seed is now its anchor (the cell nearest its mean, where its own density is highest)."""
    data = np.full((32, 92), 100, dtype=np.int8)
    data[1:31, 1:91] = 0  # one room 9 m x 3 m
    occ = OccupancyMap(data=data, resolution=0.1)
    m = model_at([(3.0, 1.5), (4.5, 1.5)], [0.7, 1.4], occ)
    m.phi = np.array([[0.97, 0.03]])  # p(i): the room 0.97, the taught place 0.03
    mask = occ.data == 0
    centres = occ.cell_centres()
    post = m.place_posterior(centres)
    anchor = tuple(occ.world_to_cell(np.array([4.5, 1.5])))
    assert post[anchor][0] > post[anchor][1]  # the room is more probable at the taught place's own mean
    assert ((post[..., 1] > post[..., 0]) & mask).any()  # the taught place wins only away from it (the rim)
    t = place_territories(m, mask, centres)
    assert t[anchor] == 1
    _, n = ndimage.label(t == 1, structure=FOUR)
    assert n == 1  # one piece: no territory on the far rim
    far = np.argwhere(t == 1)
    assert np.abs(occ.cell_to_world(far) - np.array([4.5, 1.5])).max() < 1.0
