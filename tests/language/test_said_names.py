"""Names as people say them (issue 35, item 2; :mod:`spcotmhp.language.said_names`): what a teaching utterance
teaches with its numbers, the one order kept per name, labels in taught order, and the instruction lexicon matching
a taught name holding a number whole in its variants while numbers elsewhere keep naming instances."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.errors import NotANaming
from spcotmhp.language.lexicon import tokens
from spcotmhp.language.naming import read_naming
from spcotmhp.language.numbers import number_word, numbered_labels, said_variants
from spcotmhp.language.said_names import (
    MAX_SAID_NAMES,
    MAX_TEXT,
    SaidName,
    count_names,
    event_name,
    event_text,
    keep_said_names,
    said_names,
    shown_names,
    spoken_order,
    taught_numbers,
)
from spcotmhp.language.table import word_table


@pytest.mark.parametrize(
    ("said", "words"),
    [
        ("this is aisle one", ("aisle", "one")),
        ("this is the aisle one", ("aisle", "one")),
        ("aisle one", ("aisle", "one")),
        ("This is room 101.", ("room", "101")),
        ("this is bay 3", ("bay", "3")),
        ("this is aisle #1", ("aisle", "1")),
        ("this is the first aisle", ("first", "aisle")),
        ("this is the second bedroom", ("second", "bedroom")),
        ("we are in the loading dock", ("loading", "dock")),
        ("aisle two, this is", ("aisle", "two")),
        ("ここは2号室です", ("2号室",)),
        ("ここは101号室です", ("101号室",)),
        ("ここは第二会議室です", ("第二会議室",)),
        ("ここは東の廊下です", ("東", "廊下")),
    ],
)
def test_a_teach_keeps_the_names_numbers_and_order(said, words):
    assert read_naming(said).words == words


@pytest.mark.parametrize("said", ["this is the one", "one", "this is nice", "it is two", "this is the first"])
def test_a_number_alone_or_an_adjective_names_nothing(said):
    with pytest.raises(NotANaming):
        read_naming(said)


def test_the_event_name_of_dataset_rows():
    assert event_name(["this", "is", "the", "storage", "hall"], "en") == ("storage", "hall")
    assert event_name(["hello", "there", "is", "this", "it"], "en") is None
    assert event_name(["ここ", "は", "東", "の", "廊下", "です"], "ja") == ("東", "廊下")
    assert event_name([], "en") is None


def test_one_order_per_name_the_most_taught():
    """Hand-counted: "south corridor" twice, "corridor south" once -> "south corridor", taught 3 times; a tie keeps
    the first said; earlier names count as their taught events."""
    names = [("south", "corridor"), ("corridor", "south"), ("south", "corridor"), ("hall",), None]
    assert count_names(names) == [SaidName(("south", "corridor"), 3), SaidName(("hall",), 1)]
    assert count_names([("b", "a"), ("a", "b")]) == [SaidName(("b", "a"), 2)]
    earlier = [SaidName(("corridor", "south"), 5)]
    assert count_names(names, earlier) == [SaidName(("corridor", "south"), 8), SaidName(("hall",), 1)]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.permutations(["aisle", "one", "left"]), min_size=1, max_size=30))
def test_the_kept_order_is_a_most_said_one(orders):
    (kept,) = count_names(tuple(o) for o in orders)
    counts = {tuple(o): orders.count(o) for o in orders}
    assert kept.taught == len(orders)
    assert counts[kept.words] == max(counts.values())


def test_the_kept_names_are_bounded():
    many = [(f"w{i}", "room") for i in range(MAX_SAID_NAMES + 50)]
    assert len(count_names(many)) == MAX_SAID_NAMES


def test_a_label_in_taught_order():
    names = [SaidName(("room", "101"), 4), SaidName(("loading", "dock"), 3), SaidName(("dock",), 1)]
    assert spoken_order(["101", "room"], names) == ["room", "101"]
    assert spoken_order(["dock", "loading"], names) == ["loading", "dock"]
    assert spoken_order(["dock", "loading", "room", "101"], names) == ["room", "101", "loading", "dock"]
    assert spoken_order(["kitchen"], names) is None
    assert spoken_order(["room", "kitchen"], names) is None


def test_said_names_read_from_a_model_refuse_wrong_entries():
    wrong = [{"words": "aisle"}, {"words": ["x"], "taught": True}, {"words": [], "taught": 1}, 7]
    model = SimpleNamespace(info={"said_names": [{"words": ["aisle", "one"], "taught": 3}, *wrong]})
    assert said_names(model) == [SaidName(("aisle", "one"), 3)]
    assert said_names(SimpleNamespace(info={})) == [] and said_names(SimpleNamespace()) == []


def test_numbers_of_taught_names():
    names = [SaidName(("aisle", "one"), 2), SaidName(("one",), 1), SaidName(("first", "aisle"), 1)]
    assert taught_numbers(names) == {"one", "first"}
    assert numbered_labels(["aisle one", "kitchen", "one", "room 101", "room 101", "east corridor"]) == [
        "aisle one",
        "room 101",
    ]


@pytest.mark.parametrize(
    ("word", "said"),
    [("one", ("cardinal", 1)), ("20", ("cardinal", 20)), ("third", ("ordinal", 3)), ("11th", ("ordinal", 11)),
     ("21st", ("ordinal", 21)), ("12nd", None), ("bay", None), ("２", None)],
)  # fmt: skip
def test_number_words(word, said):
    assert number_word(word) == said


EN = word_table("en")
PLACES = ["aisle", "one", "two", "room", "101", "bedroom", "second", "lab", "aisle one", "aisle two", "room 101",
          "second bedroom"]  # fmt: skip


def _place(text: str):
    return [(t.words, t.number) for t in tokens(text, EN, PLACES) if t.kind == "PLACE"]


@pytest.mark.parametrize(
    ("said", "place"),
    [
        ("go to aisle one", (("aisle", "one"), None)),
        ("go to aisle 1", (("aisle", "one"), None)),
        ("go to aisle #1", (("aisle", "one"), None)),
        ("go to aisle number one", (("aisle", "one"), None)),
        ("go to aisle two", (("aisle", "two"), None)),
        ("go to room 101", (("room", "101"), None)),
        ("go to the second bedroom", (("second", "bedroom"), None)),
        ("go to the 2nd bedroom", (("second", "bedroom"), None)),
        ("go to bedroom 2", (("bedroom",), 2)),
        ("go to bedroom two", (("bedroom",), 2)),
        ("go to lab 1", (("lab",), 1)),
        ("go to the aisle", (("aisle",), None)),
    ],
)
def test_a_taught_numbered_name_is_matched_whole(said, place):
    """A taught name with a number wins over the instance-number reading; a number said with any other name still
    names the screen's instance ("bedroom 2": "bedroom #2")."""
    assert _place(said) == [place]


