"""Named places (planning/places.py): a place is named by a bag when its label holds every word of one of the
bag's phrases, whether the labels are given as strings or as a LabelIndex built once."""

from __future__ import annotations

import numpy as np

from spcotmhp.planning.places import LabelIndex, named_places

LABELS = ["bedroom", "east corridor", "west corridor", "kitchen", "alice's room", "bedroom"]


def test_named_places_by_hand():
    index = LabelIndex(LABELS)
    for labels in (LABELS, index):
        assert named_places(labels, [{"corridor": 1.0}]).tolist() == [False, True, True, False, False, False]
        assert named_places(labels, [{"east": 1.0, "corridor": 1.0}]).tolist() == [False, True] + [False] * 4
        assert named_places(labels, [{"bedroom": 0.6}, {"kitchen": 0.4}]).tolist() == [
            True,
            False,
            False,
            True,
            False,
            True,
        ]
        assert not named_places(labels, [{"garage": 1.0}]).any()
        assert not named_places(labels, [{"bedroom": 0.0}]).any()  # a zero weight names nothing
        assert not named_places(labels, [{"east": 1.0, "kitchen": 1.0}]).any()


def test_label_index_matches_the_label_words():
    rng = np.random.default_rng(0)
    words = ["a", "b", "c", "d"]
    for _ in range(100):
        labels = [" ".join(rng.choice(words, size=rng.integers(1, 3), replace=False)) for _ in range(6)]
        phrases = [{str(w): 1.0 for w in rng.choice(words, size=rng.integers(1, 3), replace=False)} for _ in range(2)]
        expected = [any(set(p) <= set(label.split()) for p in phrases) for label in labels]
        assert named_places(LabelIndex(labels), phrases).tolist() == expected
