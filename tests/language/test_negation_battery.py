"""A battery of words that keep the robot out of a place or take it back, said with another place to go to (issue
34, safety): the place negated is never a place to visit; the sentence is read with the other place as the goal, or
refused. ("go to the bath and forget the kitchen" was read as: go to the kitchen, before session 9.) "no" and
"never mind" before a place are corrections (writers mean "go to the kitchen nvm the lounge" so): not here."""

from __future__ import annotations

import itertools

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_EN, PLACE_WORDS_JA

NEGATIONS_EN = [
    "don't go through", "do not go through", "never go through", "avoid", "stay out of", "keep out of", "not through",
    "without going through", "don't pass", "don't enter", "dont go in", "don't go into", "no going through",
    "steer clear of", "not via", "not the", "skip", "bypass", "don't use", "don't cut through", "don't go near",
    "keep away from", "don't stop in", "not into", "but not", "except", "other than", "apart from", "anything but",
    "never", "forget", "forget about", "rather than", "instead of", "not",
]  # fmt: skip
FRAMES_EN = [
    "go to the bath and {n} the kitchen", "{n} the kitchen, go to the bath", "go to the bath, {n} the kitchen",
    "go to the bath {n} the kitchen", "{n} the kitchen and go to the bath",
]  # fmt: skip
NEGATIONS_JA = [
    "を通らないで", "は通らないで", "に入らないで", "を避けて", "には行かないで", "以外", "じゃなくて",
    "は通らずに", "を通らずに", "抜きで", "を通るな", "に寄らないで", "はやめて", "に近づかないで", "は避けて",
    "を経由しないで", "を使わないで", "通らんで", "以外で", "じゃない",
]  # fmt: skip
FRAMES_JA = ["キッチン{n}風呂に行って", "風呂に行って、キッチン{n}", "キッチン{n}、風呂"]


def _not_visited(text: str, words, lang: str, negated: str) -> None:
    try:
        r = read(text, words, lang)
    except InstructionError:
        return
    assert negated not in [p.words[0] for p in r.visit], (text, r.visit)


@pytest.mark.parametrize("neg, frame", list(itertools.product(NEGATIONS_EN, FRAMES_EN)))
def test_english_negated_place_is_never_visited(neg, frame):
    _not_visited(frame.format(n=neg), PLACE_WORDS_EN, "en", "kitchen")


@pytest.mark.parametrize("neg, frame", list(itertools.product(NEGATIONS_JA, FRAMES_JA)))
def test_japanese_negated_place_is_never_visited(neg, frame):
    _not_visited(frame.format(n=neg), PLACE_WORDS_JA, "ja", "キッチン")
