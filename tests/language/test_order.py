"""spcotmhp.language.order: the sort taken without pairs is the constrained order (Kahn's algorithm) without pairs,
and the documented cases by hand."""

from __future__ import annotations

from dataclasses import replace

import pytest
from hypothesis import given
from hypothesis import strategies as st

from spcotmhp.errors import UnsupportedPhrase
from spcotmhp.language.order import Visit, _constrained_order, visiting_order


def _clauses_in_spoken_order(visits: list[Visit]) -> list[Visit]:
    """Clauses as a sentence has them: never a lower clause said after a higher one."""
    clauses = sorted(v.clause for v in visits)
    by_spoken = sorted(range(len(visits)), key=lambda k: visits[k].spoken)
    return [replace(visits[k], clause=clauses[by_spoken.index(k)]) for k in range(len(visits))]


visit_lists = st.lists(
    st.builds(
        Visit,
        spoken=st.integers(0, 20),
        rank=st.integers(0, 2),
        step=st.integers(0, 3),
        role=st.sampled_from(["goal", "via", "stop", "visit"]),
        tied=st.booleans(),
        clause=st.integers(0, 3),
    ),
    min_size=1,
    max_size=8,
    unique_by=lambda v: v.spoken,
).map(_clauses_in_spoken_order)


@given(visit_lists)
def test_the_sort_without_pairs_is_kahns_order_without_pairs(visits):
    assert visiting_order(visits, []) == _constrained_order(visits, [])
    assert visiting_order(visits, [(0, 0)]) == _constrained_order(visits, [])  # a place before itself: no pair


def test_orders_by_hand():
    # "go to the bedroom via the corridor, then to the kitchen": corridor, bedroom | kitchen
    visits = [Visit(0, role="goal"), Visit(1, role="via"), Visit(2, step=1, role="goal")]
    assert visiting_order(visits, []) == [1, 0, 2]
    # "finally the bath, first the toilet, go to the kitchen": toilet, kitchen, bath
    visits = [Visit(0, rank=2), Visit(1, rank=0), Visit(2)]
    assert visiting_order(visits, []) == [1, 2, 0]
    # two goals in one step: the last said is the destination, the other is visited first
    assert visiting_order([Visit(0), Visit(1)], []) == [0, 1]
    # "go to the kitchen before the bedroom": the pair puts the kitchen first
    assert visiting_order([Visit(0, tied=True), Visit(1)], [(0, 1)]) == [0, 1]


def test_a_stop_on_the_way_keeps_the_narrated_order():
    """Rule 4's exception: a destination that is a stop on the way (a later step or rank follows) goes after the
    places of its own clause only; places said in later clauses keep their spoken order."""
    # "go to the kitchen, pass through the corridor, and end at the entrance": kitchen, corridor, entrance
    visits = [Visit(0, role="goal", clause=1), Visit(1, role="via", clause=2), Visit(2, rank=2, clause=3)]
    assert visiting_order(visits, []) == [0, 1, 2]
    # "go to the kitchen via the corridor and end at the entrance": corridor, kitchen, entrance
    visits = [Visit(0, role="goal", clause=1), Visit(1, role="via", clause=1), Visit(2, rank=2, clause=2)]
    assert visiting_order(visits, []) == [1, 0, 2]
    # "go to the bedroom, through the corridor": the final destination, so the corridor comes first
    visits = [Visit(0, role="goal", clause=1), Visit(1, role="via", clause=2)]
    assert visiting_order(visits, []) == [1, 0]


def test_contradicting_pairs_are_refused():
    with pytest.raises(UnsupportedPhrase, match="contradict each other"):
        visiting_order([Visit(0, role="visit"), Visit(1, role="visit")], [(0, 1), (1, 0)])
