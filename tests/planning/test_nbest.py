"""N-best weights and the heaviest group of parsed hypotheses (planning/nbest.py), hand-computed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spcotmhp.errors import EmptyInstruction, InstructionTooLarge, MalformedInstruction
from spcotmhp.planning.nbest import heaviest_group, nbest_weights, normalise_scores


def test_confidences_are_divided_by_their_sum_and_all_zero_is_uniform():
    assert normalise_scores(np.array([3.0, 1.0, 0.0])).tolist() == [0.75, 0.25, 0.0]
    assert normalise_scores(np.array([0.0, 0.0])).tolist() == [0.5, 0.5]


def test_log_probabilities_are_softmaxed():
    w = normalise_scores(np.log(np.array([0.6, 0.3, 0.1])))
    assert w == pytest.approx([0.6, 0.3, 0.1], abs=1e-12)
    assert normalise_scores(np.array([-1000.0, -1000.0 - math.log(3)])) == pytest.approx([0.75, 0.25])


def test_mixed_signs_are_refused():
    with pytest.raises(MalformedInstruction, match="all >= 0"):
        normalise_scores(np.array([1.0, -1.0]))


def test_nbest_weights_keeps_the_texts_in_order():
    texts, w = nbest_weights([["b", 1], ("a", np.float32(3))], 2)
    assert texts == ["b", "a"] and w.tolist() == [0.25, 0.75]


@pytest.mark.parametrize(
    "hypotheses, error, message",
    [
        ("go", MalformedInstruction, "must be a list"),
        ([], EmptyInstruction, "empty"),
        ([("a", 1)] * 3, InstructionTooLarge, "3 hypotheses, more than the 2"),
        ([("a", 1, 2)], MalformedInstruction, "entry 0 must be"),
        ([("a", 1), (2, 1)], MalformedInstruction, "entry 1 must be"),
        ([("a", True)], MalformedInstruction, "non-numeric"),
        ([("a", float("inf"))], MalformedInstruction, "non-finite"),
        ([("a", 10**400)], MalformedInstruction, "non-finite"),
    ],
)
def test_bad_lists_are_refused(hypotheses, error, message):
    with pytest.raises(error, match=message):
        nbest_weights(hypotheses, 2)


def test_the_heaviest_shape_wins_and_its_weights_are_renormalised():
    parsed = [("a", 0.1), ("bb", 0.2), ("c", 0.3), ("dd", 0.4)]  # length 1: 0.4, length 2: 0.6
    assert heaviest_group(parsed, len) == [("bb", pytest.approx(1 / 3)), ("dd", pytest.approx(2 / 3))]


def test_a_tie_goes_to_the_smaller_group_and_zero_weights_are_uniform():
    assert heaviest_group([("a", 0.25), ("b", 0.25), ("cc", 0.5)], len) == [("cc", 1.0)]
    assert heaviest_group([("a", 0.0), ("b", 0.0)], len) == [("a", 0.5), ("b", 0.5)]
