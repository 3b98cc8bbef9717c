"""Floor phrases (spcotmhp/language/floors.py): read into the floor of the place they go with, refused where no
place takes them or where they could go with two places, and refused by a one-floor planner rather than dropped."""

from __future__ import annotations

import contextlib

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spcotmhp.errors import InstructionError, UnknownPlaceWord, UnsupportedPhrase
from spcotmhp.language.floors import MAX_FLOOR_INDEX, floor_en, floor_ja
from spcotmhp.language.reading import read
from spcotmhp.planning.instructions import parse_nbest, parse_text
from spcotmhp.planning.vocabulary import one_floor

EN = ["bedroom", "kitchen", "bath", "corridor", "living room"]
JA = ["寝室", "台所", "風呂", "廊下", "地下室"]


def said(text: str, lang: str = "en") -> list[tuple[str, object]]:
    r = read(text, EN if lang == "en" else JA, lang)
    return [(p.label, p.floor) for p in r.visit]


@pytest.mark.parametrize(
    ("text", "visit"),
    [
        ("go to the bedroom on the second floor", [("bedroom", 2)]),
        ("go to the bedroom on the 2nd floor", [("bedroom", 2)]),
        ("go to the second-floor bath", [("bath", 2)]),
        ("take me to the kitchen on floor 3", [("kitchen", 3)]),
        ("go to the kitchen on level two", [("kitchen", 2)]),
        ("go to the upstairs bedroom", [("bedroom", "upstairs")]),
        ("go to the bedroom upstairs", [("bedroom", "upstairs")]),
        ("go upstairs to the bedroom", [("bedroom", "upstairs")]),
        ("head downstairs into the kitchen", [("kitchen", "downstairs")]),
        ("go to the bedroom one floor up", [("bedroom", "upstairs")]),
        ("go to the kitchen on the floor below", [("kitchen", "downstairs")]),
        ("go to the bath on the ground floor", [("bath", "ground")]),
        (
            "go via the kitchen downstairs, then to the bedroom on the top floor",
            [("kitchen", "downstairs"), ("bedroom", "top")],
        ),
        ("go to the bedroom", [("bedroom", None)]),
    ],
)
def test_english_floor_phrases_go_with_their_place(text, visit):
    assert said(text) == visit


@pytest.mark.parametrize(
    ("text", "visit"),
    [
        ("2階の寝室に行って", [("寝室", 2)]),
        ("２階の寝室へ", [("寝室", 2)]),
        ("二階の寝室へ行って", [("寝室", 2)]),
        ("十二階の寝室へ", [("寝室", 12)]),
        ("3Fの風呂へ", [("風呂", 3)]),
        ("上の階の寝室へ", [("寝室", "upstairs")]),
        ("下の階の台所へ", [("台所", "downstairs")]),
        ("地下の台所へ", [("台所", "basement")]),
        ("地下室へ", [("地下室", None)]),  # a place word wins over the floor phrase inside it
        ("廊下を通って2階の寝室へ", [("廊下", None), ("寝室", 2)]),
    ],
)
def test_japanese_floor_phrases_go_with_their_place(text, visit):
    assert said(text, "ja") == visit


def test_floor_and_relation_compose():
    r = read("go to the bedroom on the second floor closest to the bath", EN, "en")
    assert r.visit[0].floor == 2 and r.visit[0].relation is not None and r.visit[0].relation.kind == "closest"
    assert r.visit[0].describe() == "bedroom (on floor 2, closest to the bath)"
    r = read("風呂に一番近い2階の寝室へ", JA, "ja")
    assert r.visit[0].floor == 2 and r.visit[0].relation is not None


def test_avoided_places_keep_their_floor():
    r = read("go to the kitchen, avoiding the bath upstairs", EN, "en")
    assert [(p.label, p.floor) for p in r.avoid] == [("bath", "upstairs")]


@pytest.mark.parametrize(
    ("text", "lang", "named"),
    [
        ("go to the bedroom closest to the bath upstairs", "en", "upstairs"),  # the bedroom's floor or the bath's?
        ("go via the kitchen upstairs to the bedroom", "en", "upstairs to"),  # the kitchen's floor or the bedroom's?
        ("go upstairs to the bedroom on the first floor", "en", "two floors"),
        ("2階の風呂に一番近い寝室へ", "ja", "2階の"),  # a relation's place has no floor
        ("寝室へ2階", "ja", "2階"),
    ],
)
def test_a_floor_no_place_takes_alone_is_refused_by_name(text, lang, named):
    with pytest.raises(InstructionError, match=named):
        read(text, EN if lang == "en" else JA, lang)


@pytest.mark.parametrize("text", ["go upstairs", "2階へ行って"])
def test_a_floor_alone_is_no_place(text):
    with pytest.raises(UnknownPlaceWord):
        read(text, EN if text.isascii() else JA, "en" if text.isascii() else "ja")


@pytest.mark.parametrize(("text", "named"), [("go upstairs to the bedroom", "upstairs"), ("2階の寝室へ", "2階")])
def test_a_one_floor_planner_refuses_a_floor_rather_than_dropping_it(text, named):
    ins = parse_text(text, EN if text.isascii() else JA)
    with pytest.raises(UnsupportedPhrase, match=f"'{named}.*one floor"):
        one_floor(ins)
    assert one_floor(parse_text("go to the bedroom", EN)).goal.floor is None


def test_nbest_hypotheses_merge_only_with_the_same_floor():
    ins = parse_nbest([("go to the bedroom upstairs", 0.6), ("go to the bedroom", 0.4)], EN)
    assert ins.goal.floor == "upstairs"  # the heavier shape wins; a floorless hypothesis is not merged into it


@given(st.integers(min_value=0, max_value=MAX_FLOOR_INDEX))
def test_floor_numbers_round_trip(n):
    assert floor_en(["on", "floor", str(n)], 0) == (n, 3)
    assert floor_ja(f"{n}階の") == (n, len(str(n)) + 2)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.text(max_size=40)
    | st.lists(
        st.sampled_from(
            [
                "on",
                "the",
                "second",
                "floor",
                "upstairs",
                "to",
                "bedroom",
                "2",
                "nd",
                "階",
                "の",
                "寝室",
                "上",
                "地下",
                "level",
                "one",
                "up",
            ]
        ),
        max_size=12,
    ).map(" ".join)
)
def test_any_text_reads_or_is_refused(text):
    for lang, words in (("en", EN), ("ja", JA)):
        with contextlib.suppress(InstructionError):
            parse_text(text, words, lang)
