"""A battery of words that say where a place lies, said between two places (issue 34, safety): each sentence is
read with one place to go to, picked by the relation, or refused; never silently as two visits ("the bedroom off
the kitchen" and 風呂に最寄りの寝室 were read as a stop and a goal before session 9). Words of route or order
(via, through, past, after, to, and) are not in the battery: between two places they do say two visits."""

from __future__ import annotations

import itertools

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_EN, PLACE_WORDS_JA

LOCATING_EN = [
    "nearest", "nearest to", "closest to", "near", "near to", "by", "right by", "next to", "beside", "close to",
    "furthest from", "farthest from", "far from", "opposite", "across from", "behind", "beyond", "off", "just off",
    "facing", "towards", "toward", "nearer", "handy to", "adjacent to", "in front of", "at the end of",
]  # fmt: skip
FRAMES_EN = ["go to the bedroom {r} the {p}", "the bedroom {r} the {p} please", "bedroom {r} {p}"]
LOCATING_JA = [
    "に一番近い", "に近い", "に最寄りの", "の最寄りの", "に近くの", "の近くの", "のそばの", "の横の", "の隣の",
    "から一番遠い", "から遠い", "に一番ちかい", "にいちばんちかい", "のちかくの", "にいちばん近い", "に近いほうの",
    "から近い", "の向かいの",
]  # fmt: skip
FRAMES_JA = ["{p}{r}寝室", "{p}{r}寝室に行って", "{p}{r}寝室まで", "{p}{r}寝室へお願い"]


def _one_place_or_refused(text: str, words, lang: str) -> None:
    try:
        r = read(text, words, lang)
    except InstructionError:
        return
    assert len(r.visit) == 1 and r.visit[0].words == (("bedroom",) if lang == "en" else ("寝室",)), (text, r.visit)


@pytest.mark.parametrize(
    "rel, place, frame", list(itertools.product(LOCATING_EN, ["kitchen", "bath", "entrance"], FRAMES_EN))
)
def test_english_locating_words_between_places(rel, place, frame):
    _one_place_or_refused(frame.format(r=rel, p=place), PLACE_WORDS_EN, "en")


@pytest.mark.parametrize(
    "rel, place, frame", list(itertools.product(LOCATING_JA, ["風呂", "キッチン", "玄関"], FRAMES_JA))
)
def test_japanese_locating_words_between_places(rel, place, frame):
    _one_place_or_refused(frame.format(r=rel, p=place), PLACE_WORDS_JA, "ja")
