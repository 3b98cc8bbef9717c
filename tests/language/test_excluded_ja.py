"""The place excluded after the place asked for, and the place asked about before そこ (issue 34, wave 4:
spcotmhp/language/excluded_ja.py). Cases it reads and cases that must stay refused."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_JA

JA = PLACE_WORDS_JA


def _said(place) -> str:
    kind = place.relation.kind if place.relation is not None else ""
    return place.words[0] + (f"#{place.number}" if place.number else "") + (f"{{{kind}}}" if kind else "")


@pytest.mark.parametrize(
    "text, not_goal",
    [
        ("寝室に行ってほしいけど、風呂に一番近いのはやめて", "寝室{closest}"),
        ("寝室行って。お風呂に一番近いところは除いて", "寝室{closest}"),
        ("寝室お願い、ただしトイレに一番近いのは除いて", "寝室{closest}"),
        ("寝室どれか、でもトイレに一番近いのはやめて", "寝室{closest}"),
        ("寝室に行って、でも一番狭いのは嫌", "寝室{smallest}"),
        ("寝室に行って、でも3番はやめて", "寝室#3"),
        ("寝室に行って、でも2番以外で", "寝室#2"),
        ("1番以外の寝室に行ってくれ", "寝室#1"),
    ],
)
def test_the_one_turned_down_is_not_the_goal(text, not_goal):
    r = read(text, JA, "ja")
    assert [p.words[0] for p in r.visit] == ["寝室"]
    assert [_said(p) for p in r.not_goal] == [not_goal]


@pytest.mark.parametrize("text", ["風呂に一番近いのはやめて", "一番狭いのは嫌", "3番はやめて"])
def test_with_no_place_said_before_it_stays_refused(text):
    with pytest.raises(InstructionError):
        read(text, JA, "ja")


@pytest.mark.parametrize(
    "text, kind",
    [
        ("ダイニングに一番近い寝室ってどれ？そこ行って", "closest"),
        ("いちばん 大きい 寝室 どれ？そこ 行って", "largest"),
        ("あのー玄関からいちばん遠い寝室ってどれだっけまあそこに行って", "farthest"),
    ],
)
def test_which_is_it_go_there(text, kind):
    r = read(text, JA, "ja")
    assert r.visit[-1].relation is not None and r.visit[-1].relation.kind == kind


def test_a_question_alone_stays_refused():
    with pytest.raises(InstructionError, match="ってどれ"):
        read("ダイニングに一番近い寝室ってどれ", JA, "ja")


@pytest.mark.parametrize(
    "text, goal, not_goal",
    [
        ("寝室#3のほうね、#2じゃなくて", "寝室#3", ["寝室#2"]),
        ("寝室の1番じゃなくて2番 2番に行って", "寝室#2", ["寝室#1"]),
    ],
)
def test_a_number_beside_janakute_is_another_instance(text, goal, not_goal):
    r = read(text, JA, "ja")
    assert _said(r.visit[-1]) == goal and [_said(p) for p in r.not_goal] == not_goal


def test_a_number_beside_janakute_with_no_numbered_place_stays_refused():
    with pytest.raises(InstructionError):
        read("キッチンじゃなくて2番に行って", JA, "ja")


def test_any_other_than_a_number():
    r = read("寝室に行って。1番以外ならどれでも", JA, "ja")
    assert [_said(p) for p in r.not_goal] == ["寝室#1"]
