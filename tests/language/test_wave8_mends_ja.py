"""What wave 8 (tests/data/blind34, blind35) and the Japanese development corpora misread or refused (issue 34),
read as meant: an apology between two place phrases of the same role corrects (apologies_ja), 違いました, ので、
before a pause, けん, 移る, the さ of direction, sizes and nearest-to in every combination and in kana, the topic
は before a verb of going, ちょっと待って holding on. Each with neighbours that must keep their reading."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.meaning import Reading
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_JA


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
    "text, route",
    [
        ("床が濡れているので、玄関まで行って", ["玄関"]),  # ので、: a reason, its pause a pause
        ("お客様がいらっしゃいますので、玄関まで行っていただけますか。", ["玄関"]),
        ("キッチンで、待ってて", ["キッチン"]),  # で after a place keeps its reading
        ("お風呂沸いたけん風呂場行って", ["風呂"]),  # けん (Kyushu, Chugoku): から, before the place too
        ("居間に移ってください", ["リビング"]),  # 移る: to move to
        ("居間に移っていただけますでしょうか。", ["リビング"]),
    ],
)
def test_japanese_reasons_and_verbs(text, route):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == route


@pytest.mark.parametrize("text", ["けんかしないで玄関行って", "居間に移らないで"])
def test_japanese_neighbours_stay_refused(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_JA, "ja")


@pytest.mark.parametrize(
    "text, route",
    [
        ("お風呂場のほうさ行ってくれるっしょ", ["風呂"]),  # さ (へ) after ほう
        ("食堂さゆっくり行って", ["ダイニング"]),  # an adverb between さ and the verb
    ],
)
def test_the_sa_of_direction(text, route):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == route


@pytest.mark.parametrize(
    "text, size",
    [
        ("ちっちゃいほうの寝室いって", "smallest"),  # every size word with 一番 and ほうの, not a list of pairs
        ("一番せまい寝室いって", "smallest"),
        ("いちばん広いほうの寝室", "largest"),
        ("でっかい方の寝室に行って", "largest"),
    ],
)
def test_japanese_sizes_in_every_combination(text, size):
    assert read(text, PLACE_WORDS_JA, "ja").visit[0].relation.kind == size


@pytest.mark.parametrize(
    "text",
    [
        "ふろに いちばん ちかい しんしつ",  # kana, spaced: the relation, not a stop at the bath
        "おふろに いちばんちかい しんしつ いって",
        "風呂に最寄りの寝室",  # were read as the bath, then the nearest bedroom
        "風呂に近くの寝室",
    ],
)
def test_japanese_nearest_to_a_place(text):
    r = read(text, PLACE_WORDS_JA, "ja")
    assert _route(r) == ["寝室"] and r.visit[0].relation.kind == "closest"


@pytest.mark.parametrize(
    "text, route, speed",
    [("トイレまでダッシュ", ["トイレ"], "fast"), ("そろりそろりと廊下を通って玄関へ", ["廊下", "玄関"], "slow")],
)
def test_japanese_speed_words(text, route, speed):
    r = read(text, PLACE_WORDS_JA, "ja")
    assert _route(r) == route and r.speed == speed


def test_a_stop_then_the_nearest_keeps_two_visits():
    assert _route(read("風呂に行って最寄りの寝室", PLACE_WORDS_JA, "ja")) == ["風呂", "寝室"]


@pytest.mark.parametrize(
    "text, goal, avoid",
    [
        ("すみません、ダイニングは行ってくれますか", "ダイニング", []),  # the topic は with a verb of going: the goal
        ("げんかん は 行けますか？", "玄関", []),
        ("キッチンは行って、リビングは行かないで", "キッチン", ["リビング"]),  # the contrast: one to go to, one not
    ],
)
def test_japanese_topic_before_a_verb_of_going(text, goal, avoid):
    r = read(text, PLACE_WORDS_JA, "ja")
    assert _route(r) == [goal] and [" ".join(a.words) for a in r.avoid] == avoid


@pytest.mark.parametrize(
    "text, route",
    [
        ("ちょっと待って、玄関じゃなくて廊下に行って。", ["廊下"]),
        ("台所へ行って、いやちょっと待って、居間にして", ["リビング"]),
    ],
)
def test_hold_on_before_what_is_meant(text, route):
    assert _route(read(text, PLACE_WORDS_JA, "ja")) == route


def test_hold_on_between_two_places_stays_refused():
    with pytest.raises(InstructionError):
        read("キッチン、ちょっと待って、リビング", PLACE_WORDS_JA, "ja")
