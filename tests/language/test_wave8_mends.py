"""What wave 8 (tests/data/blind32-35) misread at first sight (issue 34), read as meant: an apology after a place's
marker corrects it (lexicon_ja), the polite past 違いました corrects (ja.json), places said again first after a
correction start a restatement (walk.Walk._fresh, walk_ja), a name of several words said twice is one (lexicon).
Each with neighbours that must keep their reading."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.meaning import Reading
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_EN, PLACE_WORDS_JA

SYNTHETIC = ["alice's", "bob's", "corridor", "east", "kitchen", "room", "south"]


def _route(r: Reading) -> list[str]:
    return [" ".join(p.words) for p in r.visit]


@pytest.mark.parametrize(
    "text, route",
    [
        ("お風呂に えーとごめん洗面所に行って", ["洗面所"]),  # the apology after お風呂に corrects the phrase
        ("お風呂にごめん洗面所に行って", ["洗面所"]),
        ("キッチン通ってごめん廊下通って寝室", ["廊下", "寝室"]),
        ("キッチンごめんリビング", ["リビング"]),  # after the place itself, as before
        ("ごめん、キッチン行って", ["キッチン"]),  # opening the sentence: an apology, no correction
        ("お風呂に ごめん 行って", ["風呂"]),  # no place after it: passed over
        ("お風呂にごめん洗面所行って", ["洗面所"]),  # the goal's marker said as 行って
        ("リビングを避けてすみません寝室へ", ["寝室"]),  # another part after it: a filler (the avoidance stays)
        ("玄関までお願いします、あら違いました、廊下までお願いします", ["廊下"]),
    ],
)
def test_japanese_corrections(text, route):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == route


@pytest.mark.parametrize(
    "text, lang, route",
    [
        ("廊下通ってトイレ、じゃなくて廊下通って風呂", "ja", ["廊下", "風呂"]),  # the goal corrected
        ("廊下通ってトイレ、いや、廊下通って風呂", "ja", ["廊下", "風呂"]),
        ("廊下通ってトイレ、いや、風呂", "ja", ["廊下", "風呂"]),  # a bare place: the corrected goal, as before
        ("go to the kitchen via the hall, no, via the hall to the bath", "en", ["hall", "bath"]),
        ("go via the hall to the kitchen, sorry, via the hall to the bath", "en", ["hall", "bath"]),
    ],
)
def test_a_restatement_after_a_correction_corrects_what_differs(text, lang, route):
    words = PLACE_WORDS_JA if lang == "ja" else PLACE_WORDS_EN
    assert _route(read(text, words, lang)) == route


@pytest.mark.parametrize("text", ["go to the kitchen, no, the kitchen", "キッチン、いや、キッチン"])
def test_a_correction_to_the_same_place_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_JA if text[0] > "~" else PLACE_WORDS_EN, "ja" if text[0] > "~" else "en")


@pytest.mark.parametrize(
    "text, route",
    [
        ("alice's room alice's room go to alice's room", ["alice's room"]),
        ("go to the east corridor east corridor", ["east corridor"]),
        ("go to the kitchen kitchen", ["kitchen"]),
    ],
)
def test_a_name_said_twice_is_one(text, route):
    assert _route(read(text, SYNTHETIC, "en")) == route


def test_two_names_side_by_side_stay_two_names():
    # not one said twice: kept whole, for the planner to refuse as no place's name
    assert _route(read("go to the south corridor east corridor", SYNTHETIC, "en")) == ["south corridor east corridor"]
