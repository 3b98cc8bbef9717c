"""The planner's memo of place phrases (spcotmhp/planning/phrases.py): the same terms as computed afresh,
read-only, bounded, emptied for new settings, refusals never kept."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from spcotmhp.errors import UnknownPlaceWord
from spcotmhp.planning.phrases import PhraseMemo, phrase_key
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.query import PlaceQuery
from tests.helpers.graphs import GRAPHS
from tests.helpers.planning import home_log_p, home_model, world


@pytest.fixture(scope="module")
def planner() -> HierarchicalPlanner:
    model = home_model()
    return HierarchicalPlanner(model, log_p=home_log_p(model.map), cache=GRAPHS)


@pytest.mark.parametrize("words", [{"bedroom": 1.0}, {"kitchen": 1.0}, {"corridor": 1.0}])
@pytest.mark.parametrize("stage", [True, False])
def test_kept_terms_equal_fresh_ones(planner, words, stage):
    query = PlaceQuery(words, " ".join(words))
    semantic, likely = planner.terms.stage_terms([words], planner.settings.instance_ratio)
    for _ in range(2):  # computed, then read from the memo
        got_semantic, got_places = planner.phrase_terms(query, stage)
        assert np.array_equal(got_semantic, semantic[0])
        assert np.array_equal(got_places, planner.instances(query, likely[0], stage))
        assert not got_semantic.flags.writeable and not got_places.flags.writeable


def test_plans_the_same_from_the_memo():
    model = home_model()
    fresh = HierarchicalPlanner(model, log_p=home_log_p(model.map), cache=GRAPHS)
    start = world(model.map, 3, 12)
    first = fresh.plan("go to the bedroom via the kitchen", start)
    again = fresh.plan("go to the bedroom via the kitchen", start)
    assert first.explanation == again.explanation and np.array_equal(first.cells, again.cells)
    assert len(fresh._phrases._kept) == 2  # bedroom and kitchen, each as a stage


def test_refusals_are_not_kept(planner):
    query = PlaceQuery({"bedroom": 1.0, "kitchen": 1.0}, "bedroom kitchen")
    for _ in range(2):
        with pytest.raises(UnknownPlaceWord):
            planner.phrase_terms(query, True)
    assert phrase_key(query, True) not in planner._phrases._kept


def test_memo_is_bounded_and_follows_the_owner():
    memo = PhraseMemo(limit=2)
    calls = []

    def compute():
        calls.append(1)
        return np.zeros(3), np.zeros(3, dtype=bool)

    owner = object()
    for key in ("a", "b", "a", "c", "c"):
        memo.get(key, owner, compute)
    assert len(calls) == 3 and list(memo._kept) == ["c"]  # "a" computed once; "c" emptied the full memo
    memo.get("a", owner, compute)
    assert len(calls) == 4
    memo.get("a", object(), compute)  # another owner (new settings): computed again
    assert len(calls) == 5
    memo.get(None, owner, compute)
    memo.get(None, owner, compute)  # no key: never kept
    assert len(calls) == 7


def test_key_holds_what_the_terms_depend_on():
    one = PlaceQuery({"bedroom": 1.0}, "bedroom")
    assert phrase_key(one, True) != phrase_key(one, False)
    assert phrase_key(one, True) == phrase_key(dataclasses.replace(one, label="the bedroom"), True)
    assert phrase_key(one, True) != phrase_key(dataclasses.replace(one, every=True), True)
    assert phrase_key(one, True) != phrase_key(dataclasses.replace(one, floor=2), True)
    nbest = dataclasses.replace(one, alternatives=({"bedroom": 0.6}, {"bathroom": 0.4}))
    assert phrase_key(one, True) != phrase_key(nbest, True)
    assert phrase_key(PlaceQuery({"bedroom": [1.0]}, "bedroom"), True) is None  # type: ignore[dict-item]
