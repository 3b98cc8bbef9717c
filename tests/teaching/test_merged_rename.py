"""Issue 35's scenario on a generated home: two rooms learned as one place, then "this is the playroom" taught
twice more renamed the merged place, so "go to the bedroom" ended in the playroom. With the taught-merge split
(``learning.taught_split``) the bedroom keeps a place of its own and the plan ends in it."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.datasets.synthetic import generate_environment
from spcotmhp.learning.taught_split import split_taught_merges
from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
from spcotmhp.teaching.questions import name_vocabulary, said_merges
from spcotmhp.teaching.teach import planner_for, teach
from tests.helpers.merged_rooms import forced

KITCHEN, BEDROOM, LIVING = 0, 1, 2  # the rooms of generate_environment("flat", seed=1): kitchen, bedroom, living


@pytest.fixture(scope="module")
def home():
    """The flat, its kitchen taught as "playroom" 5 times and its bedroom 5 times, a wall between them; the
    sample the learner kept put both rooms in one place and one concept."""
    data = generate_environment("flat", seed=1, events_per_room=5)
    assert data.place_names == ["kitchen", "bedroom", "living"]
    data.tokens = [["playroom" if w == "kitchen" else w for w in t] for t in data.tokens]
    rooms = np.where(data.truth_place == KITCHEN, BEDROOM, data.truth_place)
    return data, rooms


def _bedroom_after_two_playroom_teaches(model, data):
    playroom = data.positions[data.truth_place == KITCHEN]
    for x, y in playroom[:2]:
        model = teach(model, [{"x": float(x), "y": float(y), "utterance": "this is the playroom"}]).model
    planner, _ = planner_for(model)
    end = planner.plan("go to the bedroom", data.positions[data.truth_place == LIVING][0]).path[-1]
    means = [data.positions[data.truth_place == room].mean(axis=0) for room in (BEDROOM, KITCHEN)]
    return model, [float(np.hypot(*(end - m))) for m in means]


def test_without_the_split_the_issue_reproduces(home):
    data, rooms = home
    model = forced(data, rooms, rooms).model_
    assert [m.sentence for m in said_merges(model)] == [
        "playroom and bedroom share place 1; taught 5 and 5 times, 3.3 m apart"
    ]
    model, (to_bedroom, to_playroom) = _bedroom_after_two_playroom_teaches(model, data)
    assert to_playroom < to_bedroom  # "go to the bedroom" ends nearer the playroom's teaching points
    assert [(m.name, m.other) for m in said_merges(model)] == [("bedroom", "playroom")]  # said out loud, at least


def test_with_the_split_go_to_the_bedroom_ends_in_the_bedroom(home):
    data, rooms = home
    est = forced(data, rooms, rooms)
    model = est.model_
    words, labels = name_vocabulary(model), place_labels(model, place_vocabulary(model))
    (s,) = split_taught_merges(est, data, words, labels).splits
    assert (s.name, s.other, s.between) == ("playroom", "bedroom", "wall")
    model, (to_bedroom, to_playroom) = _bedroom_after_two_playroom_teaches(est.model_, data)
    assert to_bedroom < 1.0 < to_playroom
    assert said_merges(model) == []
