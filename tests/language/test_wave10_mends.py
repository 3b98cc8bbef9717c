"""What wave 10 (tests/data/blind40, blind42) and the development corpora refused or misread (issue 34), read as
meant: a posture verb before "in" / "at" a place says where the robot ends up ("go stand at the front door"); Scots
spellings read as the words they spell (ye, wi, dinnae, the noo); a text's kisses closing it ("x", "xx"); いや待って
as one correction ("no, wait"), never a wait; Philippine English room names (CR, comfort room, sala); 東北 さ (へ) and
〜てけさい / 〜てけらいん / 〜てけね, 北海道 なまら. Each with neighbours that must keep their reading or refusal."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.lexicon import english_units
from spcotmhp.language.meaning import Reading
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_EN, PLACE_WORDS_JA


def _route(r: Reading) -> list[str]:
    return [" ".join(p.words) for p in r.visit]


@pytest.mark.parametrize(
    "text, route",
    [
        ("go stand at the entrance", ["entrance"]),
        ("go and stand at the entrance", ["entrance"]),
        ("go and sit yourself down in the living room", ["living"]),
        ("park yourself at the entrance", ["entrance"]),
        ("sit in the kitchen", ["kitchen"]),
        ("go through the corridor and stand in the hall", ["corridor", "hall"]),
    ],
)
def test_a_posture_before_a_place_is_where_the_robot_ends(text, route):
    r = read(text, PLACE_WORDS_EN, "en")
    assert _route(r) == route
    assert r.waits == ()  # standing there is ending there, not a wait of its own


@pytest.mark.parametrize("text", ["stand up", "sit down", "go and stand", "stand next to me"])
def test_a_posture_without_a_place_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_EN, "en")


def test_scots_spellings_are_read_as_the_words_they_spell():
    assert english_units("dinnae go wi ye the noo") == ["don't", "go", "with", "you", "the", "now"]
    r = read("go tae the living room but dinnae go in the kitchen", PLACE_WORDS_EN, "en")
    assert _route(r) == ["living"] and [" ".join(p.words) for p in r.avoid] == ["kitchen"]
    assert _route(read("can ye go to the dining room the noo", PLACE_WORDS_EN, "en")) == ["dining"]


@pytest.mark.parametrize("text", ["go to the kitchen x", "go to the kitchen xx", "can u go 2 the kitchen x"])
def test_a_texts_kisses_closing_it_are_passed_over(text):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == ["kitchen"]


def test_iya_matte_is_a_correction_not_a_wait():
    r = read("ゆっくりトイレいって、いやまって急ぎで", PLACE_WORDS_JA, "ja")
    assert _route(r) == ["トイレ"] and r.speed == "fast" and r.waits == ()
    assert _route(read("キッチン、いや待って、リビング", PLACE_WORDS_JA, "ja")) == ["リビング"]
    assert read("トイレで待って", PLACE_WORDS_JA, "ja").waits  # a wait said as one stays a wait


@pytest.mark.parametrize(
    "text, route",
    [
        ("Robot pls go to the CR", ["toilet"]),
        ("go to the comfort room please", ["toilet"]),
        ("pls go to the sala", ["living"]),
    ],
)
def test_philippine_english_names_of_rooms(text, route):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == route


@pytest.mark.parametrize(
    "text, route",
    [
        ("物置きさ行ってけさいん", ["物置き"]),  # 東北 さ (へ), 仙台 〜てけさいん (ください)
        ("洗面所さ行ってけらいね", ["洗面所"]),
        ("台所さ行ってけねすか", ["キッチン"]),
        ("物置きさ寄って、したっけ玄関行ってくれや", ["物置き", "玄関"]),
    ],
)
def test_tohoku_endings_and_the_direction_sa(text, route):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == route


def test_namara_says_only_how_much():
    assert read("なまら急いで玄関行って！", PLACE_WORDS_JA, "ja").speed == "fast"
    assert read("なまらゆっくり玄関行って", PLACE_WORDS_JA, "ja").speed == "slow"
