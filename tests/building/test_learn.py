"""Learning a building: supervised, Gibbs (batch) and online on the joint dataset; one vocabulary and concept set
across floors; places on their floor; teaching on a floor lands there."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.building.learn import default_places, learn_building, learn_building_online, teach_building
from spcotmhp.building.synthetic import generate_building
from spcotmhp.errors import TeachingError, UnknownFloor
from spcotmhp.planning.vocabulary import place_labels, place_vocabulary


@pytest.fixture(scope="module")
def building():
    return generate_building(3, seed=6, n_rooms=5, events_per_room=8)


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


def _labels(bm, f):
    view = bm.floor_model(f)
    names = place_labels(view, place_vocabulary(view))
    return sorted(names[k] for k in np.flatnonzero(view.active_places))


def test_supervised_concepts_are_shared(building):
    bm = learn_building(building)
    names = sorted({n for d in building.floors.values() for n in d.place_names})
    assert int(bm.model.active_concepts.sum()) == len(names)  # one concept per name, not per floor
    for f in bm.indices:
        assert _labels(bm, f) == sorted(building.floors[f].place_names)


def test_gibbs_places_stay_on_their_floors(building):
    bm = learn_building(building, supervised=False, runs=1, iterations=30, seed=1)
    assert bm.model.K == default_places(3) == 60
    floor = bm.place_floor()
    act = np.flatnonzero(bm.model.active_places)
    lay = bm.layout
    for k in act:  # every active place's mean lies on its floor's map, not in a gap
        t = lay.tile(int(floor[k]))
        x = bm.model.mu[k, 0] / lay.resolution
        assert t.col0 - 1 <= x <= t.col0 + t.shape[1] + 1
    for f in bm.indices:  # every floor has places, named from the shared vocabulary
        labels = _labels(bm, f)
        assert len(labels) >= 3 and "kitchen" in " ".join(labels)


def test_online_learning(building):
    bm = learn_building_online(building, seed=0)
    for f in bm.indices:
        assert bm.floor_places(f).sum() >= 3
        assert "kitchen" in " ".join(_labels(bm, f))


def test_teaching_lands_on_the_floor(building):
    bm = learn_building(building)
    d = building.floors[3]
    free = np.argwhere(d.map.data == 0)
    # a point far from every place of floor 3: the free cell farthest from its teaching positions
    xy = d.map.cell_to_world(free)
    far = xy[np.argmax(np.min(np.hypot(*(xy[:, None] - d.positions[None]).transpose(2, 0, 1)), axis=1))]
    updated, taught = teach_building(bm, [{"x": float(far[0]), "y": float(far[1]), "utterance": "this is the library"}],
                                     "second")  # fmt: skip
    k = taught.places[0]
    assert taught.new_places[0] and updated.place_floor()[k] == 3
    assert "library" in _labels(updated, 3) and "library" not in " ".join(_labels(updated, 1))
    assert np.allclose(updated.floor_model(3).mu[k], far, atol=0.5)
    with pytest.raises(TeachingError, match="off floor 2's map"):
        teach_building(bm, [(-100.0, 0.0, "this is the library")], 2)
    with pytest.raises(UnknownFloor):
        teach_building(bm, [(1.0, 1.0, "this is the library")], 9)
