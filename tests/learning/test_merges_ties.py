"""The name a place is called by when two names tie in p(n | k) (spcotmhp.learning.merges._called_by): two places
whose events one concept explains say that concept's names equally; each is called by the name taught at it, so
neither name is reported as merged (Nav2's depot map, seed 0: "first bay" and "bay 3" each a place, one concept)."""

from __future__ import annotations

import numpy as np

from spcotmhp.learning.merges import TIE_LOG, TaughtName, _called_by


def names() -> list[TaughtName]:
    return [TaughtName(("bay", "3"), np.array([0, 1, 2])), TaughtName(("first", "bay"), np.array([3, 4, 5]))]


def test_a_tie_goes_to_the_name_taught_at_the_place():
    place = np.array([7, 7, 7, 9, 9, 9])  # bay 3 taught at place 7, first bay at place 9
    log_p = np.log([[0.41, 0.41], [0.41, 0.41 * (1 - TIE_LOG / 10)]])  # hand-made: a tie at both places
    assert _called_by(log_p, names(), place, np.array([7, 9])).tolist() == [0, 1]


def test_no_tie_keeps_the_word_term():
    place = np.array([7, 7, 7, 9, 9, 9])
    log_p = np.log([[0.6, 0.4], [0.6, 0.4]])  # place 9 says bay 3 more: its name, whatever was taught there
    assert _called_by(log_p, names(), place, np.array([7, 9])).tolist() == [0, 0]
    assert _called_by(log_p, names(), None, np.array([7, 9])).tolist() == [0, 0]
