"""Split-merge moves of the concepts (experimental/split_merge.py): exact detailed balance by enumeration, and a
merged concept that single-site Gibbs cannot split but split-merge does."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest
from scipy.special import gammaln

from spcotmhp.errors import ModelError
from spcotmhp.experimental import research_learner
from spcotmhp.experimental.split_merge import SplitMerge, SplitMergeMoves
from spcotmhp.learning.concepts import CollapsedConceptSampler
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.model import Hyperparameters
from tests.helpers.learning import planted_dataset

ALPHA, GAMMA, BETA, CHI = 0.5, 0.3, 0.2, 0.7


def _dirmult(counts: np.ndarray, c: float) -> float:
    """log Dirichlet-multinomial of one ordered sequence with counts ``counts`` (written out, not imported)."""
    M = counts.shape[-1]
    return float(gammaln(M * c) - gammaln(M * c + counts.sum()) + np.sum(gammaln(c + counts) - gammaln(c)))


def _log_target(C, places, concept_words, feats, L, K) -> float:
    """log p(C | i, S, z, f) up to a constant, by the formula: pi, then per concept phi, W and theta."""
    lp = _dirmult(np.bincount(C, minlength=L).astype(float), ALPHA)
    for l in range(L):
        m = C == l
        lp += _dirmult(np.bincount(places[m], minlength=K).astype(float), GAMMA)
        lp += _dirmult(concept_words[m].sum(axis=0), BETA)
        lp += _dirmult(feats[m].sum(axis=0), CHI)
    return lp


def _small_case():
    words = np.array([[2, 1, 0], [1, 0, 1], [0, 1, 1], [0, 0, 2]], dtype=float)
    feats = np.array([[0.5, 0.25, 0.25], [0.1, 0.6, 0.3], [0.2, 0.2, 0.6], [0.7, 0.1, 0.2]])
    places = np.array([0, 0, 1, 1])
    sampler = CollapsedConceptSampler(words, feats, background=True, rng=np.random.default_rng(0))
    sampler.z = np.array([1, 0, 1, 1, 1, 0, 1, 1, 1], dtype=bool)  # two background tokens
    concept_words = sampler.concept_words()
    return sampler, places, concept_words, feats


def _transitions(moves: SplitMerge, C: np.ndarray, places: np.ndarray) -> dict[tuple, float]:
    """Every state one move reaches from C and its probability, by enumerating the move's random choices."""
    E, out = len(C), {}
    for i, j in itertools.permutations(range(E), 2):
        rest = [e for e in range(E) if e not in (i, j) and C[e] in (C[i], C[j])]
        perms = list(itertools.permutations(rest))
        for perm in perms:
            order = np.array([i, j, *perm], dtype=np.int64)
            p = 1.0 / (E * (E - 1)) / len(perms)
            if C[i] != C[j]:
                side = (C[order] == C[j]).astype(np.int64)
                _, logq = moves.allocate(order, places, forced=side)
                choices = [(side, logq, -1, 1.0)]
            else:
                empty = [l for l in range(moves.L) if not (C == l).any()]
                choices = []
                for sides in itertools.product((0, 1), repeat=len(rest)):
                    side = np.array([0, 1, *sides], dtype=np.int64)
                    _, logq = moves.allocate(order, places, forced=side)
                    choices += [(side, logq, new, np.exp(logq) / len(empty)) for new in empty]
            for side, logq, new, q in choices:
                proposal, log_ratio = moves.propose(C, places, order, side, logq, new)
                key = tuple(proposal)
                out[key] = out.get(key, 0.0) + p * q * min(1.0, np.exp(log_ratio))
    return out


def test_split_merge_satisfies_detailed_balance_exactly():
    L, K = 3, 2
    sampler, places, concept_words, feats = _small_case()
    moves = SplitMerge(sampler, K, L, ALPHA, GAMMA, BETA, CHI)
    states = [np.array(s) for s in itertools.product(range(L), repeat=4)]
    target = {tuple(s): _log_target(s, places, concept_words, feats, L, K) for s in states}
    T = {tuple(s): _transitions(moves, s, places) for s in states}
    checked = 0
    for a, row in T.items():
        for b, t_ab in row.items():
            if a == b:
                continue
            t_ba = T[b].get(a, 0.0)
            assert t_ba > 0.0, (a, b)
            np.testing.assert_allclose(np.exp(target[a]) * t_ab, np.exp(target[b]) * t_ba, rtol=1e-9)
            checked += 1
    assert checked > 300
    for row in T.values():  # proposals and rejections never lose probability
        assert sum(v for b, v in row.items()) <= 1.0 + 1e-12


