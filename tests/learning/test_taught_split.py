"""The taught-merge report and split (issue 35, item 5; spcotmhp/learning/merges.py, taught_split.py,
separation.py), on hand-built teaching: two rooms taught "bedroom" and "playroom" 5 times each, 3 m apart, learned
as one place (the merge the issue saw), with a wall, a door on the line between them, or no wall."""

from __future__ import annotations

import hypothesis.strategies as st
import numpy as np
import pytest
from hypothesis import given, settings

from spcotmhp.learning.merges import merges, taught_names
from spcotmhp.learning.separation import Separation
from spcotmhp.learning.taught_split import split_taught_merges
from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
from spcotmhp.teaching.questions import name_vocabulary
from tests.helpers.merged_rooms import forced, merged_fit, rooms_map, two_names


def _split(est, data):
    model = est.model_
    return split_taught_merges(est, data, name_vocabulary(model), place_labels(model, place_vocabulary(model)))


def _said(model):
    return merges(model, name_vocabulary(model), place_labels(model, place_vocabulary(model)))


def test_the_merge_is_reported_with_counts_and_distance():
    """Both names at place 0: the second most taught one ('playroom', 5 teaches; ties keep the order of the
    names, both 5) is reported against the place's name; the means are (1.5, 1.96) and (4.5, 1.96): 3.0 m."""
    model = merged_fit(two_names("wall")).model_
    (m,) = _said(model)
    assert {m.name, m.other} == {"bedroom", "playroom"}
    assert (m.place, m.taught, m.other_taught) == (0, 5, 5)
    assert m.apart_m == pytest.approx(3.0)
    assert m.sentence == f"{m.name} and {m.other} share place 0; taught 5 and 5 times, 3.0 m apart"


def test_names_with_places_of_their_own_are_not_reported():
    data = two_names("wall")
    rooms = np.repeat([0, 1], 5)
    assert _said(forced(data, rooms, rooms).model_) == []


def test_one_name_in_two_rooms_is_one_name_and_the_counts_are_those_at_the_shared_place():
    """Four rooms: 'bedroom' taught in two (places 0 and 1), 'storeroom' (4 teaches) learned into the second
    bedroom's place, a kitchen of its own (without it "bedroom" would be said at every place, which
    ``place_vocabulary`` does not count as a name). Only the storeroom is reported, with the teaches at place 1
    (4 and 5, not 4 and 10) and the distance between those means: bedroom's offsets average (0, -0.04), the
    storeroom's (0.075, 0.05), the centres 2 m apart in y: hypot(0.075, 2.09) = 2.09 m."""
    centres = ((1.5, 1.0), (4.5, 1.0), (4.5, 3.0), (1.5, 3.0))
    names = ("bedroom", "bedroom", "storeroom", "kitchen")
    data = two_names("none", names=names, counts=(5, 5, 4, 5), centres=centres)
    places = np.array([0] * 5 + [1] * 5 + [1] * 4 + [2] * 5)
    concepts = np.array([0] * 10 + [1] * 4 + [2] * 5)
    (m,) = _said(forced(data, places, concepts).model_)
    assert (m.name, m.other, m.place, m.taught, m.other_taught) == ("storeroom", "bedroom", 1, 4, 5)
    assert m.apart_m == pytest.approx(np.hypot(0.075, 2.09))


@pytest.mark.parametrize("between", ["wall", "door"])
def test_a_wall_or_a_door_between_splits_the_place(between):
    """With a wall between the rooms (door off the line) or a door on the line, the playroom's events leave
    place 0 for the lowest empty place and concept; then both names have places of their own."""
    data = two_names(between)
    est = merged_fit(data)
    outcome = _split(est, data)
    (s,) = outcome.splits
    assert s.between == between and s.place == 0 and s.new_place == 1
    moved = np.flatnonzero(est.places_ == 1)
    assert [data.tokens[e][-1] for e in moved] == [s.name] * 5
    assert len(set(est.concepts_[moved])) == 1 and est.concepts_[moved[0]] != est.concepts_[0]
    model = est.model_
    assert int(model.active_places.sum()) == 2 and _said(model) == []
    assert np.allclose(model.mu[1], data.positions[moved].mean(axis=0), atol=1e-2)
    assert model.info["taught_split"]["splits"][0]["between"] == between
    assert model.learner["arrays"]["place"].tolist() == est.places_.tolist()


