"""The gate of answers judged with the robot's walk (``teaching.answers``: ``gate``, ``gated_split_at_answer``)
and questions in turns (``teaching.questions``): on hand-built maps and states."""

from __future__ import annotations

import copy

import numpy as np

from spcotmhp.learning import online, teaching_events
from spcotmhp.metric.maps import FREE, OCCUPIED, OccupancyMap
from spcotmhp.teaching.answers import (
    ANSWER_MODELS,
    SplitEvidence,
    evidence_of,
    gated_split_at_answer,
    narrow_passage,
    two_names,
    walk_split_at_answer,
)
from spcotmhp.teaching.questions import _in_turns
from tests.teaching.test_answers import _state

RES = 0.1


def _map(free_boxes) -> OccupancyMap:
    """A 60 x 100-cell map (0.1 m cells), occupied but for the boxes (row0, col0, row1, col1) given."""
    grid = np.full((60, 100), OCCUPIED, dtype=np.int8)
    for r0, c0, r1, c1 in free_boxes:
        grid[r0:r1, c0:c1] = FREE
    return OccupancyMap(grid, RES)


def _evidence(occ: OccupancyMap) -> SplitEvidence:
    from scipy.ndimage import distance_transform_edt

    return SplitEvidence(distance_transform_edt(occ.free) * RES, occ, frozenset({0}))


def _halves(occ: OccupancyMap, a_cells, b_cells):
    """A state of events at the given cells' centres, the first list in place 0, the second in place 1."""
    xy = occ.cell_to_world(np.array(list(a_cells) + list(b_cells)))
    places = [0] * len(a_cells) + [1] * len(b_cells)
    return _state(xy, places, places, K=4, L=3)


TWO_ROOMS = [(5, 5, 35, 35), (5, 60, 35, 90), (18, 35, 24, 60)]  # 3 x 3 m rooms, a 0.6 m wide passage between
L_ROOM = [(5, 5, 25, 95), (5, 5, 55, 25)]  # one L-shaped room, arms 2 m wide
CORRIDOR = [(20, 5, 36, 95)]  # a straight corridor 1.6 m wide and 9 m long


def test_a_door_between_two_rooms_is_narrow_and_one_rooms_shape_is_not():
    """Events in the two rooms: their only path passes the 0.6 m door (clearance 0.3 m, against 1.5 m in the
    rooms): narrow. The two arms of an L (clearance 1 m all along) and the two ends of a corridor: not narrow."""
    occ = _map(TWO_ROOMS)
    st = _halves(occ, [(15, 15), (25, 25), (20, 20)], [(15, 70), (25, 80), (20, 75)])
    assert narrow_passage(_evidence(occ), st, 0, 1)
    occ = _map(L_ROOM)
    st = _halves(occ, [(15, 80), (15, 60)], [(45, 15), (35, 15)])
    assert not narrow_passage(_evidence(occ), st, 0, 1)
    occ = _map(CORRIDOR)
    st = _halves(occ, [(28, 10), (28, 30)], [(28, 70), (28, 90)])
    assert not narrow_passage(_evidence(occ), st, 0, 1)


def test_without_a_map_or_an_event_on_free_space_the_map_cannot_tell():
    occ = _map(TWO_ROOMS)
    st = _halves(occ, [(15, 15)], [(15, 70)])
    assert not narrow_passage(SplitEvidence(None, None, frozenset()), st, 0, 1)
    wall = _halves(occ, [(15, 15)], [(2, 2)])  # the second half's only event on an occupied cell
    assert not narrow_passage(_evidence(occ), wall, 0, 1)


def test_two_names_are_two_different_sets_of_name_words():
    """Words 0 "west", 1 "east", 2 "corridor", 3 "place" (a name word here), 4 "the" (not one): {west, corridor}
    and {east, corridor} are two names; {corridor} and {place, corridor} are one (one within the other); events
    without a name word do not count."""
    st = _state([(0, 0)] * 4, [0] * 4, [0] * 4)
    words = frozenset({0, 1, 2, 3})
    st.tokens = [np.array([0, 2]), np.array([1, 2]), np.array([4]), np.array([2, 3])]
    assert two_names(st, np.array([0, 1]), words)
    assert two_names(st, np.array([0, 3]), words)  # {west, corridor} and {corridor, place}
    assert not two_names(st, np.array([0, 2]), words)
    st.tokens[0] = np.array([2])
    assert not two_names(st, np.array([0, 2, 3]), words)


def test_the_gate_keeps_a_split_through_a_door_and_judges_one_room_by_its_events():
    """Ten events of one name in each of two rooms joined by a door, learned as one place, with a walk through
    both: the gated split is kept (the halves meet at the door). Twenty events of one name along a corridor with
    a walk end to end: the walk alone would split it; the gate refers it to the events, which keep it one."""
    rng = np.random.default_rng(2)
    occ = _map(TWO_ROOMS)
    cells = np.vstack([rng.integers((10, 10), (30, 30), (10, 2)), rng.integers((10, 65), (30, 85), (10, 2))])
    st = _state(occ.cell_to_world(cells), [0] * 20, [0] * 20, K=6, L=4)
    st.walk_X = occ.cell_to_world(np.array([(20, c) for c in range(10, 86, 5)]))
    assert gated_split_at_answer(st, 0, np.random.default_rng(0), _evidence(occ))
    assert st.place[0] != st.place[10] and len(set(st.place[:10])) == 1 and len(set(st.place[10:])) == 1
    occ = _map(CORRIDOR)
    cells = np.stack([np.full(20, 28), np.linspace(8, 92, 20).astype(int)], axis=1)
    st = _state(occ.cell_to_world(cells), [0] * 20, [0] * 20, K=6, L=4)
    st.walk_X = occ.cell_to_world(np.array([(28, c) for c in range(6, 95)] * 4))
    ungated = copy.deepcopy(st)
    assert walk_split_at_answer(ungated, 0, np.random.default_rng(0)) and len(set(ungated.place)) == 2
    assert not gated_split_at_answer(st, 0, np.random.default_rng(0), _evidence(occ))
    assert set(st.place) == {0}


def test_questions_in_turns_start_with_the_walks_split_after_an_even_number_of_answers():
    split, named = [{"q": "s1"}, {"q": "s2"}], [{"q": "n1"}, {"q": "n2"}, {"q": "n3"}]
    assert [q["q"] for q in _in_turns(split, named, 0)] == ["s1", "n1", "s2", "n2", "n3"]
    assert [q["q"] for q in _in_turns(split, named, 1)] == ["n1", "s1", "n2", "s2", "n3"]
    assert [q["q"] for q in _in_turns([], named, 0)] == ["n1", "n2", "n3"]


def test_gated_answer_models_bind_their_evidence_and_without_a_model_admit_no_walk():
    how = ANSWER_MODELS["alone+split+gated-walk"]
    after = how.learner_settings()["after_answer"]
    assert after.keywords["evidence"] == evidence_of(None) == SplitEvidence(None, None, frozenset())
    assert ANSWER_MODELS["alone+split+walk"].learner_settings()["after_answer"].__name__ == "walk_split_at_answer"


def test_teaching_events_live_in_their_own_module_and_online_re_exports_them():
    assert online.TeachingEvent is teaching_events.TeachingEvent and online.as_event is teaching_events.as_event
