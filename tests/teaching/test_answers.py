"""Answers to the robot's questions (issue 24, ``spcotmhp.teaching.answers``): the departures each do what they
say on hand-computed cases, the paper's model is unchanged for everything that is not an answer, and the answer
members survive a model folder."""

from __future__ import annotations

import hashlib
import warnings

import numpy as np
import pytest

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.errors import TeachingError
from spcotmhp.evaluation.online_eval import dataset_events
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.distributions import GaussianStats
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.learner_state import member_of, state_of_member
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent, as_event
from spcotmhp.learning.online_split_merge import _relabel, log_target
from spcotmhp.learning.posterior import Priors
from spcotmhp.persistence.io import load_model, save_model
from spcotmhp.teaching.answers import (
    ANSWER_MODELS,
    answer_model,
    attach_walk,
    concepts_from_places,
    own_concept,
    own_concepts,
    split_at_answer,
    walk_gain,
    walk_owner,
    walk_poses,
)
from spcotmhp.teaching.teach import teach


def _state(xs, places, concepts, alone=None, weight=None, K=4, L=3) -> CollapsedState:
    """A state of events at ``xs`` (one word each, word 0) with the given assignments, built by appending then
    setting the assignments through ``move`` (so the counts are the state's own bookkeeping)."""
    st = CollapsedState(K, L, 1, None, Hyperparameters(), replay=False, background=False)
    rng = np.random.default_rng(0)
    for j, x in enumerate(xs):
        st.append(np.asarray(x, float), np.array([0]), None, rng, False,
                  bool(alone[j]) if alone else False, float(weight[j]) if weight else 1.0)  # fmt: skip
    for j in range(st.E):
        st.move(j, -1.0)
    for j in range(st.E):
        st.place[j], st.concept[j] = places[j], concepts[j]
        st.move(j, 1.0)
    return st


def test_an_alone_event_has_no_transition_and_its_neighbours_are_linked():
    """Events in places 0, 1 (an answer, alone), 0: the walk is 0 -> 0, so trans holds one 0 -> 0 step and nothing
    for place 1; the answer's conditional has no psi factor (equal to the one without transitions)."""
    st = _state([(0, 0), (5, 5), (0, 1)], [0, 1, 0], [0, 1, 0], alone=[False, True, False])
    expected = np.zeros((4, 4))
    expected[0, 0] = 1.0
    np.testing.assert_array_equal(st.trans, expected)
    assert st.neighbours(0) == (-1, 2) and st.neighbours(2) == (0, -1) and st.neighbours(1) == (-1, -1)
    st.move(1, -1.0)
    np.testing.assert_array_equal(st.log_conditional(1), st.log_conditional(1, transitions=False))


def test_a_weighted_event_counts_as_w_events_and_its_conditional_is_to_the_power_w():
    """Weight 3 at (2, 1): n_k += 3, sx += 3 x, sxx += 3 x x^T, n_l and n_lk += 3, its word 3 times; removing
    it restores the counts; its conditional is 3 times that of the same event with weight 1."""
    st = _state([(0, 0), (2, 1)], [0, 1], [0, 1], weight=[1.0, 3.0])
    assert st.n_k[1] == 3.0 and st.n_l[1] == 3.0 and st.n_lk[1, 1] == 3.0 and st.W_lv[1, 0] == 3.0
    np.testing.assert_array_equal(st.sx[1], [6.0, 3.0])
    np.testing.assert_array_equal(st.sxx[1], [[12.0, 6.0], [6.0, 3.0]])
    assert st.trans[0, 1] == 1.0  # a transition is one step of the walk, whatever the weight
    st.move(1, -1.0)
    assert st.n_k[1] == 0.0 and st.W_lv[1, 0] == 0.0 and not st.trans.any()
    heavy = st.log_conditional(1)
    st.weight[1] = 1.0
    np.testing.assert_allclose(heavy, 3.0 * st.log_conditional(1))


