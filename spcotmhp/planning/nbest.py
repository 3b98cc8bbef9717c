"""N-best lists of recogniser hypotheses, before and after parsing (Eq. 25 of Taniguchi et al. 2024).

A list ``[(text, score), ...]`` is validated and its scores turned into weights that sum to 1
(:func:`nbest_weights`); once every hypothesis is parsed, the hypotheses sharing the heaviest shape are kept with
their weights renormalised among them (:func:`heaviest_group`), so that stage e's bag can be the weighted sum
sum_h w_h S_{h,e}. :func:`spcotmhp.planning.instructions.parse_nbest` puts the two together.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Hashable, Sequence
from typing import Any, TypeVar

import numpy as np

from spcotmhp.errors import EmptyInstruction, InstructionTooLarge, MalformedInstruction
from spcotmhp.language.wording import excerpt
from spcotmhp.logspace import logsumexp

T = TypeVar("T")


def nbest_weights(hypotheses: Any, most: int) -> tuple[list[str], np.ndarray]:
    """The texts of an N-best list and the weights of their scores (:func:`normalise_scores`).

    Raises:
        MalformedInstruction: not a list, an entry not [text, score], a score not a finite number.
        EmptyInstruction: an empty list. InstructionTooLarge: more than ``most`` entries.

    >>> nbest_weights([("go to the kitchen", 3), ("go to the kitten", 1)], 50)
    (['go to the kitchen', 'go to the kitten'], array([0.75, 0.25]))
    >>> nbest_weights([("go to the kitchen", 1.5e308), ("go to the kitten", 1.5e308)], 50)[1]
    array([0.5, 0.5])
    """
    if not isinstance(hypotheses, (list, tuple)):
        raise MalformedInstruction(f"an N-best list must be a list of [text, score] pairs, got {excerpt(hypotheses)}")
    if not hypotheses:
        raise EmptyInstruction("the N-best list is empty")
    if len(hypotheses) > most:
        raise InstructionTooLarge(f"the N-best list has {len(hypotheses)} hypotheses, more than the {most} accepted")
    texts, scores = [], []
    for i, h in enumerate(hypotheses):
        if not isinstance(h, (list, tuple)) or len(h) != 2 or not isinstance(h[0], str):
            raise MalformedInstruction(f"N-best entry {i} must be [text, score], got {excerpt(h)}")
        if isinstance(h[1], bool) or not isinstance(h[1], (int, float, np.integer, np.floating)):
            raise MalformedInstruction(f"N-best entry {i} has a non-numeric score {excerpt(h[1])}")
        try:
            s = float(h[1])
        except OverflowError:
            s = math.inf
        if not math.isfinite(s):
            raise MalformedInstruction(f"N-best entry {i} has a non-finite score {excerpt(h[1])}")
        texts.append(h[0])
        scores.append(s)
    return texts, normalise_scores(np.array(scores))


def normalise_scores(scores: np.ndarray) -> np.ndarray:
    """Weights summing to 1: confidences (all >= 0) divided by their sum (uniform when all are 0), or
    log-probabilities (all <= 0) soft-maxed; MalformedInstruction for a mix of signs."""
    if (scores >= 0).all():
        # scaled by the largest first: the weights are the same, and confidences of 1e308 cannot overflow the sum
        # (it is then at most the number of hypotheses)
        top = scores.max()
        if not top > 0:
            return np.full(len(scores), 1.0 / len(scores))
        scaled = scores / top
        return scaled / scaled.sum()
    if (scores <= 0).all():
        return np.exp(scores - logsumexp(scores))
    raise MalformedInstruction(
        "N-best scores must be all >= 0 (confidences) or all <= 0 (log-probabilities), "
        f"got {excerpt(str(scores.tolist()))}"
    )


def heaviest_group(parsed: Sequence[tuple[T, float]], shape: Callable[[T], Hashable]) -> list[tuple[T, float]]:
    """The parsed hypotheses ``(item, weight)`` whose ``shape`` has the largest total weight (ties: the smaller
    group, then the first seen), with the weights renormalised to sum 1 among them (uniform when they sum to 0).

    >>> heaviest_group([("a", 0.2), ("bb", 0.3), ("cc", 0.3), ("d", 0.2)], len)
    [('bb', 0.5), ('cc', 0.5)]
    """
    groups: dict[Hashable, list[tuple[T, float]]] = {}
    for item, w in parsed:
        groups.setdefault(shape(item), []).append((item, w))
    group = max(groups.values(), key=lambda g: (sum(w for _, w in g), -len(g)))
    total = sum(w for _, w in group)
    return [(item, w / total if total > 0 else 1.0 / len(group)) for item, w in group]