def test_the_split_is_deterministic():
    data = two_names("wall")
    runs = [merged_fit(data) for _ in range(2)]
    for est in runs:
        _split(est, data)
    assert np.array_equal(runs[0].places_, runs[1].places_)
    assert np.allclose(runs[0].model_.mu, runs[1].model_.mu)


def test_one_open_room_taught_with_two_names_is_reported_not_split():
    data = two_names("none")
    est = merged_fit(data)
    before = est.places_.copy()
    outcome = _split(est, data)
    assert outcome.splits == [] and np.array_equal(est.places_, before)
    ((m, why),) = outcome.kept
    assert "no wall or door" in why
    assert [x.sentence for x in _said(est.model_)] == [m.sentence]
    assert "taught_split" in est.model_.info


def test_a_name_taught_once_is_not_split():
    """Playroom taught once behind the wall: reported (taught 1 and 5 times), kept (rule 1: 3 teaches each)."""
    data = two_names("wall", counts=(5, 1))
    est = merged_fit(data)
    outcome = _split(est, data)
    assert outcome.splits == []
    ((m, why),) = outcome.kept
    assert (m.name, m.taught, m.other_taught) == ("playroom", 1, 5)
    assert "fewer than 3" in why


def test_two_names_each_taught_three_times_are_split_and_two_are_not():
    for n, splits in ((3, 1), (2, 0)):
        data = two_names("wall", counts=(5, n))
        assert len(_split(merged_fit(data), data).splits) == splits


def test_taught_names_come_from_the_learner_state():
    model = merged_fit(two_names("wall", counts=(5, 3))).model_
    names = taught_names(model, name_vocabulary(model))
    assert [(n.text, len(n.events)) for n in names] == [("bedroom", 5), ("playroom", 3)]


def test_separation_rules_on_the_hand_built_maps():
    """A segment through the wall is a wall; through the door on the line it crosses nothing, but the 0.8 m door
    closes in the open space (clearance 0.45 m < 0.7 m), so the rooms are two open components: a door."""
    a, b = np.array([[1.5, 2.0]]), np.array([[4.5, 2.0]])
    assert Separation(rooms_map("wall")).between(a, b) == "wall"
    door = Separation(rooms_map("door"))
    assert not door.wall(a[0], b[0]) and door.between(a, b) == "door"
    assert Separation(rooms_map("none")).between(a, b) is None
    assert Separation(rooms_map("none")).between(a, np.array([[6.5, 2.0]])) == "wall"  # off the map


def test_two_names_in_one_narrow_corridor_are_not_separated():
    """A 1.2 m corridor (clearance at most 0.6 m, below the rooms' 0.7 m): cut at 3/4 of its own clearance, the
    corridor itself does not separate two names taught along it."""
    data = np.full((40, 60), 100, dtype=np.int8)
    data[14:26, 1:59] = 0
    from spcotmhp.metric.maps import OccupancyMap

    sep = Separation(OccupancyMap(data, resolution=0.1))
    a = np.array([[1.3, 2.0], [1.5, 1.8], [1.7, 2.2]])
    assert sep.between(a, a + [3.0, 0.0]) is None


_points = st.lists(st.tuples(st.floats(0.3, 5.7), st.floats(0.3, 3.7)), min_size=1, max_size=6).map(
    lambda p: np.array(p, dtype=float)
)


@settings(max_examples=60, deadline=None)
@given(A=_points, B=_points, between=st.sampled_from(["wall", "door", "none"]))
def test_separation_is_symmetric_and_nothing_separates_in_an_empty_room(A, B, between):
    sep = Separation(rooms_map(between))
    assert sep.between(A, B) == sep.between(B, A)
    if between == "none":
        assert sep.between(A, B) is None  # the room's inside is free: no wall, no narrowing