def test_allocation_probability_by_hand():
    # order (0, 1, 2): events 0 and 1 open the two sides, event 2 is the only one allocated
    sampler, places, concept_words, feats = _small_case()
    moves = SplitMerge(sampler, 2, 3, ALPHA, GAMMA, BETA, CHI)
    _, logq = moves.allocate(np.array([0, 1, 2]), places, forced=np.array([0, 1, 0]))
    lp = []
    for e in (0, 1):
        # predictive of event 2 given one event on the side: place, concept tokens, features
        place = np.log(1 + ALPHA) + np.log((places[e] == places[2]) + GAMMA) - np.log(1 + 2 * GAMMA)
        w = concept_words[e]
        words = _dirmult(w + concept_words[2], BETA) - _dirmult(w, BETA)
        f = _dirmult(feats[e] + feats[2], CHI) - _dirmult(feats[e], CHI)
        lp.append(place + words + f)
    want = lp[0] - np.logaddexp(lp[0], lp[1])
    assert abs(logq - want) < 2e-3  # features below SMALL_COUNT use x psi(a) in the proposal (collapsed_terms.py)
    _, logq_empty = moves.allocate(np.array([0, 1]), places, forced=np.array([0, 1]))
    assert logq_empty == 0.0


def _two_rooms(n: int = 40):
    """n utterances naming the kitchen at place 0, n naming the bath at place 1, the same function words."""
    vocab = ["this", "is", "the", "kitchen", "bath"]
    words = np.zeros((2 * n, len(vocab)))
    words[:, :3] = 1.0
    words[:n, 3] = 1.0
    words[n:, 4] = 1.0
    places = np.repeat([0, 1], n)
    return words, places


def _mixed(C: np.ndarray, n: int) -> int:
    """Events in concepts that hold at least n // 4 events of both rooms."""
    return sum(int((C == l).sum()) for l in np.unique(C) if min((C[:n] == l).sum(), (C[n:] == l).sum()) >= n // 4)


def test_single_site_gibbs_stays_merged_and_split_merge_separates():
    n, L, K = 40, 10, 5
    words, places = _two_rooms(n)
    runs = {}
    for use_moves in (False, True):
        rng = np.random.default_rng(3)
        sampler = CollapsedConceptSampler(words, None, background=False, rng=rng)
        moves = SplitMerge(sampler, K, L, ALPHA, 0.05, 0.1, CHI)
        C = np.zeros(2 * n, dtype=np.int64)  # one concept for both rooms
        for _ in range(30):
            C = sampler.sweep(C, places, L, K, ALPHA, 0.05, 0.1, CHI, rng)
            if use_moves:
                C = moves.sweep(C, places, rng)
        runs[use_moves] = C
    assert _mixed(runs[False], n) == 2 * n  # every event still shares its concept with the other room
    C = runs[True]
    assert _mixed(C, n) == 0
    assert len(set(C[:n]) & set(C[n:])) == 0  # no concept holds both rooms


def test_auto_uses_the_moves_only_without_image_features():
    data = planted_dataset(E=40)
    feats = np.random.default_rng(0).random((data.n_events, 4))
    with_features = dataclasses.replace(data, features=feats)
    assert SpCoTMHP(iterations=2).fit(data).model_.info["split_merge"] is False  # off by default
    assert research_learner("auto", iterations=2).fit(data).model_.info["split_merge"] is True
    assert research_learner("auto", iterations=2).fit(with_features).model_.info["split_merge"] is False
    assert SpCoTMHP(iterations=2, variant=SplitMergeMoves()).fit(with_features).model_.info["split_merge"] is True


def test_settings_that_cannot_combine_are_refused():
    data = planted_dataset(E=20)
    with pytest.raises(ModelError, match="split_merge must be True, False or 'auto', got 'yes'"):
        research_learner("yes")
    with pytest.raises(ModelError, match="split_merge moves do not price place_concepts"):
        research_learner(True, iterations=2, hyper=Hyperparameters(place_concepts=1.0)).fit(data)