def test_a_number_word_alone_is_no_place_word():
    assert _place("go to one") == []
    assert _place("go to the one nearest the lab") == [(("lab",), None)]


WORDS = ("one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven", "twelve",
         "thirteen", "fourteen", "fifteen", "sixteen", "seventeen", "eighteen", "nineteen", "twenty")  # fmt: skip


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(["aisle", "room", "bay", "dock"]), st.integers(1, 20))
def test_every_variant_reads_back_as_the_name(head, n):
    word = WORDS[n - 1]
    name = f"{head} {word}"
    for units in said_variants(name.split()):
        got = [t.words for t in tokens("go to " + " ".join(units), EN, [head, word, name]) if t.kind == "PLACE"]
        assert got == [(head, word)], units


def test_japanese_names_are_written_as_taught():
    """Rule 6, hand-made: a dataset row's name written from its first name word to its last, particles kept; an
    English name has no text of its own (its words joined)."""
    assert event_text(["ここ", "は", "東", "の", "廊下", "です"], "ja") == "東の廊下"
    assert event_text(["ここ", "が", "2", "号室", "です"], "ja") == "2号室"
    assert event_text(["台所"], "ja") is None
    assert event_text(["this", "is", "the", "east", "corridor"], "en") is None
    assert event_text(["です"], "ja") is None


def test_the_text_said_most_is_kept_with_its_order():
    names = [("東", "廊下")] * 3 + [("廊下", "東")]
    texts = ["東の廊下", "東の廊下", "東廊下", "廊下の東"]
    (kept,) = count_names(names, texts=texts)
    assert (kept.words, kept.taught, kept.text, kept.said) == (("東", "廊下"), 4, "東の廊下", "東の廊下")
    assert count_names([("aisle", "one")])[0].said == "aisle one"


def test_shown_labels_and_the_folder_round_trip():
    model = SimpleNamespace(info={})
    keep_said_names(model, [("東", "廊下"), ("2号室",), ("台所",)], [3, 4, 5], ["東の廊下", None, None])
    kept = {tuple(e["words"]): e for e in model.info["said_names"]}
    assert kept[("東", "廊下")] == {"words": ["東", "廊下"], "taught": 1, "places": [[3, 1]], "text": "東の廊下"}
    assert "text" not in kept[("2号室",)]
    assert shown_names(["東 廊下", "東 廊下 #2", "廊下 東", "台所", "place 7"], model) == [
        "東の廊下",
        "東の廊下 #2",
        "廊下 東",
        "台所",
        "place 7",
    ]
    kept[("東", "廊下")]["text"] = "長" * (MAX_TEXT + 1)  # longer than any name: read without it
    assert all(not n.text for n in said_names(model)) and shown_names(["東 廊下"], model) == ["東 廊下"]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.sampled_from(["東 廊下", "東 廊下 #2", "台所", "place 3", "廊下", ""]), max_size=8))
def test_shown_labels_replace_only_whole_taught_names(labels):
    model = SimpleNamespace(info={})
    keep_said_names(model, [("東", "廊下"), ("廊下",)], texts=["東の廊下", "長" * (MAX_TEXT + 1)])
    shown = shown_names(labels, model)
    assert len(shown) == len(labels)
    for label, out in zip(labels, shown, strict=True):
        assert out == (label.replace("東 廊下", "東の廊下") if label.startswith("東 廊下") else label)


@pytest.mark.parametrize("said", ["go to the second bedroom", "go to the 3rd bedroom", "Go to the First bedroom."])
def test_an_ordinal_is_no_screen_number(said):
    """Where no taught name holds it, an ordinal counts along something the map does not hold: no instance."""
    assert [t.number for t in tokens(said, EN, ["bedroom", "kitchen"]) if t.kind == "PLACE"] == [None]


@pytest.mark.parametrize(
    ("said", "number"),
    [("第3寝室へ", 3), ("第2の寝室", 2), ("寝室No.1", 1), ("三番目の寝室", None), ("3番目の寝室に行って", None)],
)
def test_japanese_dai_and_no_name_the_instance_shown(said, number):
    places = [t for t in tokens(said, word_table("ja"), ["寝室", "キッチン"]) if t.kind == "PLACE"]
    assert [t.number for t in places] == [number]
