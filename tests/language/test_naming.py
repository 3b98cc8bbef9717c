"""Reading teaching utterances (spcotmhp/language/naming.py): the name taught, or NotANaming.

The frozen teaching corpora (tests/data/heldout/, blind/, blind2/: utterances with the expected name or refused=yes,
written by people who had not read the rules) are measured as right, refused (a name expected, none read) or wrong
(another name, or a name where the label refuses). Thresholds: at least 95 % right on each corpus and at most one
wrong on each: a wrong reading teaches a wrong name silently, a refusal only asks the person to say it again, so
wrong readings must stay rarer than refusals. Measured when written: heldout 78/78 right, blind 56/56, blind2 60/62
(one refused: janome reads 物置きだ as 物置 + きだ; one wrong: こどもべや read as こども, janome cutting the
hiragana compound). The rules were written after reading the three corpora, so these figures are not blind."""

from __future__ import annotations

import unicodedata
from collections import Counter

import pytest
from hypothesis import given
from hypothesis import strategies as st

from spcotmhp.errors import NotANaming
from spcotmhp.language.naming import read_naming
from tests.helpers.corpus import DATA, rows

CORPORA = ("heldout", "blind", "blind2")


def verdict(row: dict) -> str:
    expected = None if row["refused"] else unicodedata.normalize("NFKC", row["name"]).casefold()
    if expected is not None and row["lang"] == "ja":
        expected = expected.replace(" ", "")
    try:
        got = read_naming(row["text"], row["lang"]).name
    except NotANaming:
        return "right" if expected is None else "refused"
    return "right" if got == expected else "wrong"


@pytest.mark.parametrize("corpus", CORPORA)
def test_teaching_corpora_are_read_as_labelled(corpus):
    table = rows(DATA / corpus / "teaching.csv")
    counts = Counter(verdict(row) for row in table)
    wrong = [row["text"] for row in table if verdict(row) == "wrong"]
    assert counts["right"] >= 0.95 * len(table), counts
    assert counts["wrong"] <= 1, wrong


@pytest.mark.parametrize(
    ("text", "name"),
    [
        ("this is the study", "study"),
        ("This isn't the bath, it's the washroom.", "washroom"),
        ("um, this is the, uh, den", "den"),
        ("Let's call this room the library.", "library"),
        ("this is Bob's room", "bob's room"),
        ("Study.", "study"),
        ("ここはトイレじゃなくて洗面所だよ", "洗面所"),
        ("この場所は広場と呼びます", "広場"),
    ],
)
def test_names_are_read(text, name):
    assert read_naming(text).name == name


@pytest.mark.parametrize(
    ("text", "why"),
    [
        ("hello", "names no place"),
        ("is this the kitchen?", "is a question"),
        ("this isn't the study", "names no place"),
        ("this is nice", "names no place"),
        ("go to the kitchen", "names no place"),
        ("ここってキッチン？", "is a question"),
        ("ここはキッチンじゃないよ", "not its name"),
        ("キッチンに行って", "names no place"),
    ],
)
def test_utterances_that_name_nothing_are_refused(text, why):
    with pytest.raises(NotANaming, match=why):
        read_naming(text)


@given(st.text(max_size=80))
def test_any_text_is_a_name_or_a_one_line_refusal(text):
    try:
        naming = read_naming(text)
    except NotANaming as exc:
        assert "\n" not in str(exc)
        return
    assert naming.name and naming.words and all(w for w in naming.words)
