"""What wave 9 (tests/data/blind36, blind37) and the English development corpora misread or refused (issue 34),
read as meant or refused by name: "go and come" (Indian English: there and back) refused as "come back" is, never
read as the going alone; terms of address (beta, yaar, bhai) and the hesitations "ehm" and "arre" passed over.
Each with neighbours that must keep their reading."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InstructionError
from spcotmhp.language.meaning import Reading
from spcotmhp.language.reading import read
from tests.helpers.vocabulary import PLACE_WORDS_EN


def _route(r: Reading) -> list[str]:
    return [" ".join(p.words) for p in r.visit]


@pytest.mark.parametrize(
    "text, said",
    [
        ("go to the bedroom and come", "and come"),
        ("please go to the bath and come.", "and come"),
        ("go to the hall then come", "then come"),
        ("go via the corridor to the toilet and then come", "and then come"),
    ],
)
def test_go_and_come_is_refused_as_coming_back(text, said):
    with pytest.raises(InstructionError) as err:
        read(text, PLACE_WORDS_EN, "en")
    assert f"'{said}' asks to come back" in str(err.value)


@pytest.mark.parametrize(
    "text, route",
    [
        ("go to the kitchen and come to the bedroom", ["kitchen", "bedroom"]),  # a place after it: a route
        ("come to the kitchen", ["kitchen"]),
        ("go to the kitchen and come back to the hall", ["kitchen", "hall"]),
    ],
)
def test_come_with_a_place_keeps_its_reading(text, route):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == route


def test_go_and_come_with_no_place_is_refused_as_before():
    with pytest.raises(InstructionError, match="names no place"):
        read("go and come", PLACE_WORDS_EN, "en")


@pytest.mark.parametrize(
    "text",
    [
        "go to the toilet, beta",
        "beta go to the toilet",
        "yaar go to the toilet",
        "go to the toilet yaar",
        "bhai, go to the toilet please",
        "arre go to the toilet",
        "go to the ehm toilet",
    ],
)
def test_address_and_hesitations_are_passed_over(text):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == ["toilet"]


@pytest.mark.parametrize("text", ["go to the bedroom, the biggest bedroom", "the bedroom, the largest bedroom please"])
def test_a_place_said_bare_then_narrowed_is_one_place(text):
    r = read(text, PLACE_WORDS_EN, "en")
    assert len(r.visit) == 1 and r.visit[0].relation is not None and r.visit[0].relation.kind == "largest"


def test_another_place_before_a_narrowed_one_stays_on_the_route():
    r = read("go to the kitchen, the biggest bedroom", PLACE_WORDS_EN, "en")
    assert _route(r) == ["kitchen", "bedroom"]


@pytest.mark.parametrize(
    "text, route",
    [
        # issue 34's own case: read before as kitchen then toilet (goal and waypoint swapped, silently)
        ("toilet next, and pass through the kitchen on the way", ["kitchen", "toilet"]),
        ("go to the hall, then the toilet, and pass through the kitchen on the way", ["hall", "kitchen", "toilet"]),
        ("go to the bath and go through the corridor on the way", ["corridor", "bath"]),
        # a place passed in the clause of the goal is what is on the way; the goal stays the goal
        ("go to the kitchen pass through the dining room on the way", ["dining", "kitchen"]),
        ("go to the kitchen pass through the hall on the way and go fast", ["hall", "kitchen"]),
        # the place to go to "on the way" is passed on the way (as before)
        ("on the way go to the kitchen, then go to the toilet", ["kitchen", "toilet"]),
    ],
)
def test_what_is_passed_on_the_way_is_passed_before_the_goal(text, route):
    r = read(text, PLACE_WORDS_EN, "en")
    assert _route(r) == route


@pytest.mark.parametrize(
    "text",
    [
        "come on, go to the toilet",
        "c'mon go to the toilet",
        "cmon go to the toilet",
        "righty-o, go to the toilet",
        "righto go to the toilet",
        "come on into the toilet",  # "come on" urging before a way of going: the going stays
        "come on over to the toilet",
    ],
)
def test_urging_is_passed_over(text):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == ["toilet"]


@pytest.mark.parametrize(
    "text, route",
    [
        ("go to the lumber room", ["storeroom"]),
        ("take me to the stockroom", ["storeroom"]),
        ("go to the stock room via the hall", ["hall", "storeroom"]),
        ("go to the main door", ["entrance"]),
        ("is it too much to ask for you to go to the toilet", ["toilet"]),
        ("could I ask you to go to the toilet?", ["toilet"]),
        ("may I ask you to go to the toilet", ["toilet"]),
    ],
)
def test_more_names_and_request_frames(text, route):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == route


@pytest.mark.parametrize(
    "text", ["ey up, go to t'toilet", "eh up love, go through to t'toilet would you", "go t'toilet"]
)
def test_northern_english(text):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == ["toilet"]


@pytest.mark.parametrize("text", ["go to the toilet only", "Please go to the toilet only.", "go to the toilet itself"])
def test_emphasis_after_the_goal_is_left_out(text):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == ["toilet"]


@pytest.mark.parametrize("text", ["go to the bath via the kitchen only", "go to the bath only through the kitchen"])
def test_only_constraining_the_route_is_refused(text):
    with pytest.raises(InstructionError, match="'only'"):
        read(text, PLACE_WORDS_EN, "en")


@pytest.mark.parametrize(
    "text, route",
    [
        ("Where's the toilet? Go there.", ["toilet"]),
        ("where is the toilet? go there please", ["toilet"]),
        ("do you know where the toilet is go there", ["toilet"]),
        ("which bedroom is closest to the kitchen? go there", ["bedroom"]),
    ],
)
def test_a_question_answered_by_go_there(text, route):
    r = read(text, PLACE_WORDS_EN, "en")
    assert _route(r) == route


@pytest.mark.parametrize("text", ["where's the toilet", "which bedroom is closest to the kitchen?"])
def test_a_question_alone_is_still_refused(text):
    with pytest.raises(InstructionError):
        read(text, PLACE_WORDS_EN, "en")


def test_the_question_keeps_its_relation():
    r = read("which bedroom is closest to the kitchen? go there", PLACE_WORDS_EN, "en")
    assert r.visit[0].relation is not None and r.visit[0].relation.kind == "closest"


@pytest.mark.parametrize(
    "text",
    [
        "Amma says go to the toilet.",  # a family word of South Asian English, as mum says
        "go to the toilet so nani can see you",
        "lowkey need you in the toilet",  # texting's hedges
        "can u head to the toilet fr",
    ],
)
def test_family_words_and_hedges(text):
    assert _route(read(text, PLACE_WORDS_EN, "en")) == ["toilet"]
