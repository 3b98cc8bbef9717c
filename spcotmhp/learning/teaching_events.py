"""Teaching events: what the online learner takes, one at a time ("this is alice's room" at x, y), and the forms
it accepts them in (``as_event``). Kept apart from the learner (``learning.online``, which re-exports both)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TypeGuard

import numpy as np

from spcotmhp.errors import TeachingError
from spcotmhp.language.text import is_japanese
from spcotmhp.language.text import words as text_words

MAX_UTTERANCE_CHARS = 1000
MAX_WORDS = 50


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
        return cls(float(x), float(y), words, features)


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
    return TeachingEvent(float(x), float(y), tuple(said), feats, answer=answer)
