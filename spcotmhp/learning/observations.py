"""What the learners observe: a dataset as the batch sampler's arrays (positions, word counts and image feature
counts, validated: :class:`Observations`), and teaching events, what the online learner takes one at a time ("this
is alice's room" at x, y: :class:`TeachingEvent`) in the forms it accepts them (:func:`as_event`)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeGuard

import numpy as np

from spcotmhp.errors import DatasetError, TeachingError
from spcotmhp.language.text import is_japanese
from spcotmhp.language.text import words as text_words
from spcotmhp.learning.model import bag_counts
from spcotmhp.learning.model_values import MAX_WORD_CHARS

if TYPE_CHECKING:  # not at run time: loading a model for planning reads this module and needs no dataset
    from spcotmhp.datasets.dataset import Dataset


@dataclass
class Observations:
    """Arrays the sampler works on.

    Attributes:
        X: (E, 2) teaching positions x_e.
        words: (E, V) counts of each vocabulary word in S_e (bag of words; Eq. 17 is a product over words).
        vocabulary: the V words (sorted), index = column of ``words``.
        features: (E, D) image feature counts f_e, or None.
        trajectory: (T, 2) robot positions, or None.
        event_steps: (E,) index into the trajectory of each event, or None.
    """

    X: np.ndarray
    words: np.ndarray
    vocabulary: list[str]
    features: np.ndarray | None = None
    trajectory: np.ndarray | None = None
    event_steps: np.ndarray | None = None

    @property
    def E(self) -> int:
        return int(self.X.shape[0])

    @classmethod
    def from_dataset(
        cls,
        dataset: Dataset,
        use_features: bool = True,
        use_trajectory: bool = True,
        vocabulary: list[str] | None = None,
        feature_weight: float | None = 1.0,
    ) -> Observations:
        """Validate ``dataset`` and build the arrays; raises DatasetError naming the problem.

        ``vocabulary`` fixes the word columns (words outside it are dropped); by default the dataset's own.
        ``feature_weight``: each event's feature row is rescaled to sum to this weight (the image is one
        observation of a scene distribution, like one word); None converts them as the authors did,
        ``features_to_counts`` (p * 10 + 1 cast to int, about 375 counts per Places365 image).
        """
        name = dataset.name
        X = _checked_positions(name, dataset.positions)
        E = X.shape[0]
        if len(dataset.tokens) != E:
            raise DatasetError(f"{name}: {len(dataset.tokens)} token lists for {E} teaching events")
        for e, toks in enumerate(dataset.tokens):  # before learning: the model's vocabulary would refuse it after
            try:
                check_word_lengths(toks, f"teaching event {e + 1} of {E} (its words in teaching.csv)")
            except TeachingError as exc:
                raise DatasetError(f"{name}: {exc}") from None
        vocab = sorted({t for toks in dataset.tokens for t in toks}) if vocabulary is None else list(vocabulary)
        if not vocab:
            raise DatasetError(
                f"{name}: no teaching event has any word; spatial concepts are learned from the words of the utterances"
            )
        index = {w: j for j, w in enumerate(vocab)}
        words = np.zeros((E, len(vocab)))
        for e, toks in enumerate(dataset.tokens):
            words[e] = bag_counts(toks, index, len(vocab))
        features = None
        if use_features and dataset.features is not None:
            features = scale_features(_checked_features(name, dataset.features, E), feature_weight)
        trajectory = steps = None
        if use_trajectory and dataset.trajectory is not None:
            trajectory = _checked_trajectory(name, dataset.trajectory)
            if dataset.event_steps is not None:
                steps = np.asarray(dataset.event_steps, dtype=np.int64)
        return cls(X=X, words=words, vocabulary=vocab, features=features, trajectory=trajectory, event_steps=steps)


def _checked_positions(name: str, positions: np.ndarray) -> np.ndarray:
    """The teaching positions as a float (E, 2) array of finite x, y with E >= 2, else DatasetError."""
    X = np.asarray(positions, dtype=float)
    if X.ndim != 2 or X.shape[1] != 2:
        raise DatasetError(f"{name}: positions must be an (E, 2) array of x, y, got shape {X.shape}")
    if X.shape[0] == 0:
        raise DatasetError(f"{name}: no teaching events; learning needs at least 2")
    if X.shape[0] < 2:
        raise DatasetError(
            f"{name}: only 1 teaching event; learning needs at least 2 (places and "
            "transitions cannot be estimated from a single observation)"
        )
    bad = np.flatnonzero(~np.isfinite(X).all(axis=1))
    if bad.size:
        raise DatasetError(
            f"{name}: teaching event {int(bad[0])} has a non-finite position "
            f"{X[bad[0]].tolist()} ({bad.size} such events); positions must be finite metres"
        )
    return X


def _checked_features(name: str, raw: np.ndarray, E: int) -> np.ndarray:
    """The image features as a float (E, D) array of finite non-negative values, else DatasetError."""
    features = np.asarray(raw, dtype=float)
    if features.ndim != 2 or features.shape[0] != E:
        raise DatasetError(
            f"{name}: image features must be an (E, D) array with one row per teaching "
            f"event (E = {E}), got shape {features.shape}"
        )
    bad = np.flatnonzero(~(np.isfinite(features) & (features >= 0)).all(axis=1))
    if bad.size:
        raise DatasetError(
            f"{name}: image feature row {int(bad[0])} has a negative or non-finite value; features must be non-negative"
        )
    return features


def _checked_trajectory(name: str, raw: np.ndarray) -> np.ndarray:
    """The robot trajectory as a float (T, 2) array of finite positions with T >= 2, else DatasetError."""
    trajectory = np.asarray(raw, dtype=float)
    if trajectory.ndim != 2 or trajectory.shape[1] != 2 or len(trajectory) < 2:
        raise DatasetError(f"{name}: trajectory must be a (T, 2) array with T >= 2, got shape {trajectory.shape}")
    if not np.isfinite(trajectory).all():
        raise DatasetError(f"{name}: trajectory has non-finite positions")
    return trajectory


def scale_features(features: np.ndarray, weight: float | None) -> np.ndarray:
    """Feature rows as the counts f_e of Eq. 15: rows rescaled to sum to ``weight``, or (None) the authors'
    integer counts ``features_to_counts``."""
    if weight is None:
        from spcotmhp.datasets.loader import features_to_counts  # here, not at import (see above)

        return features_to_counts(features).astype(float)
    if not weight > 0:
        raise DatasetError(f"feature_weight must be > 0 or None, got {weight}")
    total = features.sum(axis=1, keepdims=True)
    return np.divide(features * weight, total, out=np.zeros_like(features), where=total > 0)


# ---- teaching events (the online learner) --------------------------------------------------------------------
MAX_UTTERANCE_CHARS = 1000
"""Longest utterance (characters) a teach accepts (the CLI, the HTTP service, the ROS 2 node and its log)."""
MAX_WORDS = 50
"""Most words of one teaching event."""


@dataclass(frozen=True)
class TeachingEvent:
    """One teaching event: a position (map frame, metres), the words of the utterance, optional image features;
    ``named``: the words are a name said for the place (a teach, ``collapsed.py``'s naming events); ``answer``: a
    teach given in reply to the robot's question (``teaching.questions``), learned as the learner's
    ``answer_alone`` / ``answer_weight`` say."""

    x: float
    y: float
    words: tuple[str, ...]
    features: np.ndarray | None = None
    named: bool = False
    answer: bool = False

    @classmethod
    def from_utterance(cls, utterance: str, x: float, y: float, features: np.ndarray | None = None) -> TeachingEvent:
        """An event from a sentence: its words (:func:`spcotmhp.language.text.words`: lower-cased, widths folded,
        punctuation dropped, "This is Alice's room!" -> this, is, alice's, room; Japanese without spaces cut into
        words, "ここは書斎です" -> ここ, は, 書斎, です). Raises TeachingError for an empty or over-long utterance."""
        return cls(float(x), float(y), utterance_words(utterance), features)


def utterance_words(utterance: object) -> tuple[str, ...]:
    """The words of a taught utterance (:meth:`TeachingEvent.from_utterance`), checked against the limits a model
    holds them to: at most ``MAX_UTTERANCE_CHARS`` characters, at least one word, each of at most
    ``model_values.MAX_WORD_CHARS`` (a word becomes one of the model's vocabulary, which refuses longer ones).
    TeachingError naming the limit otherwise; the HTTP service's ``TeachRequest`` checks its field with this too.

    >>> utterance_words("This is Alice's room!")
    ('this', 'is', "alice's", 'room')
    >>> utterance_words("this is " + "x" * 300)
    Traceback (most recent call last):
    ...
    spcotmhp.errors.TeachingError: word 3 of the utterance has 300 characters, more than the 256 a word may have
    """
    if not isinstance(utterance, str):
        raise TeachingError(f"the utterance must be text, got {type(utterance).__name__}")
    if len(utterance) > MAX_UTTERANCE_CHARS:
        raise TeachingError(
            f"the utterance has {len(utterance)} characters, more than the "
            f"{MAX_UTTERANCE_CHARS} accepted; say the place's name, e.g. 'this is the kitchen'"
        )
    words = tuple(text_words(utterance, "ja" if is_japanese(utterance) else "en"))
    if not words:
        raise TeachingError("the utterance is empty (no words); say the place's name, e.g. 'this is the kitchen'")
    check_word_lengths(words, "the utterance")
    return words


def check_word_lengths(words: tuple[str, ...] | list[str], what: str) -> None:
    """TeachingError when a word of ``words`` (of ``what``) is longer than MAX_WORD_CHARS."""
    for j, word in enumerate(words):
        if len(word) > MAX_WORD_CHARS:
            raise TeachingError(
                f"word {j + 1} of {what} has {len(word)} characters, more than the {MAX_WORD_CHARS} a word may have"
            )


def _is_number(value: object) -> TypeGuard[int | float | np.integer | np.floating]:
    """A real number (numpy scalars included), not a bool."""
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


def as_event(item: object) -> TeachingEvent:
    """A TeachingEvent, a mapping {"x", "y", "utterance" or "words"[, "features"]} or a tuple (x, y, utterance or
    words) as a TeachingEvent; TeachingError for anything else."""
    if isinstance(item, TeachingEvent):
        return item
    if isinstance(item, Mapping):
        x, y, said, feats = (
            item.get("x"),
            item.get("y"),
            item.get("utterance", item.get("words")),
            item.get("features"),
        )
    elif isinstance(item, (tuple, list)) and len(item) in (3, 4):
        x, y, said, feats = (*item, None)[:4]
    else:
        raise TeachingError(
            f"a teaching event is (x, y, utterance) or a mapping with x, y and utterance, got {type(item).__name__}"
        )
    if not (_is_number(x) and _is_number(y)):
        raise TeachingError(f"a teaching position must be two numbers (metres), got {x!r}, {y!r}")
    if isinstance(item, Mapping) and item.get("answer", False) not in (True, False):
        raise TeachingError(f"'answer' must be true or false, got {item.get('answer')!r}")
    answer = isinstance(item, Mapping) and item.get("answer", False) is True
    if isinstance(said, str):
        return dataclasses.replace(TeachingEvent.from_utterance(said, float(x), float(y), feats), answer=answer)
    if not isinstance(said, (list, tuple)) or not said or not all(isinstance(w, str) and w for w in said):
        raise TeachingError("a teaching event needs an utterance (text) or a non-empty list of words")
    if len(said) > MAX_WORDS or sum(len(w) for w in said) > MAX_UTTERANCE_CHARS:
        raise TeachingError(f"a teaching event has more than {MAX_WORDS} words or {MAX_UTTERANCE_CHARS} characters")
    check_word_lengths(said, "the teaching event")
    return TeachingEvent(float(x), float(y), tuple(said), feats, answer=answer)
