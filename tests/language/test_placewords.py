"""Place words as the units they match (spcotmhp/language/placewords.py): spelling variants and the table's other
names of a kind of place (synonyms), which name a place word only when they can name exactly one of the map's."""

from __future__ import annotations

import pytest

from spcotmhp.errors import AmbiguousPlace, UnknownPlaceWord
from spcotmhp.language.reading import read


def goal(text: str, words: list[str], lang: str = "en") -> tuple[str, ...]:
    return read(text, words, lang).visit[-1].words


@pytest.mark.parametrize(
    ("text", "words", "lang", "named"),
    [
        ("go to the loo", ["toilet", "bath"], "en", ("toilet",)),
        ("pop into the restroom", ["toilet", "washroom"], "en", ("toilet",)),
        ("go to the storage room", ["storeroom", "kitchen"], "en", ("storeroom",)),
        ("go to the front door", ["entrance", "kitchen"], "en", ("entrance",)),
        ("go to the bathroom", ["bath", "kitchen"], "en", ("bath",)),  # the only place it may name here
        ("go to the hallway", ["corridor", "kitchen"], "en", ("corridor",)),
        ("go to the hall", ["hall", "corridor"], "en", ("hall",)),  # a place word of the map is itself
        ("go to the hallway", ["hall", "corridor"], "en", ("corridor",)),  # senses: a corridor first
        ("go to the hallway", ["hall", "kitchen"], "en", ("hall",)),  # its other sense where there is no corridor
        ("go into alice room", ["alice's", "room", "kitchen"], "en", ("alice's",)),  # the 's not said
        ("go to the eastern corridor", ["east", "corridor", "south"], "en", ("east", "corridor")),
        ("go to the E corridor", ["east", "corridor", "south"], "en", ("east", "corridor")),  # as on signs
        ("please head to the shower", ["bath", "toilet"], "en", ("bath",)),
        ("go to the front entrance", ["entrance", "kitchen"], "en", ("entrance",)),
        ("台所を通って居間へ", ["キッチン", "リビング"], "ja", ("リビング",)),
        ("お台所へ", ["キッチン", "リビング"], "ja", ("キッチン",)),  # after an honorific
        ("お手洗いへ行っておくれ", ["トイレ", "風呂"], "ja", ("トイレ",)),
        ("浴室に向かって", ["トイレ", "風呂"], "ja", ("風呂",)),
        ("ご飯食べるとこ行って", ["ダイニング", "キッチン"], "ja", ("ダイニング",)),  # told by what is done there
        ("料理する部屋に行って", ["ダイニング", "キッチン"], "ja", ("キッチン",)),
        ("靴脱ぐとこまで行って", ["玄関", "廊下"], "ja", ("玄関",)),
        ("go to the cooking room", ["kitchen", "dining"], "en", ("kitchen",)),
        ("go to the room for bathing", ["bath", "toilet"], "en", ("bath",)),
    ],
)
def test_other_names_read_as_the_one_place_word_they_name(text, words, lang, named):
    assert goal(text, words, lang) == named


@pytest.mark.parametrize(
    ("text", "words", "lang", "error", "message"),
    [
        ("go to the bathroom", ["bath", "toilet", "washroom"], "en", AmbiguousPlace,
         "'bathroom' may name the bath or the toilet"),  # never the washroom but told by a sink (told_senses)
        ("go to the loo", ["bath", "kitchen"], "en", UnknownPlaceWord, "loo"),  # no toilet in this map
        ("手を洗うとこに行って", ["洗面所", "トイレ"], "ja", UnknownPlaceWord, "手を洗う"),  # done in two kinds of room
        ("go to the cooking room", ["dining", "bath"], "en", UnknownPlaceWord, "cooking"),  # no kitchen in this map
    ],
)  # fmt: skip
def test_an_other_name_that_could_name_several_places_or_none_is_refused(text, words, lang, error, message):
    with pytest.raises(error, match=message):
        read(text, words, lang)


def test_a_possessive_without_its_s_is_the_owner_only_before_a_noun():
    """ "alice room" is Alice's room; "go to alice" (a person) names no place."""
    with pytest.raises(UnknownPlaceWord):
        read("go to alice", ["alice's", "room", "kitchen"], "en")


@pytest.mark.parametrize(
    ("text", "words", "named"),
    [
        ("goto kitchen", ["kitchen", "bath"], ("kitchen",)),
        ("can u go to da bath", ["kitchen", "bath"], ("bath",)),
        ("cd u go 2 the kitchen", ["kitchen", "bath"], ("kitchen",)),
        ("kitchen plz ty", ["kitchen", "bath"], ("kitchen",)),
    ],
)
def test_text_speak_is_the_words_it_stands_for(text, words, named):
    assert goal(text, words) == named
