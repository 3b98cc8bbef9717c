"""Rule 1 of the sentence grammar: longest-match items against a lexicon compiled once per grammar and vocabulary."""

from __future__ import annotations

import pytest

from spcotmhp.planning.grammar import ENGLISH, JAPANESE
from spcotmhp.planning.scan import lexicon, merge_phrases, scan

WORDS = ("entrance", "corridor", "kitchen", "living")


def test_a_lexicon_is_compiled_once_and_read_only():
    first = lexicon(ENGLISH, WORDS)
    assert lexicon(ENGLISH, WORDS) is first and lexicon(JAPANESE, WORDS) is not first
    assert first.places[("kitchen",)] == ("place", "kitchen") and first.grammar[("via",)] == ("marker", "waypoint")
    with pytest.raises(TypeError):
        first.places[("attic",)] = ("place", "attic")  # type: ignore[index]


def test_the_longest_entry_wins_and_adjacent_place_words_are_one_phrase():
    items = merge_phrases(scan("Go to the kitchen, passing through the entrance corridor", ENGLISH, WORDS), ENGLISH)
    kinds = [(it.kind, it.value, it.surface) for it in items]
    assert ("marker", "waypoint", "passing through") in kinds  # not "passing" + "through"
    assert ("place", "entrance", "entrance corridor") in kinds and items[-1].words == ["entrance", "corridor"]
    assert ("other", "", "go") not in kinds  # "go" is a filler, "Go" lower-cased


def test_the_first_before_a_place_is_a_modifier():
    items = scan("go to the first kitchen", ENGLISH, WORDS)
    assert [it.kind for it in items if it.surface == "first"] == ["modifier"]
    assert [it.kind for it in scan("first go to the kitchen", ENGLISH, WORDS) if it.surface == "first"] == ["order"]


def test_a_full_stop_ends_a_clause_and_other_symbols_are_space():
    kinds = [(it.kind, it.surface) for it in scan("Go to the kitchen. First, the living-room!", ENGLISH, WORDS)]
    assert ("connector", ".") in kinds and ("connector", "!") in kinds and ("order", "first") in kinds
    assert ("place", "living") in kinds and ("filler", "room") in kinds  # the hyphen is space


def test_katakana_place_words_are_also_matched_in_hiragana_unless_a_place_is_called_so():
    words = ("キッチン", "トイレ", "風呂", "ドア")
    items = scan("きっちんとといれとどあ", JAPANESE, words)
    assert [(it.kind, it.words) for it in items[:3]] == [
        ("place", ["キッチン"]),
        ("connector", []),
        ("place", ["トイレ"]),
    ]
    assert items[-1].kind == "other"  # two characters (ドア): too short to spell a place by sound alone
    own = scan("きっちん", JAPANESE, ("キッチン", "きっちん"))  # a place called by the hiragana spelling keeps it
    assert [it.words for it in own] == [["きっちん"]]