def test_walk_poses_keep_one_pose_per_half_metre_travelled():
    """A straight walk of 2 m in 0.1 m steps: poses at 0, 0.5, 1.0, 1.5 and 2.0 m (the first step into each
    0.5 m of travel)."""
    traj = np.stack([np.linspace(0.0, 2.0, 21), np.zeros(21)], axis=1)
    np.testing.assert_allclose(walk_poses(traj)[:, 0], [0.0, 0.5, 1.0, 1.5, 2.0], atol=1e-9)
    assert walk_poses(traj[:1]).shape == (1, 2)


def test_walk_gain_is_the_niw_marginal_of_events_and_their_poses_minus_the_events_alone():
    """Two places; poses near each go to it (walk_owner); the gain equals the NIW marginals computed directly."""
    st = _state([(0, 0), (0.5, 0), (6, 6), (6.5, 6)], [0, 0, 1, 1], [0, 0, 1, 1])
    assert walk_gain(st) == 0.0
    st.walk_X = np.array([[0.2, 0.1], [6.2, 6.1], [0.3, -0.2]])
    np.testing.assert_array_equal(walk_owner(st), [0, 1, 0])
    gauss = Priors.build(st.hyper, st.K, st.L, st.V, st.D).gauss
    X = np.vstack([st.X, st.walk_X])
    with_walk = GaussianStats.from_assignments(X, np.array([0, 0, 1, 1, 0, 1, 0]), st.K)
    expected = gauss.log_marginal(with_walk) - gauss.log_marginal(GaussianStats.from_assignments(st.X, st.place, st.K))
    assert walk_gain(st) == pytest.approx(expected, rel=1e-12)


def test_the_split_at_an_answer_separates_two_rooms_and_not_one():
    """Ten events at each of two spots 8 m apart learned as one place and concept: the split at an answer in one
    of them is kept (log_target rises) and gives the two rooms; ten events around one spot stay one place."""
    rng = np.random.default_rng(1)
    two = np.vstack([rng.normal((0, 0), 0.3, (10, 2)), rng.normal((8, 0), 0.3, (10, 2))])
    st = _state(two, [0] * 20, [0] * 20, K=6, L=4)
    before = log_target(st)
    assert split_at_answer(st, 0, np.random.default_rng(0))
    assert log_target(st) > before
    assert len(set(st.place[:10])) == 1 and len(set(st.place[10:])) == 1 and st.place[0] != st.place[10]
    one = _state(rng.normal((0, 0), 0.3, (20, 2)), [0] * 20, [0] * 20, K=6, L=4)
    assert not split_at_answer(one, 0, np.random.default_rng(0))
    assert set(one.place) == {0}


FRAMES = (("we", "are", "in", "the"), ("this", "place", "is", "called"), ("here", "is", "the"), ("this", "is", "the"),
          ("you", "are", "in", "the"), ())  # fmt: skip
NAMES = ("kitchen", "bath", "toilet", "dining", "living", "study", "hall", "office", "garage")
WORDS = sorted({w for f in FRAMES for w in f}) + list(NAMES)


def _framed(concept_of, n=10) -> CollapsedState:
    """Nine rooms 4 m apart on a line, ``n`` events each, said in six frames in turn ("we are in the kitchen",
    "this place is called kitchen", ..., "kitchen"), with background words, every token a concept token
    (collapsed switches), and the concept of an event in room r said in frame f ``concept_of(r, f)``."""
    rng = np.random.default_rng(3)
    st = CollapsedState(12, 12, len(WORDS), None, Hyperparameters(), replay=False, background=True)
    st.words = list(WORDS)
    rooms = []
    for r, name in enumerate(NAMES):
        for j in range(n):
            tokens = np.array([WORDS.index(w) for w in [*FRAMES[j % len(FRAMES)], name]])
            st.append(rng.normal((4.0 * r, 0.0), 0.3), tokens, None, rng)
            rooms.append((r, j % len(FRAMES)))
    for j in range(st.E):
        st.move(j, -1.0)
    for j, (r, f) in enumerate(rooms):
        st.z[j][:] = True
        st.place[j], st.concept[j] = r, concept_of(r, f)
        st.move(j, 1.0)
    return st


