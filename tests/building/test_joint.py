"""The joint dataset: every floor's events on their own cells of the joint grid, truth numbered building-wide,
concepts shared by name, adjacency block-diagonal; floors that disagree are refused."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from spcotmhp.building.joint import joint_dataset
from spcotmhp.building.loader import Building
from spcotmhp.building.synthetic import generate_building
from spcotmhp.errors import BuildingError


@pytest.fixture(scope="module")
def building():
    return generate_building(3, seed=2, n_rooms=5, events_per_room=4)


def test_events_keep_their_cells(building):
    lay = building.layout()
    d = joint_dataset(building, lay)
    assert d.n_events == sum(f.n_events for f in building.floors.values())
    start = 0
    for i in lay.indices:
        f = building.floors[i]
        mine = d.positions[start : start + f.n_events]
        cells = f.map.world_to_cell(f.positions) + [0, lay.tile(i).col0]
        assert (d.map.world_to_cell(mine) == cells).all()
        assert d.tokens[start : start + f.n_events] == f.tokens
        assert (lay.floor_of(mine) == i).all()
        start += f.n_events
    assert d.name == building.name and d.lang == "en"


def test_trajectories_follow_one_another(building):
    d = joint_dataset(building)
    assert d.trajectory is not None and d.event_steps is not None
    assert len(d.trajectory) == sum(len(f.trajectory) for f in building.floors.values())
    assert (np.diff(d.event_steps) >= 0).all()
    assert np.allclose(d.trajectory[d.event_steps], d.positions)


def test_truth_is_building_wide_and_concepts_are_shared_by_name(building):
    d = joint_dataset(building)
    sizes = [len(f.place_names) for f in building.floors.values()]
    assert len(d.place_names) == sum(sizes)
    names = np.array(d.place_names)
    # every event's truth place carries the name its floor gave it
    expect = np.concatenate([np.array(f.place_names)[f.truth_place] for f in building.floors.values()])
    assert (names[d.truth_place] == expect).all()
    # one concept per name, whatever the floor
    for c in np.unique(d.truth_concept):
        assert len(set(names[d.truth_place[d.truth_concept == c]])) == 1
    kitchens = {int(c) for c in d.truth_concept[names[d.truth_place] == "kitchen"]}
    assert len(kitchens) == 1
    A = d.adjacency
    assert A.shape == (sum(sizes), sum(sizes))
    assert A[: sizes[0], sizes[0] :].sum() == 0 and A[sizes[0] :, : sizes[0]].sum() == 0


def test_floors_must_agree(building):
    floors = dict(building.floors)
    floors[2] = dataclasses.replace(floors[2], trajectory=None, event_steps=None)
    with pytest.raises(BuildingError, match=r"floor\(s\) 1, 3 have a trajectory.csv and floor\(s\) 2 do not"):
        joint_dataset(Building(building.spec, floors))
    feats = {i: dataclasses.replace(f, features=np.ones((f.n_events, 3 + i))) for i, f in building.floors.items()}
    with pytest.raises(BuildingError, match="image features have different widths"):
        joint_dataset(Building(building.spec, feats))
    no_names = {i: dataclasses.replace(f, place_names=None, adjacency=None) for i, f in building.floors.items()}
    d = joint_dataset(Building(building.spec, no_names))
    assert d.place_names is None and d.adjacency is None
    assert d.truth_concept is not None  # as given: the floors' ids, read building-wide
