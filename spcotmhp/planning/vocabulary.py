"""Which words of a learned vocabulary name places, and what to call each place.

The instruction parser matches place words against the model's vocabulary; these functions decide which
vocabulary words count as place words (on-site names in any language, never function words) and give each place
a readable label for plans and explanations.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy.special import logsumexp

from spcotmhp.planning.grammar import GRAMMARS

PLACE_WORD_RATIO = 0.75
"""A word is a place word when, for some active place, its rescaled score is >= this fraction of the best
word's score for that place (see :func:`place_vocabulary`)."""


_FUNCTION_WORDS = frozenset().union(*(g.fillers | g.connectors | set(g.markers) for g in GRAMMARS.values()))
"""Grammar and filler words of every supported language (never place words)."""


def place_vocabulary(model: Any, ratio: float = PLACE_WORD_RATIO, instance_ratio: float = 10.0) -> list[str]:
    """The words of ``model.vocabulary`` that name places, sorted.

    Score of word w for place k: sum_l p(l | k) W_l(w) / sum_c W_c(w), the unigram-rescaled word probability that
    :meth:`SpatialConceptModel.place_names` ranks by. Function words spread over the concepts ("this", です) score
    about 1/(number of concepts using them); a name scores near 1 for its places (1/3 for each of three
    bedrooms with a concept each, which is then also the best score of those places). A word is kept when

    1. it scores at least ``ratio`` (0.75) times the best word of some active place, so every word of a
       multi-word name ("entrance corridor") is kept and a function word shared by two concepts (1/2) is not;
    2. and, with more than one active place, it does not name every active place: p(i | w) (Eq. 28's semantic
       term for the bag {w}) is below 1/``instance_ratio`` of its maximum for some place;
    3. and it is not a grammar or filler word of a supported language ("here", "called", "um", です): rules 1-2
       alone cannot tell a filler from a name shared by many places ("office" x 7 scores 1/7, as "called" or a
       noise word may in little data). A site whose name is such a word cannot be named in instructions.
    """
    if not len(model.vocabulary):
        return []
    act = np.asarray(model.active_places, dtype=bool)
    with np.errstate(divide="ignore"):
        log_pi, log_phi, log_W = np.log(model.pi), np.log(model.phi), np.log(model.W)
    lp_lk = log_pi[:, None] + log_phi
    p_l_given_k = np.exp(lp_lk - logsumexp(lp_lk, axis=0, keepdims=True))
    rescaled = model.W / model.W.sum(axis=0, keepdims=True)
    score = (p_l_given_k.T @ rescaled)[act]
    keep = (score >= ratio * score.max(axis=1, keepdims=True)).any(axis=0)
    if act.sum() > 1:
        semantic = logsumexp(lp_lk[:, :, None] + log_W[:, None, :], axis=0)[act]      # (K_active, V)
        keep &= ~(semantic >= semantic.max(axis=0) - np.log(instance_ratio)).all(axis=0)
    return sorted(w for w, k in zip(model.vocabulary, keep) if k and w not in _FUNCTION_WORDS)


def place_labels(model: Any, place_words: Sequence[str]) -> list[str]:
    """A name per place: the place word it is most often called, argmax_w sum_l p(l | k) W_l(w) over
    ``place_words`` (function words are already out, so no rescaling is needed, and a name shared by many
    places is not beaten by a rare noise word); ``model.place_names()`` where no place word is known."""
    fallback = model.place_names()
    if not place_words:
        return fallback
    idx = [model.word_index[w] for w in place_words]
    with np.errstate(divide="ignore"):
        lp_lk = np.log(model.pi)[:, None] + np.log(model.phi)
    p_l_given_k = np.exp(lp_lk - logsumexp(lp_lk, axis=0, keepdims=True))
    best = np.argmax(p_l_given_k.T @ model.W[:, idx], axis=1)
    return [place_words[j] for j in best]