def _snapshot(st: CollapsedState) -> list[np.ndarray]:
    return [np.copy(getattr(st, n)) for n in ("n_k", "n_l", "n_lk", "W_lv", "bg_v", "z_tot", "place", "concept")] + [
        np.concatenate(st.z)
    ]


def test_concepts_from_places_gathers_concepts_by_place_and_frames_into_the_background():
    """Concepts learned by the sentence's frame (one per frame, both rooms in each) with every token a concept
    token: the move is kept, the joint rises above the old state's at its switch mode, each room ends with one
    concept of its own, and the names stay concept tokens while most frame words go to the background."""
    st = _framed(lambda r, f: f)
    at_mode = _framed(lambda r, f: f)
    at_mode.switch_mode()
    assert concepts_from_places(st)
    assert log_target(st) > log_target(at_mode)
    rooms = st.concept.reshape(len(NAMES), -1)
    assert (rooms == rooms[:, :1]).all() and len(set(rooms[:, 0])) == len(NAMES)
    names = np.concatenate([[WORDS[v] in NAMES for v in t] for t in st.tokens])
    z = np.concatenate(st.z)
    assert z[names].all() and z.mean() < 0.5  # every name a concept token, most frame words in the background


def test_concepts_from_places_leaves_a_state_it_cannot_improve_as_it_was():
    """Once kept, the move made again is not kept (its proposal is where the state already is) and every count
    and switch stays as it was, bit for bit; a state without its vocabulary is not touched."""
    st = _framed(lambda r, f: r)
    assert concepts_from_places(st)  # by room already, but every frame word a concept token
    before = _snapshot(st)
    assert not concepts_from_places(st)
    assert all(np.array_equal(a, b) for a, b in zip(before, _snapshot(st), strict=True))
    st.words = None
    assert not concepts_from_places(st)


def test_with_joint_an_event_put_in_a_far_place_goes_back_to_its_room():
    """One kitchen event learned in the garage's place (32 m away): concepts derived again with ``joint`` move it
    back to the kitchen's place; without ``joint`` places are held and it stays."""
    for joint in (False, True):
        st = _framed(lambda r, f: f)
        garage = int(st.place[-1])
        st.move(0, -1.0)
        st.place[0], st.concept[0] = garage, 0
        st.move(0, 1.0)
        assert concepts_from_places(st, joint=joint)
        assert (st.place[0] == st.place[1]) == joint and (st.place[0] == garage) != joint


def test_own_concept_separates_two_rooms_of_two_names_sharing_a_concept():
    """Two rooms of different names in one concept: a concept of its own for one room is kept (each name then
    in one concept); a room that already has a concept of its own is left alone."""
    st = _framed(lambda r, f: r)
    concepts_from_places(st)  # frame words in the background
    kitchen = np.flatnonzero(st.place == 0)
    _relabel(st, "concept", np.flatnonzero(st.place == 1), int(st.concept[kitchen[0]]))  # bath in kitchen's concept
    st.switch_mode()
    before = log_target(st)
    assert own_concept(st, 0)
    assert log_target(st) > before
    assert len(set(st.concept[:10])) == 1 and st.concept[0] != st.concept[10]
    snapshot = _snapshot(st)
    assert own_concepts(st, 0) == 0
    assert all(np.array_equal(a, b) for a, b in zip(snapshot, _snapshot(st), strict=True))


def test_answer_flags_are_read_and_bad_ones_refused():
    assert as_event({"x": 1, "y": 2, "utterance": "this is the study", "answer": True}).answer
    assert not as_event({"x": 1, "y": 2, "words": ["study"]}).answer
    with pytest.raises(TeachingError, match="'answer' must be true or false"):
        as_event({"x": 1, "y": 2, "utterance": "this is the study", "answer": "yes"})
    with pytest.raises(TeachingError, match="answers must be one of"):
        answer_model("louder")
    assert ANSWER_MODELS["paper"].learner_settings() == {
        "answer_alone": False,
        "answer_weight": 1.0,
        "after_answer": None,
    }


