"""Argument checks of the instruction parsers (spcotmhp/planning/arguments.py), through the parsers."""

from __future__ import annotations

import pytest

from spcotmhp.errors import InvalidSettings, MalformedInstruction
from spcotmhp.planning.instructions import parse_nbest, parse_structured, parse_text

WORDS = ["kitchen", "bath", "corridor"]
NBEST = [("go to the kitchen", 1.0)]


@pytest.mark.parametrize(
    "call, function",
    [
        (lambda: parse_text("go to the kitchen", "kitchen"), "parse_text"),
        (lambda: parse_structured({"goal": ["kitchen"]}, "kitchen"), "parse_structured"),
        (lambda: parse_nbest(NBEST, "kitchen"), "parse_nbest"),
    ],
)
def test_place_words_as_one_string_is_refused(call, function):
    """Audit item 12: a str was read as its letters ("known place words: c, e, h, i, k, n, t")."""
    with pytest.raises(MalformedInstruction) as info:
        call()
    assert str(info.value) == (
        f"{function}: place_words must be a list of words, not one string ('kitchen'); give ['kitchen']"
    )


@pytest.mark.parametrize(
    "obj, message",
    [
        ({"goal": [1]}, "goal must be a non-empty list of words; goal[0] is 1, not a word"),
        ({"goal": ["kitchen", None]}, "goal must be a non-empty list of words; goal[1] is None, not a word"),
        ({"goal": ["bath"], "waypoints": [["corridor", 2.5]]}, "waypoints[0] must be a non-empty list of words; "),
        ({"goal": 5}, "goal must be a non-empty list of words; got 5"),
    ],
)
def test_structured_names_the_element_that_is_not_a_word(obj, message):
    """Audit item 12: {'goal': [1]} said "must be a non-empty list of words, got a list"."""
    with pytest.raises(MalformedInstruction) as info:
        parse_structured(obj, WORDS)
    assert str(info.value).startswith(message)


def test_nbest_unknown_keyword_names_parse_nbest():
    """Audit item 12: max_bogus was passed on and raised a TypeError naming parse_text()."""
    with pytest.raises(TypeError) as info:
        parse_nbest(NBEST, WORDS, max_bogus=3)
    assert str(info.value) == (
        "parse_nbest() got unexpected keyword argument(s) 'max_bogus'; accepted: max_hypotheses, max_chars, "
        "max_waypoints, max_avoided"
    )


@pytest.mark.parametrize("value", [float("nan"), 2.5, -1, True, "3"])
@pytest.mark.parametrize(
    "call, name",
    [
        (lambda v: parse_text("go to the kitchen", WORDS, max_waypoints=v), "max_waypoints"),
        (lambda v: parse_text("go to the kitchen", WORDS, max_chars=v), "max_chars"),
        (lambda v: parse_structured({"goal": ["bath"]}, WORDS, max_avoided=v), "max_avoided"),
        (lambda v: parse_nbest(NBEST, WORDS, max_hypotheses=v), "max_hypotheses"),
        (lambda v: parse_nbest(NBEST, WORDS, max_waypoints=v), "max_waypoints"),
    ],
)
def test_limits_must_be_counts(call, name, value):
    """Audit item 13: max_waypoints=nan raised a bare ValueError from int(nan)."""
    with pytest.raises(InvalidSettings, match=f"{name} must be an integer >= 0 or None \\(the default\\), got "):
        call(value)


def test_good_arguments_still_parse():
    assert parse_text("go to the kitchen", ("kitchen",), max_waypoints=0).goal.label == "kitchen"
    assert parse_nbest(NBEST, WORDS, max_hypotheses=1, max_chars=100).goal.label == "kitchen"
