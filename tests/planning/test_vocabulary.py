"""Which words name places (``spcotmhp.planning.vocabulary``), on hand-made models."""

from __future__ import annotations

import dataclasses

import numpy as np

from spcotmhp.planning.vocabulary import place_labels, place_vocabulary
from tests.helpers.planning import home_model


def test_grammar_words_set_no_bar_for_a_places_names():
    """A teach said "this is the study" at the learned 3LDK_06's small pantry: "this is the" went into the
    pantry's concept, outscored "pantry" (and "study") there, and "pantry" stopped being a place word (audit L1).
    Here the kitchen's concept says kitchen 0.2, pantry 0.13, this and the 0.3 each; a fifth concept holds no
    data (uniform words, pi 0.01), as a weak-limit model's empty ones do. Rescaled at the kitchen: kitchen
    0.2 / (0.2 + 1/6) = 0.545, pantry 0.13 / 0.297 = 0.438 >= 0.75 * 0.545, this 0.3 / 0.467 = 0.643 (whose bar,
    0.482, pantry would miss)."""
    base = home_model()
    vocab = [*base.vocabulary, "pantry", "the", "this"]  # bedroom, corridor, kitchen, pantry, the, this
    W = np.full((5, 6), 1e-4)
    W[:4, :3] = base.W
    W[2, :] = [1e-4, 1e-4, 0.2, 0.13, 0.3, 0.3]
    W[4, :] = 1 / 6
    W /= W.sum(axis=1, keepdims=True)
    phi = np.vstack([base.phi, np.full(4, 0.25)])
    pi = np.array([0.2475] * 4 + [0.01])
    active = np.array([True] * 4 + [False])  # the fifth concept holds no data
    model = dataclasses.replace(base, W=W, vocabulary=vocab, phi=phi, pi=pi, active_concepts=active)
    words = place_vocabulary(model)
    assert words == ["bedroom", "corridor", "kitchen", "pantry"]
    assert place_labels(model, words)[2] == "kitchen"  # pantry, said 0.13 < 0.75 * 0.2, is not in the label


def test_a_place_whose_events_carry_no_name_is_not_labelled_with_every_name():
    """A new place taught "this is the" (or, on m01 over HTTP, "ここ") holds no place word: its p(l | k) spread
    over every concept, it said each name equally, and its label was every name of the home (audit L2). Four
    concepts say their name 0.4 and this, is, the 0.2 each (7 words: chance 1/7); place 3's p(l | k) is uniform,
    so it says each name 0.25 * 0.4 = 0.1 < 1/7; place 0's concept 0 (p 0.75) says bedroom 0.3."""
    names = ["bedroom", "corridor", "kitchen", "study"]
    base = home_model()
    W = np.full((4, 7), 0.1)  # bedroom, corridor, kitchen, study, this, is, the
    W[:, :4] = 0.0
    W[np.arange(4), np.arange(4)] = 0.4
    W[:, 4:] = 0.2
    phi = np.zeros((4, 4))
    phi[:3, :3] = 0.8 * np.eye(3)
    phi[3, :3] = 0.8 / 3
    phi[:, 3] = 0.2
    model = dataclasses.replace(base, W=W, vocabulary=[*names, "this", "is", "the"], phi=phi, pi=np.full(4, 0.25))
    labels = place_labels(model, names)
    assert labels == ["bedroom", "corridor", "kitchen", "place 3"]