def _digest(line: str) -> str:
    return hashlib.sha256(line.encode()).hexdigest()[:16]


def test_the_paper_model_is_unchanged_where_nothing_is_an_answer():
    """Online learning of 3LDK_01's first 60 events, batch Gibbs (10 sweeps) and one ordinary teach give exactly
    what main gave before answers existed (digests of the printed results, computed with main at 87153de by the
    same lines); events marked as answers under the paper's answer model learn exactly as unmarked ones."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_bundled("3LDK_01")
        events = dataset_events(data)[:60]
        online = OnlineSpCoTMHP(K=10, L=10, map=data.map, check_map=False, seed=3).partial_fit(events)
        batch = SpCoTMHP(K=10, L=10, iterations=10, seed=1).fit(data)
        x, y = (float(v) for v in data.positions[3])
        taught = teach(batch.model_, [{"x": x, "y": y, "utterance": "this is the study"}])
        marked = OnlineSpCoTMHP(
            K=10, L=10, map=data.map, check_map=False, seed=3, **ANSWER_MODELS["paper"].learner_settings()
        )
        marked.partial_fit([TeachingEvent(e.x, e.y, e.words, e.features, e.named, answer=True) for e in events])
    assert _digest(f"online {online.places_.tolist()} {online.concepts_.tolist()}") == "be8beef9c822b500"
    line = f"batch {batch.places_.tolist()} {batch.concepts_.tolist()} {round(float(batch.log_joint_), 6)!r}"
    assert _digest(line) == "6dc75c0e613e4c81"
    assert _digest(f"teach {taught.places} {round(float(taught.model.mu[taught.places[0]][0]), 9)!r}") == (
        "367d09e7d63cb7c7"
    )
    np.testing.assert_array_equal(marked.places_, online.places_)
    np.testing.assert_array_equal(marked.concepts_, online.concepts_)


def test_answers_and_the_walk_survive_a_model_folder(tmp_path):
    """A model taught one answer (alone, weight 3) with a walk attached: saved and loaded, its learner state
    holds the same flags, weights and poses, and its counts still cover its events."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_bundled("3LDK_01")
        model = (
            OnlineSpCoTMHP(K=10, L=10, map=data.map, check_map=False, seed=0)
            .partial_fit(dataset_events(data)[:30])
            .model_
        )
    assert attach_walk(model, np.asarray(data.positions[:30]))
    x, y = (float(v) for v in data.positions[0])
    model = teach(model, [{"x": x, "y": y, "utterance": "this is the study", "answer": True}], "alone+split+w3").model
    st = state_of_member(model.learner, model)
    assert st.alone[-1] and st.weight[-1] == 3.0 and not any(st.alone[:-1]) and st.walk_X is not None
    back = load_model(save_model(model, tmp_path / "m"))
    again = state_of_member(back.learner, back)
    assert again.alone == st.alone and again.weight == st.weight
    np.testing.assert_array_equal(again.walk_X, st.walk_X)
    for name, value in member_of(st)["arrays"].items():
        np.testing.assert_array_equal(back.learner["arrays"][name], value)


def test_the_predictive_of_many_positions_is_that_of_each():
    """``log_predictive`` of (P, 2) positions (walk_owner's) equals P single calls, to the bit, with an empty
    place at the map's density."""
    st = _state([(0, 0), (0.5, 0.2), (6, 6), (6.5, 5.8)], [0, 0, 1, 1], [0, 0, 1, 1])
    st.log_new_place = -3.0
    xy = np.array([[0.1, 0.3], [5.0, 6.0], [-2.0, 1.0]])
    np.testing.assert_array_equal(st.log_predictive(xy), np.stack([st.log_predictive(x) for x in xy]))
    assert (st.log_predictive(xy)[:, 2:] == -3.0).all()
