"""What wave 9 (tests/data/blind38, blind39) and the Japanese development corpora misread or refused (issue 34),
read as meant: 名古屋弁 (〜てちょうでゃあ, 〜てちょうよ, 行きゃあ, だがや / だで / だて) and 関西弁 (や, やで, やねん,
やけど, やから, ちゃう, ほんま, ええ, ねん, あんな, 〜とき) written in the standard forms before the grammar reads
them (ja.json's dialect table). Each with neighbours that must keep their reading: や listing two places, ええと the
hesitation."""

from __future__ import annotations

import pytest

from spcotmhp.language.meaning import Reading
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_JA


def _route(r: Reading) -> list[str]:
    return [" ".join(p.words) for p in r.visit]


def _not_goal(r: Reading) -> list[str]:
    return [" ".join(p.words) for p in r.not_goal]


@pytest.mark.parametrize(
    "text, route",
    [
        ("寝室まで行ってちょうでゃあ", ["寝室"]),
        ("トイレ行ってちょうよ", ["トイレ"]),
        ("廊下通って玄関まで行ってちょう、頼むわ", ["廊下", "玄関"]),
        ("寝室行きゃあ", ["寝室"]),
        ("トイレに入りゃあて", ["トイレ"]),
        ("玄関だがや、玄関行ってちょう", ["玄関"]),
        ("寝室だて、寝室", ["寝室"]),
    ],
)
def test_nagoya(text, route):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == route


@pytest.mark.parametrize(
    "text, route, not_goal",
    [
        ("トイレやで トイレ", ["トイレ"], []),
        ("玄関や、玄関行って", ["玄関"], []),
        ("悪いけど寝室やねん、寝室行って", ["寝室"], []),
        ("ごめんやけど廊下行ってくれへん", ["廊下"], []),
        ("寝室ちゃうでトイレやで", ["トイレ"], ["寝室"]),
        ("ほんまに玄関行ってや", ["玄関"], []),
        ("どこの寝室でもええから行って", ["寝室"], []),
        ("あんな、トイレ行っといてほしいねん", ["トイレ"], []),
        ("玄関行っとき", ["玄関"], []),
    ],
)
def test_kansai(text, route, not_goal):
    r = read(text, PLACE_WORDS_JA, "ja")
    assert _route(r) == route and _not_goal(r) == not_goal


def test_ya_between_two_places_still_lists_them():
    r = read("トイレや寝室は通らないで玄関へ", PLACE_WORDS_JA, "ja")
    assert _route(r) == ["玄関"] and sorted(" ".join(p.words) for p in r.avoid) == ["トイレ", "寝室"]


def test_eeto_stays_a_hesitation():
    assert _route(read("ええと、玄関行って", PLACE_WORDS_JA, "ja")) == ["玄関"]


@pytest.mark.parametrize(
    "text, route",
    [
        ("リビング行って ごめん玄関", ["玄関"]),  # after a goal's marker, a place ending the sentence is the goal again
        ("リビング行って あっごめん玄関やった", ["玄関"]),  # や, った after it: no part of an instruction
        ("トイレ行ってすみません洗面所。", ["洗面所"]),
    ],
)
def test_an_apology_after_a_goal_corrects_a_place_ending_the_sentence(text, route):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == route


def test_an_apology_before_another_part_stays_a_filler():
    r = read("リビングを避けてすみません寝室", PLACE_WORDS_JA, "ja")
    assert _route(r) == ["寝室"] and [" ".join(p.words) for p in r.avoid] == ["リビング"]


@pytest.mark.parametrize("text", ["寝室、一番広い寝室に行って", "寝室 寝室や 一番広い寝室や", "寝室 一番広い寝室へ"])
def test_a_place_said_bare_then_narrowed_is_one_place(text):
    r = read(text, PLACE_WORDS_JA, "ja")
    assert len(r.visit) == 1 and r.visit[0].relation is not None and r.visit[0].relation.kind == "largest"


@pytest.mark.parametrize(
    "text, route",
    [
        ("寝室に移動していただいてもよろしいですか", ["寝室"]),  # よろしい is not the filler よろ (よろしく) and しい
        ("トイレまでお願いしてもよろしいでしょうか", ["トイレ"]),
        ("廊下通って玄関行ってもよろしいですか", ["廊下", "玄関"]),
        ("寝室行ってくれたらいいな", ["寝室"]),  # a wish that is a request, not a condition
        ("トイレ行ってくれたら助かる", ["トイレ"]),
        ("玄関行ってくれたらええねん", ["玄関"]),
        ("もしもし 寝室行って", ["寝室"]),  # the telephone's hello, not the もし of a condition
    ],
)
def test_polite_requests_and_hello(text, route):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == route


def test_a_condition_is_still_refused():
    from spcotmhp.errors import InstructionError

    with pytest.raises(InstructionError, match="condition"):
        read("もし寝室が空いてたら行って", PLACE_WORDS_JA, "ja")


@pytest.mark.parametrize("text", ["寝室に。どれでも構いません", "寝室へ、どれでもかまわない", "とりま寝室"])
def test_any_one_will_do_and_for_now(text):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == ["寝室"]


@pytest.mark.parametrize("text", ["寝室だったらどこでもいい", "寝室やったらどれでもええわ", "寝室行っとこか"])
def test_any_of_a_kind_and_lets(text):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == ["寝室"]


def test_a_condition_with_da_ttara_is_still_refused():
    from spcotmhp.errors import InstructionError

    with pytest.raises(InstructionError, match="condition"):
        read("寝室だったら行って", PLACE_WORDS_JA, "ja")
