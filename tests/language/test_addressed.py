"""spcotmhp/language/addressed.py: talk said to someone else before the robot is called by name."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_EN, PLACE_WORDS_JA


@pytest.mark.parametrize(
    "text, lang, goal, speed",
    [
        ("Kids, watch this. Robot, go to the living room!", "en", "living", None),
        ("Jake, stop pushing it! Sorry. Robot, please go to the kitchen.", "en", "kitchen", None),
        ("Emma, no, the robot is not a horse. Robot, go to the hall, please.", "en", "hall", None),
        ("あー天気予報か ロボット寝室行ってていいよ", "ja", "寝室", None),
        ("テレビ中ごめん ロボット 台所寄ってから寝室行って 急ぎで", "ja", "寝室", "fast"),
        ("ちょっとCMのうちにさ、ロボットは風呂場行っといて", "ja", "風呂", None),
        ("ロボットさんは リビングへ 行ってください", "ja", "リビング", None),  # the topic's は after the name
    ],
)
def test_talk_before_the_robots_name_is_said_to_someone_else(text, lang, goal, speed):
    r = read(text, PLACE_WORDS_EN if lang == "en" else PLACE_WORDS_JA, lang)
    assert r.visit[-1].words[0] == goal and r.speed == speed


@pytest.mark.parametrize(
    "text, lang, speed",
    [
        ("Slowly. Robot, go to the kitchen.", "en", "slow"),  # a speed before the name stays the robot's
        ("ゆっくりね ロボット キッチン行って", "ja", "slow"),
    ],
)
def test_a_class_before_the_name_is_kept(text, lang, speed):
    r = read(text, PLACE_WORDS_EN if lang == "en" else PLACE_WORDS_JA, lang)
    assert r.speed == speed


@pytest.mark.parametrize(
    "text, lang",
    [
        ("Avoid the hall. Robot, go to the kitchen.", "en"),  # a place before the name: never passed over
        ("The robot is blocking the door, go to the kitchen", "en"),  # the robot as a subject, not addressed
        ("ママ見てロボットが動くよ ほらキッチンいって", "ja"),  # ロボットが: a subject
    ],
)
def test_a_place_before_the_name_or_a_name_as_subject_is_no_address(text, lang):
    words = PLACE_WORDS_EN if lang == "en" else PLACE_WORDS_JA
    try:
        r = read(text, words, lang)
    except InstructionError:
        return
    assert not any(h.startswith(("avoid", "the robot", "ママ")) for h in r.heard), r.heard
    if text.startswith("Avoid"):
        assert [p.words[0] for p in r.avoid] == ["hall"]
